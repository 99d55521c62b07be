//! View samples found by a ray a pixel (`--primary rays`, primary_rays.comp) against the
//! rasterised G-buffer: the same surfaces, so the same first frame up to the last bits of an
//! interpolated attribute.

use crate::common;

use leakless::{Method, Primary, RenderSettings, RenderedFrame};

/// Per pixel, whether `a` and `b` differ by more than a part in a thousand (of the larger, or
/// of 1e-3 where both are darker).
fn differs(a: [f32; 3], b: [f32; 3]) -> bool {
    a.iter().zip(b).any(|(x, y)| (x - y).abs() > 1e-3 * x.abs().max(y.abs()).max(1e-3))
}

fn mean(layer: &[[f32; 3]]) -> f64 {
    layer.iter().map(|p| (p[0] + p[1] + p[2]) as f64).sum::<f64>() / layer.len() as f64
}

/// Direct light (a function of the view samples alone, its random numbers seeded by pixel) with
/// the G-buffer rasterised and ray cast, on both backends: the pixels that differ are the odd
/// pixel whose centre lies on an edge, and the image means agree.
#[test]
fn primary_rays_find_the_surfaces_the_raster_finds() {
    for backend in common::choices() {
        for (path, width, height) in [
            ("scenes/cornell-box.gltf", 64, 48),
            ("tests/scenes/textured-quad.gltf", 66, 66),
            ("scenes/atrium.gltf", 64, 48),
            ("scenes/door.gltf", 64, 48),
        ] {
            let render = |primary| {
                let settings =
                    RenderSettings { width, height, backend, method: Method::Direct, primary, ..Default::default() };
                common::render_with(path, settings).expect("a device: choices() found one")
            };
            let (raster, rays): (RenderedFrame, RenderedFrame) = (render(Primary::Raster), render(Primary::Rays));
            let differing = raster.direct.iter().zip(&rays.direct).filter(|(a, b)| differs(**a, **b)).count();
            let share = differing as f64 / raster.direct.len() as f64;
            let (m_raster, m_rays) = (mean(&raster.direct), mean(&rays.direct));
            eprintln!("{path} {backend:?}: {differing} pixels differ ({share:.4}), means {m_raster} {m_rays}");
            assert!(share <= 0.005, "{path} {backend:?}: {differing} pixels differ");
            assert!((m_rays - m_raster).abs() <= 0.002 * m_raster, "{path} {backend:?}: means {m_raster} {m_rays}");
            assert!(rays.timings.iter().any(|t| t.name == "primary rays"), "{path}: no primary rays pass");
        }
    }
}

/// `--primary auto` casts rays where the CPU preset says a scene of more triangles than pixels
/// rasterises slowly, and rasterises otherwise and on the GPU preset (lavapipe forced to it: a
/// CPU device keeps its raster whatever its ray queries).
#[test]
fn auto_casts_rays_for_more_triangles_than_pixels_on_a_cpu() {
    if common::gpu().is_none() {
        return;
    }
    // The sphere has 5120 triangles: more than 64×48 pixels, fewer than 128×96.
    let scene = common::scene("scenes/sphere.gltf");
    for (tuning, (width, height), expected) in [
        (leakless::TuningChoice::Cpu, (64, 48), Primary::Rays),
        (leakless::TuningChoice::Cpu, (128, 96), Primary::Raster),
        (leakless::TuningChoice::Gpu, (64, 48), Primary::Raster),
    ] {
        let gpu = common::gpu().expect("a device");
        let settings = RenderSettings { width, height, tuning, primary: Primary::Auto, ..Default::default() };
        let renderer = leakless::Renderer::new(gpu, &scene, settings).expect("renderer");
        assert_eq!(renderer.primary(), expected, "{tuning:?} at {width}x{height}");
    }
}

/// On a GPU the rule follows its ray queries: without them (a compute chip such as the H200,
/// whose raster took 6.5 ms of a 1080p frame) every frame casts rays; with them it rasterises.
/// The device report is lavapipe's, its type and ray queries set to a GPU's.
#[test]
fn auto_casts_rays_on_a_gpu_without_ray_queries_and_rasterises_on_one_with_them() {
    use leakless::{DeviceTuning, PrimaryAuto, TuningChoice};
    use leakless_device::DeviceType;
    let Some(gpu) = common::gpu() else { return };
    let mut report = gpu.report().clone();
    drop(gpu);
    assert_eq!(DeviceTuning::choose(&report, TuningChoice::Auto).primary_auto, PrimaryAuto::RaysOverDenseMeshes);
    report.device_type = DeviceType::Discrete;
    for (ray_query, expected) in [(false, PrimaryAuto::Rays), (true, PrimaryAuto::Raster)] {
        report.ray_query = ray_query;
        let tuning = DeviceTuning::choose(&report, TuningChoice::Auto);
        assert_eq!(tuning.primary_auto, expected, "ray queries {ray_query}");
    }
}
