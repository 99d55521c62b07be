//! The renderer: one scene on one device, rendered frame after frame through the pass graph,
//! keeping its state between frames (docs/architecture.md). The CLI, the benchmarks, the
//! tests and the app all drive it the same way:
//!
//! * setters change the camera, the lights and every setting; the next frame declares its
//!   resources from them, so only what a change needs is made anew (the graph's pool remakes
//!   a resource whose description changed), and any change restarts accumulation;
//! * [`Renderer::render_frame`] declares and submits one frame without waiting for it (two
//!   frames are in flight) and without reading anything back but a few counters;
//! * reading the layers back is an explicit request ([`Renderer::render`],
//!   [`Renderer::read_layers`]).

mod accumulation;
mod budget;
mod capture;
mod controls;
mod frame;
mod kernel_radius;
mod motion;
mod plan;
mod readback;
mod reuse;
mod stages;
mod upscale;
mod view_samples;

use std::collections::VecDeque;

use ash::vk;
use glam::camera::rh::proj::vulkan;
use glam::Mat4;
use leakless_device::Gpu;
use leakless_graph::{GraphRunner, PassTiming};
use leakless_scene::{Camera, Light, Scene};

use controls::check_tuning;

pub use budget::{BudgetReport, MAX_FRAME_MS};
pub use capture::Capture;
pub use frame::{DisplayTarget, Overlay};
pub use readback::RenderedFrame;

use crate::error::Result;
use crate::gpu_scene::GpuScene;
use crate::passes::frame_passes;
use crate::passes::gbuffer::GBufferPass;
use crate::passes::hang::HangPass;
use crate::passes::luminance::LuminanceStats;
use crate::passes::tonemap::{TonemapPass, ViewLayer};
use crate::pipelines::Pipelines;
use crate::scene_pose::ScenePose;
use crate::settings::{Method, RenderSettings};
use crate::splatting::{default_list_capacity, SplatFrame, SplatStats};
use crate::trace::{Backend, BackendChoice, ResolvedBackend, TraceScene, TraceStats};
use crate::tuning::DeviceTuning;

/// Frames the renderer keeps in flight: the host records one while the GPU runs the other.
pub const FRAMES_IN_FLIGHT: usize = 2;

/// The raster passes, and the stall of fault injection; the compute passes are functions
/// over the graph and the renderer's [`Pipelines`].
struct Passes {
    gbuffer: GBufferPass,
    /// One per target format (the PNG's, the window's).
    tonemaps: Vec<TonemapPass>,
    /// Debug builds: the stall `LEAKLESS_FAULT_HANG` arms (see passes/hang.rs).
    hang: Option<HangPass>,
}

/// What a submitted frame was, to make sense of its counters once it completes.
struct Pending {
    index: u64,
    /// The frame only showed the last image (paused): its report keeps the last counts.
    shown_only: bool,
    /// The frame copied its layers out (a readback request): a shown-only frame's copy is
    /// what the next `read_layers` reads.
    readback: bool,
    seed: u32,
    splat: Option<SplatFrame>,
    /// Samples (reference) or frames (photons) in the image after this frame.
    accumulated: u32,
    /// Photon batches in the image after this frame.
    batches: u32,
    /// Batches the frame traced.
    frame_batches: u32,
    /// The paths the frame budget chose for it (`None`: `--paths` a batch).
    budget_paths: Option<u32>,
    /// It was timed pass by pass for the budget's split (`budget_wants_timed_frame`).
    budget_timed: bool,
    /// Its render size.
    size: (u32, u32),
    method: Method,
    started: std::time::Instant,
}

/// What a completed frame measured: its passes, its counts, its luminance.
#[derive(Clone, Debug)]
pub struct FrameReport {
    pub index: u64,
    /// The frame slot whose per-frame buffers hold what the frame copied out.
    pub slot: usize,
    /// The seed of the frame's photons.
    pub seed: u32,
    pub method: Method,
    pub timings: Vec<PassTiming>,
    /// The frame's GPU time, first pass's start to last pass's end
    /// ([`CompletedFrame::span_ms`](leakless_graph::CompletedFrame::span_ms)).
    pub gpu_span_ms: f64,
    pub splat: Option<SplatStats>,
    pub luminance: LuminanceStats,
    /// Samples (reference) or frames accumulated in the image.
    pub accumulated: u32,
    /// Photon batches (of `paths` paths) accumulated in the image: frames grow while the view
    /// is still (`RenderSettings::max_batches`).
    pub batches: u32,
    /// Batches this frame traced: of `paths` photon paths, or of `spp` reference samples per
    /// pixel (1 for a frame that does not accumulate).
    pub frame_batches: u32,
    /// Host time from the start of the frame's declaration to the moment the host saw it
    /// complete (includes waiting for it).
    pub wall_ms: f64,
    /// What the frame budget measured and chose, for a frame whose paths it chose.
    pub budget: Option<BudgetReport>,
}

pub struct Renderer {
    settings: RenderSettings,
    camera: Camera,
    lights: Vec<Light>,
    scene: Scene,
    gpu_scene: GpuScene,
    /// The animated instances at the renderer's time.
    pose: ScenePose,
    backend: ResolvedBackend,
    /// Each backend's trace structures, made when first used.
    traces: [Option<TraceScene>; 2],
    passes: Passes,
    /// The compute passes' pipelines, for every backend used so far.
    pipelines: Pipelines,
    view: ViewLayer,
    exposure: Option<f32>,
    /// Node-list entries per frame: grows after a frame that dropped entries, unless fixed.
    list_capacity: u32,
    /// What the image holds of the frames since the last change.
    accumulation: accumulation::Accumulation,
    /// What temporal reuse remembers of its history's frame.
    reuse: reuse::ReuseState,
    /// Photon frames advance the seed unless frozen (a fixed seed fixes the frame).
    advance_seed: bool,
    seed_offset: u32,
    /// The frame-time budget, when one is set (`set_frame_budget`).
    budget: Option<budget::BudgetState>,
    /// The view's photon density, for the radius that follows the photon count.
    kernel: kernel_radius::KernelState,
    pending: VecDeque<Pending>,
    last: Option<FrameReport>,
    runner: GraphRunner,
    // Dropped last: every resource above belongs to this device.
    gpu: Gpu,
}

impl Renderer {
    pub fn new(gpu: Gpu, scene: &Scene, settings: RenderSettings) -> Result<Renderer> {
        let tuning = DeviceTuning::choose(gpu.report(), settings.tuning);
        Self::with_tuning(gpu, scene, settings, tuning)
    }

    /// A renderer with a tuning of the caller's (the GPU report's sweeps; tests of each of its
    /// code paths) rather than `settings.tuning`'s preset.
    pub fn with_tuning(gpu: Gpu, scene: &Scene, settings: RenderSettings, tuning: DeviceTuning) -> Result<Renderer> {
        settings.validate()?;
        check_tuning(&settings, &tuning, gpu.report())?;
        let resolved = resolve(&gpu, settings.backend)?;
        crate::limits::check(&settings, scene, resolved.backend, &gpu.report().limits)?;
        let gpu_scene = GpuScene::upload(&gpu, scene)?;
        let pose = ScenePose::new(scene, &gpu_scene.bvh.bvh);
        let reuse = reuse::ReuseState::new(pose.version, &pose.vertices);
        let passes = Passes {
            gbuffer: GBufferPass::new(&gpu)?,
            tonemaps: vec![TonemapPass::new(&gpu, readback::DISPLAY_FORMAT)?],
            hang: HangPass::from_env(&gpu)?,
        };
        let pipelines = Pipelines::new(&gpu, &frame_passes(), resolved.backend, &tuning)?;
        let mut runner = GraphRunner::new(&gpu, FRAMES_IN_FLIGHT)?;
        if let Some(hang) = &passes.hang {
            hang.release_on_device_lost(&mut runner);
        }
        let mut renderer = Renderer {
            list_capacity: 0,
            camera: scene.camera_or_framing(),
            lights: scene.lights.clone(),
            scene: scene.clone(),
            gpu_scene,
            pose,
            backend: resolved,
            traces: [None, None],
            passes,
            pipelines,
            view: ViewLayer::Final,
            exposure: None,
            accumulation: Default::default(),
            reuse,
            advance_seed: false,
            seed_offset: 0,
            budget: None,
            kernel: Default::default(),
            pending: VecDeque::new(),
            last: None,
            runner,
            settings,
            gpu,
        };
        renderer.list_capacity = renderer.default_list_capacity();
        renderer.prepare_backend(resolved.backend)?;
        renderer.gpu.check_validation()?;
        Ok(renderer)
    }

    /// Makes the trace structures and pipelines of `backend` on its first use.
    fn prepare_backend(&mut self, backend: Backend) -> Result<()> {
        let slot = &mut self.traces[backend as usize];
        if slot.is_none() {
            *slot = Some(TraceScene::build(&self.gpu, &self.scene, &self.gpu_scene, &self.pose, backend)?);
        }
        self.pipelines.prepare(&self.gpu, backend, &[])
    }

    /// Makes the on-demand pipelines (`ComputePassDef::on_demand`) that a frame of `splat`'s
    /// photons (its gather's estimator), of the path tracer (`reference`) and of this frame's
    /// view samples runs, where no frame made them before: a method the renderer has not run
    /// costs no pipeline.
    fn prepare_pipelines(&mut self, splat: Option<&crate::splatting::SplatFrame>, reference: bool) -> Result<()> {
        use crate::passes::{primary_rays::PRIMARY_RAYS, reference::REFERENCE};
        let mut wanted: Vec<_> = splat.map(|f| f.gather_pass()).into_iter().collect();
        if reference {
            wanted.push(REFERENCE.name);
        }
        if self.primary() == crate::Primary::Rays {
            wanted.push(PRIMARY_RAYS.name);
        }
        self.pipelines.prepare(&self.gpu, self.backend.backend, &wanted)
    }

    fn default_list_capacity(&self) -> u32 {
        let s = &self.settings;
        let photons = s.splat.paths.saturating_mul(s.max_bounces.max(1));
        s.splat.list_capacity.unwrap_or_else(|| {
            default_list_capacity(photons, s.width * s.height)
                .min(crate::limits::max_list_entries(&self.gpu.report().limits))
        })
    }

    /// What the renderer tunes to its device ([`DeviceTuning`]).
    pub fn tuning(&self) -> &DeviceTuning {
        self.pipelines.tuning()
    }

    /// Whether the pipeline of the pass labelled `label` is made on the current backend
    /// (on-demand passes are made by the first frame that runs them).
    pub fn has_pipeline(&self, label: &str) -> bool {
        self.pipelines.table(self.backend.backend).contains_label(label)
    }

    /// How this frame finds its view samples: `--primary`, with `auto` resolved for this
    /// device, scene and size (never `Auto`).
    pub fn primary(&self) -> crate::Primary {
        use crate::{tuning::PrimaryAuto, Primary};
        match self.settings.primary {
            Primary::Auto => {
                let pixels = self.settings.width as usize * self.settings.height as usize;
                match self.tuning().primary_auto {
                    PrimaryAuto::Rays => Primary::Rays,
                    PrimaryAuto::RaysOverDenseMeshes if self.scene.triangle_count() > pixels => Primary::Rays,
                    PrimaryAuto::RaysOverDenseMeshes | PrimaryAuto::Raster => Primary::Raster,
                }
            }
            chosen => chosen,
        }
    }

    pub fn gpu(&self) -> &Gpu {
        &self.gpu
    }

    pub fn backend(&self) -> Backend {
        self.backend.backend
    }

    /// Why this backend runs (`auto`'s choice, or the flag that forced it).
    pub fn backend_why(&self) -> &'static str {
        self.backend.why
    }

    /// What building the current backend's trace structures cost.
    pub fn trace_stats(&self) -> &TraceStats {
        self.traces[self.backend.backend as usize].as_ref().expect("current backend made").stats()
    }

    pub fn settings(&self) -> &RenderSettings {
        &self.settings
    }

    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    pub fn scene_name(&self) -> &str {
        &self.scene.name
    }

    pub fn camera(&self) -> &Camera {
        &self.camera
    }

    pub fn lights(&self) -> &[Light] {
        &self.lights
    }

    pub fn view_layer(&self) -> ViewLayer {
        self.view
    }

    /// Samples (reference) or frames accumulated in the image since the last change.
    pub fn accumulated(&self) -> u32 {
        self.accumulation.accumulated
    }

    /// The newest completed frame's report.
    pub fn last_report(&self) -> Option<&FrameReport> {
        self.last.as_ref()
    }

    /// Emissive triangles the renderer lights the scene with.
    pub fn emitter_count(&self) -> usize {
        self.gpu_scene.emitter_table.len()
    }

    /// The seed the next photon frame uses.
    pub fn frame_seed(&self) -> u32 {
        self.settings.seed.wrapping_add(self.seed_offset)
    }

    /// Waits until the next frame's slot is free (collecting the frame that ran in it) and
    /// returns its index: per-frame objects outside the renderer (the swapchain's acquire
    /// semaphores) are safe to reuse for that slot once this returns.
    pub fn wait_for_slot(&mut self) -> Result<usize> {
        if let Some(done) = self.runner.acquire_slot(&self.gpu)? {
            self.collect(done)?;
        }
        Ok(self.runner.next_slot())
    }

    /// The camera's view-projection for the output aspect ratio (the glTF yfov is kept), in
    /// Vulkan's clip space, y pointing down the image, with reversed depth: 1 at the near
    /// plane, 0 at the far one (or at infinity). A float depth buffer then keeps about the same
    /// relative precision at every distance; with depth 0 at the near plane, two surfaces a
    /// tenth of a millimetre apart 5 m away tie, and the raster can keep the hidden one (a
    /// wall's face below the floor it stands in). Without pixel jitter: what the first frame
    /// after a change sees through.
    pub fn view_proj(&self) -> Mat4 {
        let aspect = self.settings.width as f32 / self.settings.height as f32;
        let c = &self.camera;
        let proj = match c.zfar {
            // Near and far swapped: the same frustum with depth running from 1 down to 0.
            Some(zfar) => vulkan::perspective(c.yfov, aspect, zfar, c.znear),
            None => vulkan::perspective_infinite_reverse(c.yfov, aspect, c.znear),
        };
        proj * c.view_from_world()
    }

    /// The view-projection moved by `jitter` pixels on the image (accumulated frames).
    fn jittered_view_proj(&self, jitter: glam::Vec2) -> Mat4 {
        if jitter == glam::Vec2::ZERO {
            return self.view_proj();
        }
        let (w, h) = (self.settings.width as f32, self.settings.height as f32);
        // Clip-space x' = x + t·w moves the image by t in NDC, which spans 2 over the image.
        Mat4::from_translation(glam::Vec3::new(2.0 * jitter.x / w, 2.0 * jitter.y / h, 0.0)) * self.view_proj()
    }

    fn extent(&self) -> vk::Extent2D {
        vk::Extent2D { width: self.settings.width, height: self.settings.height }
    }

    /// Waits for every frame in flight (before reading back, or tearing resources down).
    pub fn wait_idle(&mut self) -> Result<()> {
        for done in self.runner.wait_idle(&self.gpu)? {
            self.collect(done)?;
        }
        Ok(())
    }

    /// The tonemap for `format`, made when first asked for (the window's swapchain format).
    pub fn prepare_display(&mut self, format: vk::Format) -> Result<()> {
        if !self.passes.tonemaps.iter().any(|t| t.format() == format) {
            self.passes.tonemaps.push(TonemapPass::new(&self.gpu, format)?);
        }
        Ok(())
    }
}

fn resolve(gpu: &Gpu, choice: BackendChoice) -> Result<ResolvedBackend> {
    let report = gpu.report();
    choice.resolve(gpu.capabilities(), report.device_type, &report.name)
}

impl Drop for Renderer {
    fn drop(&mut self) {
        // A stalled pass (fault injection) must end before the device can be waited on.
        if let Some(hang) = &self.passes.hang {
            hang.release();
        }
        // Frames may be in flight: their resources must outlive them. The runner gives up on a
        // frame that makes no progress within LEAKLESS_GPU_TIMEOUT (a lost device); a released
        // stall may still be draining then (on a loaded machine, past a 1 s timeout), and the
        // device's own wait lets it end before the resources it uses are destroyed. It is the
        // wait that dropping the device makes anyway, only before them.
        if self.runner.wait_idle(&self.gpu).is_err() {
            let _ = self.gpu.wait_idle();
        }
    }
}
