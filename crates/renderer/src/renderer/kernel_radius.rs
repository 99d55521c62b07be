//! The gather radius of each photon frame where `--radius` is not given: the one at which a
//! kernel holds about K photons ([`KernelDensity`]), from the density of photons on the
//! surfaces the view sees. Each frame that starts an accumulation (every frame while the view
//! moves) measures that density for the frames after it. A frame with none before it (a
//! render's first, the app's first) is preceded by a probe: its own photons (same paths, same
//! seed), splatted and gathered at a guessed radius without visibility rays, in a submission
//! that the renderer waits for; its counts give the density, and the frame gathers at the
//! radius they ask for.

use bytemuck::{Pod, Zeroable};
use leakless_device::SubmitSync;

use super::view_samples::ViewSamples;
use super::Renderer;
use crate::error::Result;
use crate::passes::gather::{self, GatherCounters, GatherOutputs};
use crate::passes::gbuffer::GBufferHandles;
use crate::passes::photons::PhotonCounters;
use crate::passes::splat::SplatCounters;
use crate::passes::{names, readback, ViewInputs};
use crate::photon_lights::upload_lights;
use crate::splatting::{self, auto_radius, progressive_radius, KernelDensity, SplatFrame, KERNEL_RADIUS_RANGE};

/// What the renderer knows of the view's photon density.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct KernelState {
    /// From the last frame (or probe) that gathered photons.
    density: Option<KernelDensity>,
    /// A probe ran (even one that saw no photon: a dark view waits for frames that do).
    probed: bool,
    /// The single-frame radius of one batch of `--paths` paths when the accumulation started:
    /// its batches follow Knaus and Zwicker's sequence from it, whatever frames measure later.
    accumulation_radius: Option<f32>,
    /// The radius of the accumulation's first frame (its paths may be the budget's).
    first_radius: Option<f32>,
    /// A fixed radius for every accumulation's first frame (`render --first-frame-radius`:
    /// what a capture of the app records, with `--radius` for the batches after it).
    fixed_first_radius: Option<f32>,
}

/// Probes at most this many times: each but the first starts from the radius the one before
/// asked for.
const MAX_PROBES: u32 = 3;

/// A probe whose count is within this factor of K measured near enough the radius it asks
/// for: the count grows as r² only where the density is even over the change of radius.
const PROBE_TOLERANCE: f64 = 2.0;

/// The counters a probe copies out, in this order.
#[repr(C)]
#[derive(Clone, Copy, Default, Pod, Zeroable)]
struct ProbeCounters {
    photons: PhotonCounters,
    lists: SplatCounters,
    gather: GatherCounters,
}

const PROBE_COUNTERS_BUFFER: &str = "kernel probe counters";

impl Renderer {
    /// The radius a single frame of `paths` light paths gathers within: `--radius`, else the
    /// one at which a kernel holds `kernel_photons` photons of them, as far as the frames so far
    /// measured the view's density (the scene's fixed 5% radius before any did).
    pub fn single_frame_radius(&self, paths: u32) -> f32 {
        let fixed = auto_radius(&self.scene);
        match (self.settings.splat.radius, self.kernel.density) {
            (Some(r), _) => r,
            (None, Some(d)) => d.radius(self.settings.splat.kernel_photons, paths, fixed),
            (None, None) => fixed,
        }
    }

    /// The radius of photon batch `first_batch` of the accumulation, for a frame of `paths`
    /// paths (batch 0: the single frame; after it, the sequence from the accumulation's start).
    /// A frame of fewer paths than `--paths` (the frame budget's cut) keeps the radius of
    /// `--paths`, its kernels holding fewer than K photons: the cut then cuts the gather's work
    /// with the photons', which a radius growing as 1/√p would keep at K photons a sample
    /// (docs/results.md, *Frame budget*). More paths than `--paths` shrink it.
    pub(super) fn batch_radius(&self, first_batch: u32, paths: u32) -> f32 {
        let paths = paths.max(self.settings.splat.paths);
        match (first_batch, self.settings.splat.radius, self.kernel.accumulation_radius) {
            (0, _, _) => self.kernel.fixed_first_radius.unwrap_or_else(|| self.single_frame_radius(paths)),
            (i, Some(r), _) => progressive_radius(r, i),
            (i, None, Some(start)) => progressive_radius(start, i),
            (i, None, None) => progressive_radius(self.accumulation_start(), i),
        }
    }

    /// An accumulation starts: its batches' radii follow from the density known now.
    pub(super) fn start_accumulation_radius(&mut self) {
        self.kernel.accumulation_radius = Some(self.accumulation_start());
    }

    /// The radius an accumulation's batches shrink from: the count's radius for one batch of
    /// `--paths` paths, at most the scene's fixed radius. An accumulation averages its batches'
    /// noise away, so its kernels need no more photons than its bias allows; where photons are
    /// few, a start at the count's radius lets that bias last (docs/results.md, *Converging at
    /// the photon count's radius*).
    fn accumulation_start(&self) -> f32 {
        let single = self.single_frame_radius(self.settings.splat.paths);
        match self.settings.splat.radius {
            Some(_) => single,
            None => single.min(auto_radius(&self.scene)),
        }
    }

    /// The first frame of an accumulation was made at `radius`.
    pub(super) fn record_first_radius(&mut self, radius: f32) {
        self.kernel.first_radius = Some(radius);
    }

    /// The radii of the current accumulation: its first frame's, and the one its later
    /// batches shrink from (`progressive_radius`); `None` before a photon frame.
    pub fn accumulation_radii(&self) -> Option<(f32, f32)> {
        self.kernel.first_radius.zip(self.kernel.accumulation_radius)
    }

    /// Fixes the radius of every accumulation's first frame (`None`: as `--radius` or the
    /// photon count says).
    pub fn set_first_frame_radius(&mut self, radius: Option<f32>) -> Result<()> {
        if let Some(r) = radius.filter(|r| !(r.is_finite() && *r > 0.0)) {
            return Err(crate::RenderError::Settings(format!("--first-frame-radius {r} must be a positive number")));
        }
        self.kernel.fixed_first_radius = radius;
        Ok(())
    }

    /// Forgets the density the frames so far measured: the next frame probes its own photons
    /// (a render has no frames before it).
    pub(super) fn forget_kernel_density(&mut self) {
        (self.kernel.density, self.kernel.probed) = (None, false);
    }

    /// Whether the next frame that starts an accumulation needs a probe first.
    pub(super) fn needs_kernel_probe(&self) -> bool {
        self.settings.splat.radius.is_none() && self.kernel.density.is_none() && !self.kernel.probed
    }

    /// A completed frame's counts: one that started an accumulation at the count-following
    /// radius measures the density for the frames after it.
    pub(super) fn observe_kernel(&mut self, frame: &SplatFrame, gather: &GatherCounters) {
        if frame.first_batch != 0 || self.settings.splat.radius.is_some() {
            return;
        }
        let measured =
            KernelDensity::measured(gather.accepted(), gather.valid_samples, frame.settings.paths, frame.radius);
        // A frame whose visibility rays culled every photon it accepted sees a sealed room's
        // walls from inside: the photons its kernels took are the sparse ones behind them, and
        // a radius for K of those grows to the range's cap over 16× the area, all culled. The
        // image does not depend on the radius there: the fixed one, until a frame keeps some.
        if frame.settings.visibility && gather.accepted() > 0 && gather.occluded() >= gather.accepted() {
            self.kernel.density = None;
        } else if measured.is_some() {
            self.kernel.density = measured;
        }
    }

    /// Measures the density with `frame`'s own photons before it is rendered: see the module.
    pub(super) fn probe_kernel(&mut self, frame: &SplatFrame) -> Result<()> {
        self.wait_idle()?;
        self.kernel.probed = true;
        let probed = self.probe_radius(frame);
        // The budget times frames, not the probe's waited submissions.
        self.restart_budget_clock();
        probed
    }

    fn probe_radius(&mut self, frame: &SplatFrame) -> Result<()> {
        let fixed = auto_radius(&self.scene);
        let k = self.settings.splat.kernel_photons as f64;
        // 10k paths at the fixed radius held 2–40 photons a kernel in the shipped scenes.
        let (lo, hi) = KERNEL_RADIUS_RANGE;
        let mut radius = (fixed * (10_000.0 / frame.settings.paths.max(1) as f32).sqrt()).clamp(lo * fixed, hi * fixed);
        for _ in 0..MAX_PROBES {
            let mut probe = frame.clone();
            probe.radius = radius;
            probe.first_batch = 0;
            probe.settings.visibility = false;
            let counters = self.run_probe(&probe)?;
            let Some(density) = KernelDensity::measured(
                counters.gather.accepted(),
                counters.gather.valid_samples,
                probe.settings.paths,
                radius,
            ) else {
                return Ok(()); // no photon in view: the fixed radius, until a frame sees some
            };
            self.kernel.density = Some(density);
            let next = density.radius(k as f32, probe.settings.paths, fixed);
            let count = density.photons_per_kernel(probe.settings.paths, radius);
            if (k / PROBE_TOLERANCE..=k * PROBE_TOLERANCE).contains(&count) || next == radius {
                break;
            }
            radius = next;
        }
        Ok(())
    }

    /// One probe: the view's G-buffer and `probe`'s photons, splatted and gathered; its counts.
    fn run_probe(&mut self, probe: &SplatFrame) -> Result<ProbeCounters> {
        self.prepare_pipelines(Some(probe), false)?;
        let frame_constants = self.frame_constants(glam::Vec2::ZERO);
        let extent = self.extent();
        let trace_scene = self.traces[self.backend.backend as usize].as_ref().expect("current backend made");
        let raster = (&self.passes.gbuffer, self.gpu_scene.vertex_count);
        let view_samples = ViewSamples::new(self.primary(), raster, &frame_constants, self.camera.zfar.is_some());
        let mut g = self.runner.graph(&self.gpu)?.with_pipelines(self.pipelines.table(self.backend.backend));
        let frame =
            g.upload("frame", ash::vk::BufferUsageFlags::UNIFORM_BUFFER, bytemuck::bytes_of(&frame_constants))?;
        let lights = upload_lights(&mut g, &self.lights, &self.gpu_scene.emitter_table, &self.scene.bounds())?;
        // Instances moved since the last frame are where it placed them: the probe estimates.
        let scene = self.gpu_scene.import(&mut g);
        let trace = trace_scene.import(&mut g, &self.gpu_scene, &self.pose)?;
        crate::frame_set::bind(&mut g, &scene, &trace);
        let mut gbuffer = GBufferHandles::new(&mut g, extent)?;
        view_samples.add(&mut g, (&frame, &scene), &mut gbuffer);
        let view = ViewInputs { frame: &frame, lights: &lights.lights, scene: &scene, gbuffer: &gbuffer };
        let mut indirect_sum = super::frame::layer(&mut g, extent, "indirect sum")?;
        let mut leaked = super::frame::layer(&mut g, extent, "leaked")?;
        let mut counts = super::frame::layer(&mut g, extent, "gather counts")?;
        let mut gather_counters = gather::counters(&mut g)?;
        let out = GatherOutputs {
            indirect_sum: &mut indirect_sum,
            leaked: &mut leaked,
            counts: &mut counts,
            counters: &mut gather_counters,
        };
        let s = splatting::add(&mut g, probe, &view, &lights, out)?;
        let copied = [&s.photons, &s.lists, &gather_counters];
        readback::add_buffers(&mut g, (PROBE_COUNTERS_BUFFER, names::FRAME_COUNTERS), &copied)?;
        let submitted = g.submit(&SubmitSync::default())?;
        let done = self.runner.wait_for(&self.gpu, submitted)?;
        let buffer = self.runner.pool().frame_buffer(PROBE_COUNTERS_BUFFER, done.slot).expect("copied above");
        let mut counters = ProbeCounters::default();
        buffer.read(0, bytemuck::bytes_of_mut(&mut counters))?;
        Ok(counters)
    }
}
