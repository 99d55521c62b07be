//! Benchmarks: ratios measured in one process (lavapipe's speed varies by tens of percent
//! between processes), printed by `leakless bench`, never asserted by a timed test.

use leakless_device::Gpu;
use leakless_graph::PassName;
use leakless_scene::Scene;

use crate::raycast::RayCaster;
use crate::raygen;
use leakless::error::Result;
use leakless::gpu_types::GpuRay;
use leakless::passes::names::group;
use leakless::passes::photons::PHOTONS;
use leakless::trace::Backend;

/// Rays per second of one backend on one ray set and query.
#[derive(Clone, Debug)]
pub struct RayRate {
    pub backend: Backend,
    pub set: &'static str,
    pub query: &'static str,
    pub rays: usize,
    /// Best of the repeats, host wall time of the trace submission alone.
    pub best_ms: f64,
    /// The compute traversal's mean work per ray (nodes processed, triangles tested), from its
    /// counting pass (untimed); `None` on ray queries.
    pub work_per_ray: Option<(f64, f64)>,
}

impl RayRate {
    pub fn mrays_per_s(&self) -> f64 {
        self.rays as f64 / (self.best_ms * 1e3)
    }
}

/// Occlusion and closest-hit rays per second on every backend the device has, for coherent
/// camera rays (`width`×`height`) and incoherent hemisphere rays from their hits.
pub fn rays(gpu: &Gpu, scene: &Scene, width: u32, height: u32, repeats: u32) -> Result<Vec<RayRate>> {
    let mut backends = vec![];
    if gpu.capabilities().ray_query {
        backends.push(Backend::RayQuery);
    }
    backends.push(Backend::Compute);
    let coherent = raygen::camera_rays(&scene.camera_or_framing(), width, height);
    let mut incoherent: Option<Vec<GpuRay>> = None;
    let mut rates = Vec::new();
    for backend in backends {
        let mut caster = RayCaster::new(gpu, scene, backend)?;
        if incoherent.is_none() {
            let hits = caster.cast(&coherent, false)?.hits;
            incoherent = Some(raygen::hemisphere_rays(scene, &coherent, &hits, 7));
        }
        for (set, rays) in [("coherent", &coherent), ("incoherent", incoherent.as_ref().expect("made above"))] {
            for (query, occlusion) in [("occluded", true), ("closest", false)] {
                caster.cast(rays, occlusion)?; // warm-up: shader compilation, caches
                let mut best = f64::INFINITY;
                for _ in 0..repeats.max(1) {
                    best = best.min(caster.cast(rays, occlusion)?.trace_ms);
                }
                let work_per_ray = caster.count_work(rays, occlusion)?.map(|work| {
                    let n = work.len().max(1) as f64;
                    let sum = |f: fn(&leakless::passes::raycast::RayWork) -> u32| {
                        work.iter().map(|w| f(w) as f64).sum::<f64>() / n
                    };
                    (sum(|w| w.nodes), sum(|w| w.triangles))
                });
                rates.push(RayRate { backend, set, query, rays: rays.len(), best_ms: best, work_per_ray });
            }
        }
    }
    Ok(rates)
}

/// How the benchmarks time a frame on `gpu` (its tuning's timing), for their headers.
pub fn timing_phrase(gpu: &Gpu) -> &'static str {
    timing_words(leakless::DeviceTuning::choose(gpu.report(), leakless::TuningChoice::Auto).timing)
}

/// What a frame's time is under `timing`.
pub fn timing_words(timing: leakless_graph::Timing) -> &'static str {
    match timing {
        leakless_graph::Timing::PerPassSubmit => "wall time of each pass submitted alone, the frame their sum",
        leakless_graph::Timing::Timestamps => {
            "GPU timestamps in one submission, the frame from the first pass's start to the last one's end"
        }
    }
}

/// A renderer's second frame (the first compiles shaders), timed as the device tuning says:
/// on a CPU device every pass submitted and timed on its own, on a GPU the whole frame in one
/// submission with GPU timestamps. What `bench splat`, `bench leak`, `chart` and the GPU
/// report compare.
#[derive(Clone, Debug)]
pub struct Measured {
    pub label: String,
    pub settings: leakless::RenderSettings,
    pub frame: leakless::RenderedFrame,
    /// Each pass's time, ms, in frame order, with the pass's group
    /// (`passes::names::group`): the host wall time of its own submission, or its GPU
    /// timestamps' difference.
    pub passes: Vec<(String, &'static str, f64)>,
    /// The timing the frame was measured with (the device tuning's).
    pub timing: leakless_graph::Timing,
}

impl Measured {
    /// Renders `scene` with `settings` twice and keeps the second frame.
    pub fn run(
        open: &dyn Fn() -> Result<Gpu>,
        scene: &Scene,
        label: &str,
        settings: &leakless::RenderSettings,
    ) -> Result<Measured> {
        Self::best_of(open, scene, label, settings, 1)
    }

    /// Renders a first frame (shader compilation), then `repeats` more, and keeps the fastest
    /// (a fixed seed makes them the same image).
    pub fn best_of(
        open: &dyn Fn() -> Result<Gpu>,
        scene: &Scene,
        label: &str,
        settings: &leakless::RenderSettings,
        repeats: u32,
    ) -> Result<Measured> {
        Self::best_of_renderer(&mut leakless::Renderer::new(open()?, scene, settings.clone())?, label, repeats)
    }

    /// [`Measured::best_of`] with a renderer of the caller's (kept for the next settings, or
    /// with a tuning of its own).
    pub fn best_of_renderer(renderer: &mut leakless::Renderer, label: &str, repeats: u32) -> Result<Measured> {
        let settings = renderer.settings().clone();
        let timing = renderer.tuning().timing;
        renderer.set_timing(timing);
        renderer.render()?;
        let mut best: Option<Measured> = None;
        for _ in 0..repeats.max(1) {
            let frame = renderer.render()?;
            let passes = frame.timings.iter().map(|t| (t.name.clone(), t.group, t.wall_ms.unwrap_or(t.ms))).collect();
            let run = Measured { label: label.to_string(), settings: settings.clone(), frame, passes, timing };
            if best.as_ref().is_none_or(|b| run.frame_ms() < b.frame_ms()) {
                best = Some(run);
            }
        }
        renderer.gpu().check_validation()?;
        Ok(best.expect("at least one frame"))
    }

    /// The photon counts (every run of these benchmarks uses a photon method).
    pub fn stats(&self) -> &leakless::splatting::SplatStats {
        self.frame.splat.as_ref().expect("benchmarks run photon methods")
    }

    /// Summed time of the passes of `group` (`passes::names::group`).
    pub fn group_ms(&self, group: &str) -> f64 {
        // (+ 0.0: an empty f64 sum is -0.0.)
        self.passes.iter().filter(|(_, g, _)| *g == group).map(|(_, _, ms)| ms).sum::<f64>() + 0.0
    }
    /// The frame's time: its passes' submissions summed, or on the GPU its span from the
    /// first pass's start to the last one's end.
    pub fn frame_ms(&self) -> f64 {
        match self.timing {
            leakless_graph::Timing::PerPassSubmit => self.passes.iter().map(|(_, _, ms)| ms).sum(),
            leakless_graph::Timing::Timestamps => self.frame.gpu_span_ms,
        }
    }
    /// The time of the pass `name`.
    pub fn pass_ms(&self, name: PassName) -> f64 {
        self.passes.iter().filter(|(n, _, _)| n == name.label).map(|(_, _, ms)| ms).sum::<f64>() + 0.0
    }
    /// The photon pass and the passes that order its paths (emission_order.rs): what the
    /// photon pass's ray rate is measured over (not its counters' clear, nor the dispatch
    /// command made from them, which the frame's `photons` group also holds).
    pub fn photons_ms(&self) -> f64 {
        use leakless::passes::emission_order::{
            EMISSION_CELLS, EMISSION_CELLS_CLEAR, EMISSION_CELL_STARTS, EMISSION_ORDER,
        };
        let passes =
            [PHOTONS.name, EMISSION_CELLS_CLEAR, EMISSION_CELLS.name, EMISSION_CELL_STARTS, EMISSION_ORDER.name];
        passes.into_iter().map(|p| self.pass_ms(p)).sum()
    }
    pub fn hierarchy_ms(&self) -> f64 {
        self.group_ms(group::HIERARCHY)
    }
    pub fn splat_ms(&self) -> f64 {
        self.group_ms(group::SPLAT)
    }
    pub fn gather_ms(&self) -> f64 {
        self.group_ms(group::GATHER)
    }
}
