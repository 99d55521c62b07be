//! Shared by the GPU tests: open the device with validation on, or say loudly why not.

#![allow(dead_code)]

use std::path::{Path, PathBuf};

use leakless::{Gpu, GpuOptions, RenderSettings, RenderedFrame, Renderer, Scene};

pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

pub fn scene(path: &str) -> Scene {
    Scene::load(&root().join(path)).unwrap_or_else(|e| panic!("loading {path}: {e}"))
}

/// Opens the Vulkan device with validation (unless LEAKLESS_VALIDATION=0). With no device,
/// the test is skipped loudly, or fails when LEAKLESS_REQUIRE_DEVICE=1 (CI).
pub fn gpu() -> Option<Gpu> {
    let validation = std::env::var("LEAKLESS_VALIDATION").map_or(true, |v| v != "0");
    match Gpu::new(&GpuOptions {
        validation: Some(validation),
        ray_tracing: false,
    }) {
        Ok(gpu) => Some(gpu),
        Err(e) if std::env::var("LEAKLESS_REQUIRE_DEVICE").as_deref() == Ok("1") => {
            panic!("LEAKLESS_REQUIRE_DEVICE=1 but no Vulkan device: {e}")
        }
        Err(e) => {
            eprintln!(
                "\n*** SKIPPED: no Vulkan device ({e}); install one with tools/install-deps ***\n"
            );
            None
        }
    }
}

pub fn render(path: &str, width: u32, height: u32) -> Option<RenderedFrame> {
    let gpu = gpu()?;
    let scene = scene(path);
    let mut renderer =
        Renderer::new(gpu, &scene, RenderSettings { width, height }).expect("renderer");
    let frame = renderer.render().expect("render");
    renderer.gpu().check_validation().expect("validation clean");
    Some(frame)
}

pub fn all_finite(layer: &[[f32; 3]]) -> bool {
    layer.iter().all(|p| p.iter().all(|c| c.is_finite()))
}

pub fn tmp_path(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"));
    dir.join(name)
}
