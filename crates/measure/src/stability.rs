//! `leakless stability`: each scene × method × backend against the reference — light in the
//! scene's dark box (a leak where the reference is black), energy against the reference, relMSE, RMSE, HDR-FLIP, NaN/Inf
//! count, flicker and frame time. What the stress scenes (docs/scenes.md) are measured by.

use leakless_device::Gpu;
use leakless_scene::Scene;

use crate::bench::Measured;
use crate::chart::flip;
use crate::extras::{extras, in_dark_box};
use crate::flicker::{flicker, FLICKER_FRAMES};
use crate::metrics;
use crate::metrics::{luminance, mean_luminance};
use leakless::error::Result;
use leakless::trace::{Backend, BackendChoice};
use leakless::{Method, RenderSettings, RenderedFrame, Renderer, SplatSettings};

/// The methods measured.
pub const STABILITY_METHODS: [Method; 4] = [Method::Direct, Method::Splat, Method::LeakLessCapped, Method::LeakLess];

/// What one scene, method and backend measured.
#[derive(Clone, Debug)]
pub struct StabilityRow {
    pub scene: String,
    pub method: Method,
    pub backend: Backend,
    /// Mean luminance of the radiance over the pixels whose surface lies in the scene's dark
    /// box, where the reference is exactly 0 (`None` when no pixel sees the box).
    pub dark_radiance: Option<f64>,
    /// The image's mean luminance over the reference's (`None` for a black reference).
    pub energy: Option<f64>,
    /// Share of the gathered indirect energy the visibility test removed.
    pub leaked_fraction: Option<f64>,
    pub relmse: Option<f64>,
    pub rmse: Option<f64>,
    pub flip: f64,
    /// Values in any layer that are NaN or infinite.
    pub non_finite: usize,
    pub flicker: Option<f64>,
    pub frame_ms: f64,
}

/// One scene's rows.
#[derive(Clone, Debug)]
pub struct SceneStability {
    pub scene: String,
    pub purpose: Option<String>,
    pub rows: Vec<StabilityRow>,
}

#[derive(Clone, Debug)]
pub struct StabilityConfig {
    pub width: u32,
    pub height: u32,
    pub paths: u32,
    pub spp: u32,
    pub max_bounces: u32,
    pub backends: Vec<Backend>,
    /// Each scene's fixed radius (5% of its bounding radius), not the photon count's.
    pub fixed_radius: bool,
}

fn dark_radiance(frame: &RenderedFrame, in_dark: &[bool]) -> Option<f64> {
    let n = in_dark.iter().filter(|d| **d).count();
    if n == 0 {
        return None;
    }
    let sum: f64 = frame.radiance.iter().zip(in_dark).filter(|(_, d)| **d).map(|(p, _)| luminance(p)).sum();
    Some(sum / n as f64)
}

/// Measures `scene` with every method on every backend of `config`, each on a fresh device.
pub fn measure(
    open: &dyn Fn(bool) -> Result<Gpu>,
    scene: &Scene,
    config: &StabilityConfig,
    progress: &mut dyn FnMut(&str),
) -> Result<SceneStability> {
    let base = RenderSettings {
        width: config.width,
        height: config.height,
        max_bounces: config.max_bounces,
        seed: 1,
        splat: SplatSettings {
            paths: config.paths,
            radius: config.fixed_radius.then(|| leakless::splatting::auto_radius(scene)),
            ..Default::default()
        },
        ..Default::default()
    };
    progress("reference");
    let mut renderer = Renderer::new(
        open(false)?,
        scene,
        RenderSettings { method: Method::Reference, spp: config.spp, backend: BackendChoice::Compute, ..base.clone() },
    )?;
    let reference = renderer.render()?;
    let positions = renderer.capture()?.position;
    drop(renderer);
    let in_dark = in_dark_box(scene, &positions).unwrap_or_else(|| vec![false; positions.len()]);
    let reference_mean = mean_luminance(&reference.radiance);
    let eps = metrics::epsilon(&reference.radiance);
    let mut rows = Vec::new();
    for &backend in &config.backends {
        let choice = match backend {
            Backend::RayQuery => BackendChoice::RayQuery,
            Backend::Compute => BackendChoice::Compute,
        };
        for method in STABILITY_METHODS {
            progress(&format!("{} {}", method.name(), backend.name()));
            let settings = RenderSettings { method, backend: choice, ..base.clone() };
            let opener = || open(backend == Backend::RayQuery);
            let measured = Measured::best_of(&opener, scene, method.name(), &settings, 1)?;
            let frame = &measured.frame;
            let non_finite = [&frame.radiance, &frame.direct, &frame.indirect, &frame.leaked]
                .iter()
                .flat_map(|l| l.iter().flatten())
                .filter(|c| !c.is_finite())
                .count();
            let flicker = if method.splats() {
                let mut r = Renderer::new(opener()?, scene, settings.clone())?;
                Some(flicker(&mut r, FLICKER_FRAMES)?)
            } else {
                None
            };
            rows.push(StabilityRow {
                scene: scene.name.clone(),
                method,
                backend,
                dark_radiance: dark_radiance(frame, &in_dark),
                energy: (reference_mean > 0.0).then(|| mean_luminance(&frame.radiance) / reference_mean),
                leaked_fraction: frame.splat.as_ref().and_then(crate::chart::leaked_fraction),
                relmse: metrics::rel_mse(&frame.radiance, &reference.radiance, None, eps),
                rmse: metrics::rmse(&frame.radiance, &reference.radiance, None),
                flip: flip::hdr_flip(&frame.radiance, &reference.radiance, frame.width, frame.height),
                non_finite,
                flicker,
                frame_ms: measured.frame_ms(),
            });
        }
    }
    Ok(SceneStability {
        scene: scene.name.clone(),
        purpose: extras(scene)["purpose"].as_str().map(str::to_string),
        rows,
    })
}
