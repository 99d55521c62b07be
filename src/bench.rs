//! Benchmarks: ratios measured in one process (lavapipe's speed varies by tens of percent
//! between processes), printed by `leakless bench`, never asserted by a timed test.

use leakless_device::Gpu;
use leakless_scene::Scene;

use crate::error::Result;
use crate::gpu_types::GpuRay;
use crate::raycast::RayCaster;
use crate::raygen;
use crate::trace::Backend;

/// Rays per second of one backend on one ray set and query.
#[derive(Clone, Debug)]
pub struct RayRate {
    pub backend: Backend,
    pub set: &'static str,
    pub query: &'static str,
    pub rays: usize,
    /// Best of the repeats, host wall time of the trace submission alone.
    pub best_ms: f64,
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
                rates.push(RayRate { backend, set, query, rays: rays.len(), best_ms: best });
            }
        }
    }
    Ok(rates)
}
