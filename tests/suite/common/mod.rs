//! Shared by the GPU tests: open the device with validation on, or say loudly why not.

#![allow(dead_code)]

use std::path::{Path, PathBuf};

use leakless::{Backend, Gpu, GpuOptions, RenderSettings, RenderedFrame, Renderer, Scene};

pub mod recorded;

pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

pub fn scene(path: &str) -> Scene {
    Scene::load(&root().join(path)).unwrap_or_else(|e| panic!("loading {path}: {e}"))
}

/// A scene's glTF `extras` (tools/gen-scenes writes there what tests measure against); an
/// empty value when it has none.
pub fn extras(scene: &Scene) -> serde_json::Value {
    scene.extras.as_deref().map(|e| serde_json::from_str(e).expect("extras are JSON")).unwrap_or_default()
}

/// The number `key` of a scene's extras.
pub fn extra(scene: &Scene, key: &str) -> f32 {
    extras(scene)[key].as_f64().unwrap_or_else(|| panic!("extras.{key}")) as f32
}

/// Opens the Vulkan device with validation (unless LEAKLESS_VALIDATION=0) and ray tracing.
/// With no device, the test is skipped loudly, or fails when LEAKLESS_REQUIRE_DEVICE=1 (CI).
pub fn gpu() -> Option<Gpu> {
    gpu_with(true)
}

/// The backends to test on, as render-setting choices (see [`backends`]).
pub fn choices() -> Vec<leakless::BackendChoice> {
    let Some(gpu) = gpu() else { return vec![] };
    backends(&gpu)
        .into_iter()
        .map(
            |b| {
                if b == Backend::RayQuery {
                    leakless::BackendChoice::RayQuery
                } else {
                    leakless::BackendChoice::Compute
                }
            },
        )
        .collect()
}

/// Renders an in-memory scene once, with validation checked.
pub fn render_scene(scene: &Scene, settings: RenderSettings) -> Option<RenderedFrame> {
    let gpu = gpu_with(settings.backend.wants_ray_queries())?;
    let mut renderer = Renderer::new(gpu, scene, settings).expect("renderer");
    let frame = renderer.render().expect("render");
    renderer.gpu().check_validation().expect("validation clean");
    Some(frame)
}

/// [`render_scene`] with a backend of [`choices`], which has a device.
pub fn render_chosen(scene: &Scene, settings: RenderSettings) -> RenderedFrame {
    render_scene(scene, settings).expect("checked by common::choices()")
}

pub fn gpu_with(ray_tracing: bool) -> Option<Gpu> {
    leakless::stderr_log::install();
    let validation = std::env::var("LEAKLESS_VALIDATION").map_or(true, |v| v != "0");
    match Gpu::new(&GpuOptions { validation: Some(validation), ray_tracing, window: None }) {
        Ok(gpu) => Some(gpu),
        Err(e) if std::env::var("LEAKLESS_REQUIRE_DEVICE").as_deref() == Ok("1") => {
            panic!("LEAKLESS_REQUIRE_DEVICE=1 but no Vulkan device: {e}")
        }
        Err(e) => {
            eprintln!("\n*** SKIPPED: no Vulkan device ({e}); install one with tools/install-deps ***\n");
            None
        }
    }
}

/// The backends to test on this device: the compute BVH always, ray queries when present.
/// With LEAKLESS_REQUIRE_RAYQUERY=1 (CI on Mesa 25) a device without them is a failure.
pub fn backends(gpu: &Gpu) -> Vec<Backend> {
    if gpu.capabilities().ray_query {
        vec![Backend::RayQuery, Backend::Compute]
    } else if std::env::var("LEAKLESS_REQUIRE_RAYQUERY").as_deref() == Ok("1") {
        panic!("LEAKLESS_REQUIRE_RAYQUERY=1 but {} has no ray queries", gpu.report().name)
    } else {
        eprintln!("\n*** ray queries unavailable on {}: testing the compute backend only ***\n", gpu.report().name);
        vec![Backend::Compute]
    }
}

pub fn render(path: &str, width: u32, height: u32) -> Option<RenderedFrame> {
    render_with(path, RenderSettings { width, height, ..Default::default() })
}

pub fn render_with(path: &str, settings: RenderSettings) -> Option<RenderedFrame> {
    render_scene(&scene(path), settings)
}

/// The label of a scene file's recorded references: its name without directory and extension.
pub fn label(path: &str) -> String {
    Path::new(path).file_stem().expect("a scene file").to_string_lossy().into_owned()
}

/// The reference path tracer's image of `path` at 64×48 (the size the comparison tests use),
/// recorded (see [`recorded`]).
pub fn reference(path: &str, spp: u32, max_bounces: u32) -> Option<RenderedFrame> {
    let settings = RenderSettings {
        width: 64,
        height: 48,
        method: leakless::Method::Reference,
        spp,
        max_bounces,
        seed: 1,
        ..Default::default()
    };
    recorded::reference(&label(path), settings, |s| render_with(path, s))
}

/// The reference path tracer's antialiased image of `path` at 8 bounces: `frames` frames of
/// `spp` samples each (one batch a frame), at the pixel jitters of the photon frames an
/// accumulation of as many frames renders; recorded (see [`recorded`]).
pub fn jittered_reference(
    path: &str,
    (width, height): (u32, u32),
    spp: u32,
    frames: u32,
    seed: u32,
) -> Option<RenderedFrame> {
    let settings = RenderSettings {
        width,
        height,
        method: leakless::Method::Reference,
        spp,
        frames,
        max_batches: 1,
        max_bounces: 8,
        seed,
        ..Default::default()
    };
    recorded::reference(&label(path), settings, |s| render_with(path, s))
}

/// A photon method at the leak scenes' test settings: 64×48, 4 bounces, seed 1.
pub fn photon_settings(
    method: leakless::Method,
    backend: leakless::BackendChoice,
    paths: u32,
    radius: f32,
) -> RenderSettings {
    RenderSettings {
        width: 64,
        height: 48,
        backend,
        method,
        max_bounces: 4,
        seed: 1,
        splat: leakless::SplatSettings { paths, radius: Some(radius), ..Default::default() },
        ..Default::default()
    }
}

/// Relative RMS difference of two layers: sqrt(Σ|a−b|²) / sqrt(Σ|b|²).
pub fn relative_rms(a: &[[f32; 3]], b: &[[f32; 3]]) -> f64 {
    let (mut num, mut den) = (0.0f64, 0.0f64);
    for (x, y) in a.iter().zip(b) {
        for c in 0..3 {
            num += ((x[c] - y[c]) as f64).powi(2);
            den += (y[c] as f64).powi(2);
        }
    }
    (num / den.max(1e-30)).sqrt()
}

pub fn mean(layer: &[[f32; 3]]) -> [f64; 3] {
    let mut m = [0.0f64; 3];
    for p in layer {
        for c in 0..3 {
            m[c] += p[c] as f64;
        }
    }
    m.map(|v| v / layer.len() as f64)
}

pub fn all_finite(layer: &[[f32; 3]]) -> bool {
    layer.iter().all(|p| p.iter().all(|c| c.is_finite()))
}

pub fn tmp_path(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"));
    dir.join(name)
}
