//! One frame, top to bottom: the camera, lights and moved instances of this frame, the
//! G-buffer, direct light, the indirect light of the method, compose, the luminance statistics,
//! and (for a window or a readback) the tonemap; then the counters copied out for the stats.
//! Declared anew every frame from the renderer's state; submitted without waiting.

use std::time::Instant;

use bytemuck::{Pod, Zeroable};
use leakless_device::{Image, SubmitSync};
use leakless_graph::{Access, BufferHandle, CompletedFrame, Graph, ImageHandle, Timing};

use super::plan::{self, FramePlan, PlanState};
use super::readback::{ReadbackRequest, LAYERS_BUFFER};
use super::reuse::ReuseInputs;
use super::stages::{self, FrameStage, Layers};
use super::view_samples::ViewSamples;
use super::{FrameReport, Pending, Renderer};
use crate::error::Result;
use crate::frame_set;
use crate::gpu_types::Frame;
use crate::passes::gather::GatherCounters;
use crate::passes::gbuffer::{self, GBufferHandles};
use crate::passes::luminance::{self, LuminanceInputs, LuminanceStats};
use crate::passes::photons::PhotonCounters;
use crate::passes::splat::SplatCounters;
use crate::passes::temporal::TemporalMode;
use crate::passes::tonemap::{TonemapPass, ViewLayer};
use crate::passes::{instance_vertices, names, readback, ViewInputs};
use crate::photon_lights::upload_lights;
use crate::splatting::{self, grown_batch_capacity, SplatFrame, SplatStats};

/// Draws over the tonemapped image (the app's overlay): passes added to the frame's graph
/// after the tonemap, writing `target`.
pub trait Overlay {
    fn add<'r>(&'r self, graph: &mut Graph<'r>, target: &mut ImageHandle) -> Result<()>;
}

/// Where a windowed frame ends: an acquired swapchain image, the semaphores around it, and
/// what to draw over it.
pub struct DisplayTarget<'a> {
    pub image: &'a Image,
    pub sync: SubmitSync<'a>,
    pub overlay: Option<&'a dyn Overlay>,
}

/// The counters copied out of every frame, in this order (the splat's only when it ran).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
struct FrameCounters {
    luminance: LuminanceStats,
    photons: PhotonCounters,
    lists: SplatCounters,
    gather: GatherCounters,
}

const COUNTERS_BUFFER: &str = "frame counters";

impl Renderer {
    /// Declares and submits the next frame. With a `display`, the tonemapped image goes to its
    /// swapchain image (then the overlay); without, nothing is shown. Does not wait for the
    /// GPU, except for the frame that last used this frame's slot.
    pub fn render_frame(&mut self, display: Option<DisplayTarget<'_>>) -> Result<()> {
        self.submit_frame(display, None)
    }

    /// Declares and submits one frame (see `render_frame`), with the readback `request`.
    pub(super) fn submit_frame(
        &mut self,
        display: Option<DisplayTarget<'_>>,
        request: Option<ReadbackRequest>,
    ) -> Result<()> {
        let mut started = Instant::now();
        if let Some(done) = self.runner.acquire_slot(&self.gpu)? {
            self.collect(done)?;
        }
        let method = self.settings.method;
        let plan = plan::plan(&self.plan_state());
        let FramePlan { render, progressive, index, first_batch, frame_batches, accumulated, batches, .. } = plan;
        // Temporal reuse averages frames after a change: each must trace fresh photons (the
        // accumulation that follows, when nothing moves, continues this frame's sequence).
        let reuse = render && self.settings.reuse && method.splats();
        if reuse && self.advance_seed && progressive && index == 0 {
            self.seed_offset = self.seed_offset.wrapping_add(1);
        }
        let seed = self.frame_seed();
        let budget_paths = if render && method.splats() { self.budget_paths(first_batch, frame_batches) } else { None };
        if render && first_batch == 0 {
            self.start_accumulation_radius();
        }
        let mut splat = if render { self.splat_frame(first_batch, frame_batches, budget_paths, seed)? } else { None };
        if let Some(frame) = splat.as_ref().filter(|f| f.first_batch == 0 && self.needs_kernel_probe()) {
            self.probe_kernel(&frame.clone())?;
            // The frame's time (the budget's measure) starts after the probe's wait.
            started = Instant::now();
            self.start_accumulation_radius();
            splat = self.splat_frame(first_batch, frame_batches, budget_paths, seed)?;
        }
        if let Some(frame) = splat.as_ref().filter(|f| f.first_batch == 0) {
            self.record_first_radius(frame.radius);
        }
        self.prepare_pipelines(splat.as_ref(), render && method == crate::Method::Reference)?;
        let jitter = if progressive { pixel_jitter(index) } else { glam::Vec2::ZERO };
        let frame_constants = self.frame_constants(jitter);
        let primary = self.primary();
        let extent = self.extent();
        // Instances moved since the vertex buffer was last written: this frame copies them.
        let place_instances = render && self.gpu_scene.placed_version != self.pose.version;
        if place_instances {
            self.gpu_scene.placed_version = self.pose.version;
        }
        let trace_scene = self.traces[self.backend.backend as usize].as_ref().expect("current backend made");
        let passes = &self.passes;
        let raster = (&passes.gbuffer, self.gpu_scene.vertex_count);
        let view_samples = ViewSamples::new(primary, raster, &frame_constants, self.camera.zfar.is_some());
        // The frame the budget wants timed is timed pass by pass where the caller submits a
        // frame at once and the device's timestamps do not bracket the work (lavapipe): the
        // budget splits a frame's time by its passes' host times (`budget_wants_timed_frame`).
        let budget_timed = budget_paths.is_some() && self.budget_wants_timed_frame();
        let timing = if budget_timed { Timing::PerPassSubmit } else { self.runner.timing() };
        let mut g = self
            .runner
            .graph(&self.gpu)?
            .with_pipelines(self.pipelines.table(self.backend.backend))
            .with_timing(timing);

        // The camera, the lights and the scene of this frame.
        let frame =
            g.upload("frame", ash::vk::BufferUsageFlags::UNIFORM_BUFFER, bytemuck::bytes_of(&frame_constants))?;
        let lights = upload_lights(&mut g, &self.lights, &self.gpu_scene.emitter_table, &self.scene.bounds())?;
        let mut scene = self.gpu_scene.import(&mut g);
        if place_instances {
            let first_vertex = 3 * self.scene.static_triangle_count();
            instance_vertices::add(&mut g, &self.pose.vertices, first_vertex, &mut scene)?;
        }
        let trace = trace_scene.import(&mut g, &self.gpu_scene, &self.pose)?;
        frame_set::bind(&mut g, &scene, &trace);

        // View samples and their direct light.
        let mut gbuffer = GBufferHandles::new(&mut g, extent)?;
        if render {
            view_samples.add(&mut g, (&frame, &scene), &mut gbuffer);
        }
        let stage = FrameStage { plan: &plan, settings: &self.settings, method, seed, extent };
        let mut direct = layer(&mut g, extent, "direct")?;
        let view = ViewInputs { frame: &frame, lights: &lights.lights, scene: &scene, gbuffer: &gbuffer };
        let seen = display.is_some() || request.is_some();
        stages::direct_light(&mut g, &stage, self.accumulation.accumulated, seen, &view, &mut direct);

        // Indirect light: photons splatted and gathered, or path-traced samples accumulated.
        let (sums, counters) =
            stages::indirect_light(&mut g, &stage, self.accumulation.accumulated, splat.as_ref(), &view, &lights)?;
        let (layers, gather_counts) = stages::compose_layers(&mut g, &stage, &frame, direct, sums, splat.is_some())?;
        let mut layers = stages::accumulate_layers(&mut g, &stage, &frame, layers, self.accumulation.image_is_mean)?;

        // Temporal reuse: the frames before, reprojected, with this frame (or, while nothing
        // moves, weighing into the accumulation's mean).
        let (mut reused, mut history_shown) = (None, None);
        if reuse {
            let kernel_pixels = splat
                .as_ref()
                .map_or(0.0, |s| s.radius * 0.5 * self.settings.height as f32 / (0.5 * self.camera.yfov).tan());
            let input = ReuseInputs {
                frame: &frame,
                gbuffer: &gbuffer,
                pose_version: self.pose.version,
                first_moving_triangle: self.scene.static_triangle_count() as u32,
                kernel_pixels,
            };
            let (with_history, history, mode) = self.reuse.add(&mut g, &stage, input, layers)?;
            (layers, history_shown, reused) = (with_history, Some(history), Some(mode));
        } else if !render && self.accumulation.image_is_reused {
            layers.indirect = layer(&mut g, extent, "reused indirect")?;
            layers.radiance = layer(&mut g, extent, "reused radiance")?;
        }
        if render {
            self.accumulation.image_is_mean = progressive;
            self.accumulation.image_is_reused = reuse;
        }
        let Layers { direct, indirect, leaked, radiance } = layers;

        // What the frame shows, and its luminance statistics (exposure, leaked energy).
        let shown = match self.view {
            ViewLayer::Final => &radiance,
            ViewLayer::Direct => &direct,
            ViewLayer::Indirect => &indirect,
            ViewLayer::Leaked => &leaked,
            ViewLayer::Candidates | ViewLayer::VisibilityRays => &gather_counts,
            // Without reuse every pixel holds its one frame: the radiance's .a is 1.
            ViewLayer::History => history_shown.as_ref().unwrap_or(&radiance),
        };
        let input = LuminanceInputs { displayed: shown, mode: self.view.mode(), indirect: &indirect, leaked: &leaked };
        let luminance = luminance::add(&mut g, input)?;
        let tonemaps = Tonemaps { passes: &passes.tonemaps, history_frames: self.reuse.history_frames };
        let sync = match display {
            Some(display) => tonemaps.display(&mut g, display, (self.view, self.exposure), shown, &luminance)?,
            None => SubmitSync::default(),
        };
        if let Some(request) = request {
            let shown_rgba8 = tonemaps.readback(&mut g, extent, (request.view, request.exposure), shown, &luminance)?;
            let layers = [&radiance, &direct, &indirect, &leaked, &gbuffer.position, &shown_rgba8];
            readback::add(&mut g, LAYERS_BUFFER, &layers)?;
        }

        // The counters, for the stats of this frame once it completed.
        let mut copied = vec![&luminance];
        if let Some(s) = &counters.splat {
            copied.extend([&s.photons, &s.lists, &counters.gather]);
        }
        readback::add_buffers(&mut g, (COUNTERS_BUFFER, names::FRAME_COUNTERS), &copied)?;

        if let Some(hang) = &passes.hang {
            hang.add(&mut g);
        }
        let _in_flight = g.submit(&sync)?;
        if budget_paths.is_some() {
            self.budget_frame_submitted(budget_timed);
        }
        if matches!(reused, Some(TemporalMode::Motion | TemporalMode::Restart)) {
            let camera = self.camera.position();
            self.reuse.remember(self.view_proj(), camera, self.pose.version, &self.pose.vertices);
        }
        let index = self.runner.next_frame() - 1;
        self.pending.push_back(Pending {
            index,
            shown_only: !render,
            readback: request.is_some(),
            seed,
            splat,
            accumulated,
            batches,
            frame_batches,
            budget_paths,
            budget_timed,
            size: (self.settings.width, self.settings.height),
            method,
            started,
        });
        (self.accumulation.accumulated, self.accumulation.batches) = (accumulated, batches);
        // Fresh photons for the next frame, unless it continues an accumulation's sequence.
        if self.advance_seed && method.splats() && render && !progressive {
            self.seed_offset = self.seed_offset.wrapping_add(1);
        }
        Ok(())
    }

    /// The photon frame's settings (radius, paths, seed, list capacity) for a frame of
    /// `frame_batches` batches from `first_batch`, or of the budget's `budget_paths`; `None`
    /// for a method without photons.
    fn splat_frame(
        &self,
        first_batch: u32,
        frame_batches: u32,
        budget_paths: Option<u32>,
        seed: u32,
    ) -> Result<Option<SplatFrame>> {
        let Some(mut settings) = self.settings.photon_settings() else {
            return Ok(None);
        };
        if let Some(radius) = settings.radius.filter(|r| !(r.is_finite() && *r > 0.0)) {
            return Err(crate::RenderError::Settings(format!("--radius {radius} must be a positive number")));
        }
        let tuning = self.pipelines.tuning().clone();
        settings.branching.get_or_insert(tuning.branching);
        let batch_paths = settings.paths;
        // Within limits::max_frame_paths: the batches are clamped to it, and check() holds
        // one batch to it.
        settings.paths = budget_paths.unwrap_or(batch_paths.saturating_mul(frame_batches));
        // The node lists hold a batch's entries per `batch_paths` paths.
        let list_batches = settings.paths.div_ceil(batch_paths.max(1)).max(1);
        let max_workgroups = tuning.max_workgroups(self.gpu.report().limits.max_compute_work_group_count[0]);
        Ok(Some(SplatFrame {
            radius: self.batch_radius(first_batch, settings.paths),
            path_offset: self.path_offset(first_batch, batch_paths),
            first_batch,
            eye: self.camera.position().to_array(),
            settings,
            max_bounces: self.settings.max_bounces,
            seed,
            // The renderer's capacity is per batch, unless fixed by the user.
            list_capacity: match self.settings.splat.list_capacity {
                Some(fixed) => fixed,
                None => (self.list_capacity as u64 * list_batches as u64)
                    .min(crate::limits::max_list_entries(&self.gpu.report().limits) as u64)
                    as u32,
            },
            batches: list_batches,
            bounds: self.scene.bounds(),
            tuning,
            max_workgroups,
            compute_trace: self.backend() == crate::trace::Backend::Compute,
        }))
    }

    /// What the next frame's plan depends on.
    fn plan_state(&self) -> PlanState {
        let limits = &self.gpu.report().limits;
        let batches_that_fit = if self.settings.method.splats() {
            let fits = crate::limits::max_frame_paths(limits, self.settings.max_bounces)
                / self.settings.splat.paths.max(1) as u64;
            // Lists grown to what a batch needs: a frame holds no more batches than they take.
            let lists_hold = match self.settings.splat.list_capacity {
                None => splatting::batches_the_lists_hold(self.list_capacity, crate::limits::max_list_entries(limits)),
                Some(_) => u32::MAX, // the user's fixed capacity: drops are reported
            };
            (fits.clamp(1, u32::MAX as u64) as u32).min(lists_hold)
        } else {
            u32::MAX
        };
        PlanState {
            method: self.settings.method,
            paused: self.accumulation.paused,
            full: self.accumulation_full(),
            accumulating: self.accumulating(),
            accumulated: self.accumulation.accumulated,
            batches: self.accumulation.batches,
            max_batches: self.settings.max_batches,
            batches_that_fit,
            spp: self.settings.spp,
            samples_per_frame: self.accumulation.samples_per_frame,
        }
    }

    /// Makes the report of a completed frame from its counters, and grows the node lists when
    /// it dropped entries (unless the capacity is fixed): the next frame holds them all.
    pub(super) fn collect(&mut self, done: CompletedFrame) -> Result<()> {
        // Frames before it that never reported (their submission failed) are gone too; a frame
        // the renderer did not submit itself (a G-buffer capture) has nothing to report.
        while self.pending.front().is_some_and(|p| p.index < done.index) {
            if self.pending.pop_front().is_some_and(|p| p.budget_timed) {
                self.budget_timed_frame_lost();
            }
        }
        if self.pending.front().is_none_or(|p| p.index != done.index) {
            return Ok(());
        }
        let pending = self.pending.pop_front().expect("checked above");
        let buffer = self.runner.pool().frame_buffer(COUNTERS_BUFFER, done.slot).expect("every frame copies counters");
        let bytes = if pending.splat.is_some() { std::mem::size_of::<FrameCounters>() } else { 16 };
        let mut counters = FrameCounters::default();
        buffer.read(0, &mut bytemuck::bytes_of_mut(&mut counters)[..bytes])?;
        let splat = pending.splat.as_ref().map(|frame| {
            let mut stats = SplatStats::new(frame, &counters.photons, &counters.lists, &counters.gather);
            stats.leaked_energy_fraction = counters.luminance.leaked_fraction();
            stats
        });
        if let Some(frame) = &pending.splat {
            self.observe_kernel(frame, &counters.gather);
            if self.settings.splat.list_capacity.is_none() {
                let max_entries = crate::limits::max_list_entries(&self.gpu.report().limits);
                if let Some(grown) =
                    grown_batch_capacity(self.list_capacity, frame.batches, &counters.lists, max_entries)
                {
                    if grown > self.list_capacity {
                        // The frame lost photons: an accumulation restarts without it, and
                        // temporal reuse forgets it.
                        self.list_capacity = grown;
                        self.restart();
                        self.runner.invalidate_histories();
                    }
                }
            }
        }
        if pending.shown_only {
            // Only the luminance is new: the image is the last one, copied out again if asked.
            if let Some(last) = &mut self.last {
                last.luminance = counters.luminance;
                if pending.readback {
                    last.slot = done.slot;
                }
                return Ok(());
            }
        }
        let budget = self.observe_budget(&pending, &done);
        self.last = Some(FrameReport {
            index: done.index,
            slot: done.slot,
            seed: pending.seed,
            method: pending.method,
            // A pass split into several dispatches (the reference's) reports once.
            timings: super::readback::merged_by_name(&done.timings),
            gpu_span_ms: done.span_ms,
            splat,
            luminance: counters.luminance,
            accumulated: pending.accumulated,
            batches: pending.batches,
            frame_batches: pending.frame_batches,
            wall_ms: pending.started.elapsed().as_secs_f64() * 1e3,
            budget,
        });
        Ok(())
    }
}

/// A layer of the frame: one of the storage images the passes write and the readback copies.
pub(super) fn layer(g: &mut Graph<'_>, extent: ash::vk::Extent2D, name: &'static str) -> Result<ImageHandle> {
    let usage = ash::vk::ImageUsageFlags::STORAGE | ash::vk::ImageUsageFlags::TRANSFER_SRC;
    Ok(g.image(&leakless_device::ImageDesc { name, extent, format: gbuffer::FORMAT, usage })?)
}

impl Renderer {
    /// The frame's constants: the camera (moved by `jitter` pixels), the size, the lights.
    pub(super) fn frame_constants(&self, jitter: glam::Vec2) -> Frame {
        Frame {
            view_proj: self.jittered_view_proj(jitter).to_cols_array_2d(),
            camera_position: self.camera.position().extend(1.0).to_array(),
            width: self.settings.width,
            height: self.settings.height,
            light_count: self.lights.len() as u32,
            emitter_count: self.gpu_scene.emitter_table.len() as u32,
        }
    }
}

/// The tonemap's exposure for `view`: `exposure` (the user's, or automatic), except for the
/// history length, which maps 0 … `history_frames` (the longest history) onto the whole ramp,
/// so that its colours mean the same in every frame.
/// The tonemaps a frame ends with: into the window's swapchain image, or into an RGBA8
/// image for a readback.
struct Tonemaps<'a> {
    passes: &'a [TonemapPass],
    history_frames: u32,
}

impl<'r> Tonemaps<'r> {
    /// Tonemaps `shown` into the display's acquired image, draws its overlay over it and
    /// presents it; the semaphores the submission waits on and signals.
    fn display<'d>(
        &self,
        g: &mut Graph<'r>,
        display: DisplayTarget<'d>,
        (view, exposure): (ViewLayer, Option<f32>),
        shown: &ImageHandle,
        luminance: &BufferHandle,
    ) -> Result<SubmitSync<'d>>
    where
        'd: 'r,
    {
        let stage = ash::vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT;
        let mut target = g.import_acquired_image(display.image, stage);
        let tonemap = self.passes.iter().find(|t| t.format() == target.format()).ok_or_else(|| {
            crate::RenderError::Settings(format!("no tonemap for {:?}: call prepare_display", target.format()))
        })?;
        tonemap.add(g, view, view_exposure(view, exposure, self.history_frames), shown, luminance, &mut target);
        if let Some(overlay) = display.overlay {
            overlay.add(g, &mut target)?;
        }
        let mut present = g.pass(names::PRESENT);
        present.read(&target, Access::Present);
        present.record(|_| Ok(()));
        Ok(display.sync)
    }

    /// Tonemaps `shown` into an RGBA8 image that a readback copies out.
    fn readback(
        &self,
        g: &mut Graph<'r>,
        extent: ash::vk::Extent2D,
        (view, exposure): (ViewLayer, Option<f32>),
        shown: &ImageHandle,
        luminance: &BufferHandle,
    ) -> Result<ImageHandle> {
        let mut shown_rgba8 = g.image(&leakless_device::ImageDesc {
            name: "display",
            extent,
            format: super::readback::DISPLAY_FORMAT,
            usage: ash::vk::ImageUsageFlags::COLOR_ATTACHMENT | ash::vk::ImageUsageFlags::TRANSFER_SRC,
        })?;
        let tonemap = self.passes.iter().find(|t| t.format() == shown_rgba8.format()).expect("made at start");
        tonemap.add(g, view, view_exposure(view, exposure, self.history_frames), shown, luminance, &mut shown_rgba8);
        Ok(shown_rgba8)
    }
}

fn view_exposure(view: ViewLayer, exposure: Option<f32>, history_frames: u32) -> Option<f32> {
    match view {
        ViewLayer::History => Some(1.0 / history_frames as f32),
        _ => exposure,
    }
}

/// Frame `index`'s sub-pixel offset of the view, in pixels within ±½: none for frame 0 (the
/// frame without accumulation), then the R2 sequence (Roberts 2018; the plastic number's
/// powers), which covers the pixel evenly at every count, so accumulated frames are
/// antialiased.
fn pixel_jitter(index: u32) -> glam::Vec2 {
    if index == 0 {
        return glam::Vec2::ZERO;
    }
    const G: f64 = 1.324_717_957_244_746;
    let i = index as f64;
    let x = (0.5 + i / G).fract() - 0.5;
    let y = (0.5 + i / (G * G)).fract() - 0.5;
    glam::Vec2::new(x as f32, y as f32)
}
