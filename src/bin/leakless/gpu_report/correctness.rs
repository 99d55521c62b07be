//! The report's correctness section: every shipped scene rendered with validation on, against
//! the same render made on lavapipe's compute backend (`tests/fixtures/gpu-report/`, made by
//! `leakless gpu-report --make-fixtures`). Another device traces the same photons up to
//! floating-point rounding, so a correct render is much closer to the fixture than a render of
//! another seed is: that seed's error is kept in the fixture as the yardstick, and a render
//! matches within half of it.

use std::path::{Path, PathBuf};

use anyhow::Context;
use serde::Serialize;

use leakless::metrics;
use leakless::output::exr::{self, ExrLayer};
use leakless::{BackendChoice, Method, RenderSettings, Renderer, Scene, SplatSettings};

use super::Report;

const FIXTURES: &str = "tests/fixtures/gpu-report";
const SIZE: (u32, u32) = (64, 48);
const PATHS: u32 = 10_000;
/// A render matches when its relMSE against the fixture is at most this share of another
/// seed's: the same photons, up to rounding that sends some paths elsewhere.
const MATCH_SHARE: f64 = 0.5;
/// The attribute holding another seed's relMSE against the fixture.
const NOISE_ATTRIBUTE: &str = "leakless.other_seed_relmse";

/// One scene's check.
#[derive(Serialize)]
pub struct Check {
    pub scene: String,
    pub backend: String,
    /// relMSE against the fixture (ε = 1% of its squared mean).
    pub rel_mse: f64,
    /// relMSE of another seed's render against the fixture, on the fixture's device.
    pub other_seed_rel_mse: f64,
    /// Mean of the render over the fixture's.
    pub mean_ratio: f64,
    pub non_finite: usize,
    pub passed: bool,
    pub verdict: String,
}

fn settings(backend: BackendChoice, seed: u32) -> RenderSettings {
    RenderSettings {
        width: SIZE.0,
        height: SIZE.1,
        backend,
        method: Method::LeakLess,
        seed,
        splat: SplatSettings { paths: PATHS, ..Default::default() },
        ..Default::default()
    }
}

/// The shipped scenes (`scenes/*.gltf`), sorted.
fn scenes(root: &Path) -> anyhow::Result<Vec<PathBuf>> {
    let mut scenes: Vec<PathBuf> =
        std::fs::read_dir(root.join("scenes"))?.map(|e| e.map(|e| e.path())).collect::<Result<_, _>>()?;
    scenes.retain(|p| p.extension().is_some_and(|e| e == "gltf"));
    scenes.sort();
    Ok(scenes)
}

fn render(gpu: leakless::Gpu, scene: &Scene, settings: RenderSettings) -> anyhow::Result<(String, Vec<[f32; 3]>)> {
    let mut renderer = Renderer::new(gpu, scene, settings)?;
    let frame = renderer.render()?;
    renderer.gpu().check_validation()?;
    Ok((renderer.backend().name().to_string(), frame.radiance))
}

fn fixture_path(root: &Path, scene: &Scene) -> PathBuf {
    root.join(FIXTURES).join(format!("{}.exr", scene.name))
}

pub fn make_fixtures(root: &Path) -> anyhow::Result<()> {
    std::fs::create_dir_all(root.join(FIXTURES))?;
    for path in scenes(root)? {
        let scene = Scene::load(&path).with_context(|| format!("loading {}", path.display()))?;
        let (_, image) = render(super::open(true)?, &scene, settings(BackendChoice::Compute, 0))?;
        let (_, other) = render(super::open(true)?, &scene, settings(BackendChoice::Compute, 1))?;
        let noise = metrics::rel_mse(&other, &image, None, metrics::epsilon(&image)).unwrap_or(f64::NAN);
        let gpu = super::open(false)?;
        let attributes = [
            ("leakless.device", gpu.report().name.clone()),
            ("leakless.driver", gpu.report().driver.clone()),
            ("leakless.parameters", settings(BackendChoice::Compute, 0).describe()),
            (NOISE_ATTRIBUTE, format!("{noise:e}")),
        ];
        let out = fixture_path(root, &scene);
        exr::write(&out, SIZE.0, SIZE.1, &[ExrLayer { name: "", pixels: &image }], &attributes)?;
        println!("wrote {} (another seed's relMSE {noise:.4})", out.display());
    }
    Ok(())
}

pub fn run(report: &mut Report, root: &Path) -> anyhow::Result<()> {
    for path in scenes(root)? {
        let scene = Scene::load(&path).with_context(|| format!("loading {}", path.display()))?;
        let fixture_file = fixture_path(root, &scene);
        let fixture = exr::read(&fixture_file)
            .with_context(|| format!("reading {} (leakless gpu-report --make-fixtures)", fixture_file.display()))?;
        let channel = |c: &str| fixture.channel(c).map(<[f32]>::to_vec).context("the fixture has no R, G, B");
        let (r, g, b) = (channel("R")?, channel("G")?, channel("B")?);
        let reference: Vec<[f32; 3]> = (0..r.len()).map(|i| [r[i], g[i], b[i]]).collect();
        let noise: f64 = fixture.attribute(NOISE_ATTRIBUTE).and_then(|s| s.parse().ok()).unwrap_or(f64::NAN);
        let gpu = open_validated()?;
        report.validation |= gpu.capabilities().validation;
        let (backend, image) = render(gpu, &scene, settings(BackendChoice::Auto, 0))?;
        let check = compare(&scene.name, backend, &image, &reference, noise);
        println!("  {}: relMSE {:.2e} (another seed: {:.2e}), {}", check.scene, check.rel_mse, noise, check.verdict);
        report.correctness.push(check);
    }
    Ok(())
}

/// The device with validation, or without where the layer is present but cannot load (a packed
/// layer built for another C++ runtime): the report still runs, and says validation was off.
fn open_validated() -> leakless::Result<leakless::Gpu> {
    super::open(true).or_else(|e| {
        eprintln!("gpu-report: no device with validation ({e}); rendering without it");
        super::open(false)
    })
}

fn compare(scene: &str, backend: String, image: &[[f32; 3]], reference: &[[f32; 3]], noise: f64) -> Check {
    let non_finite = image.iter().flatten().filter(|c| !c.is_finite()).count();
    let rel_mse = metrics::rel_mse(image, reference, None, metrics::epsilon(reference)).unwrap_or(f64::NAN);
    let mean_ratio = metrics::mean_value(image) / metrics::mean_value(reference);
    let lit = image.iter().flatten().filter(|&&c| c != 0.0).count();
    let (passed, verdict) = if non_finite > 0 {
        (false, format!("{non_finite} NaN or infinite channels"))
    } else if metrics::mean_value(reference) == 0.0 {
        // The camera's room is sealed from every light: exactly black, or light leaked.
        match lit {
            0 => (true, "black, as on lavapipe".to_string()),
            n => (false, format!("{n} channels lit where lavapipe's image is black")),
        }
    } else if noise.is_nan() {
        (false, format!("the fixture has no {NOISE_ATTRIBUTE} (leakless gpu-report --make-fixtures)"))
    } else if rel_mse.is_nan() || rel_mse > MATCH_SHARE * noise {
        (false, format!("{:.0}% of another seed's error from lavapipe's image", 100.0 * rel_mse / noise))
    } else if mean_ratio.is_nan() || (mean_ratio - 1.0).abs() > 0.02 {
        (false, format!("mean off by {:+.1}%", 100.0 * (mean_ratio - 1.0)))
    } else if rel_mse == 0.0 {
        (true, "bit-identical".to_string())
    } else {
        (true, format!("matches ({:.1}% of another seed's error)", 100.0 * rel_mse / noise))
    };
    Check {
        scene: scene.to_string(),
        backend,
        rel_mse,
        other_seed_rel_mse: noise,
        mean_ratio,
        non_finite,
        passed,
        verdict,
    }
}
