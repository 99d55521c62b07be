//! The report's correctness section: every shipped scene rendered with validation on, against
//! the same render made on lavapipe's compute backend (`tests/fixtures/gpu-report/`, made by
//! `leakless gpu-report --make-fixtures`). Another device traces the same photons up to
//! floating-point rounding, so a correct render is much closer to the fixture than a render of
//! another seed is: that seed's error is kept in the fixture as the yardstick, and a render
//! matches within half of it.

use std::path::{Path, PathBuf};

use anyhow::Context;
use serde::Serialize;

use leakless::output::exr::{self, ExrLayer};
use leakless::{BackendChoice, Method, RenderSettings, Renderer, Scene, SplatSettings};
use leakless_measure::metrics;

use super::Report;

const FIXTURES: &str = "tests/fixtures/gpu-report";
const SIZE: (u32, u32) = (64, 48);
const PATHS: u32 = 10_000;
/// A render matches when its relMSE against the fixture is at most this share of another
/// seed's: the same photons, up to rounding that sends some paths elsewhere.
const MATCH_SHARE: f64 = 0.5;
/// The share of pixels left out of the relMSE (the worst ones): where a primary ray grazes an
/// edge between two surfaces, rounding on another device can put the pixel on the other
/// surface, a whole pixel's difference that relMSE at 64×48 weighs like noise everywhere
/// (the cornell box's block edges on an H200). 0.5% is 15 pixels: a leak or a wrong pass
/// changes far more.
const EDGE_SHARE: f64 = 0.005;
/// The attribute holding another seed's relMSE against the fixture.
const NOISE_ATTRIBUTE: &str = "leakless.other_seed_relmse";

/// One scene's check.
#[derive(Serialize)]
pub struct Check {
    pub scene: String,
    pub backend: String,
    /// relMSE against the fixture (ε = 1% of its squared mean) without the worst
    /// [`EDGE_SHARE`] of the pixels.
    pub rel_mse: f64,
    /// relMSE over every pixel.
    pub rel_mse_all: f64,
    /// Pixels more than 5% (and 1% of the mean) off the fixture's.
    pub pixels_off: usize,
    /// relMSE of another seed's render against the fixture, on the fixture's device.
    pub other_seed_rel_mse: f64,
    /// Mean of the render over the fixture's.
    pub mean_ratio: f64,
    pub non_finite: usize,
    pub passed: bool,
    pub verdict: String,
}

/// At the scene's fixed radius: the fixtures compare devices, not the probe that chooses the
/// count's radius (which a device's rounding may move by a hair).
fn settings(scene: &Scene, backend: BackendChoice, seed: u32) -> RenderSettings {
    RenderSettings {
        width: SIZE.0,
        height: SIZE.1,
        backend,
        method: Method::LeakLess,
        seed,
        splat: SplatSettings {
            paths: PATHS,
            radius: Some(leakless::splatting::auto_radius(scene)),
            ..Default::default()
        },
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
        let (_, image) = render(super::open(true)?, &scene, settings(&scene, BackendChoice::Compute, 0))?;
        let (_, other) = render(super::open(true)?, &scene, settings(&scene, BackendChoice::Compute, 1))?;
        let noise = metrics::rel_mse(&other, &image, None, metrics::epsilon(&image)).unwrap_or(f64::NAN);
        let gpu = super::open(false)?;
        let attributes = [
            ("leakless.device", gpu.report().name.clone()),
            ("leakless.driver", gpu.report().driver.clone()),
            ("leakless.parameters", settings(&scene, BackendChoice::Compute, 0).describe()),
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
        let (backend, image) = render(gpu, &scene, settings(&scene, BackendChoice::Auto, 0))?;
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
    let eps = metrics::epsilon(reference);
    let rel_mse_all = metrics::rel_mse(image, reference, None, eps).unwrap_or(f64::NAN);
    let rel_mse =
        metrics::rel_mse(image, reference, Some(&without_worst(image, reference, eps)), eps).unwrap_or(f64::NAN);
    let pixels_off = pixels_off(image, reference);
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
        rel_mse_all,
        pixels_off,
        other_seed_rel_mse: noise,
        mean_ratio,
        non_finite,
        passed,
        verdict,
    }
}

/// Every pixel but the [`EDGE_SHARE`] with the largest relative squared error.
fn without_worst(image: &[[f32; 3]], reference: &[[f32; 3]], eps: f64) -> Vec<bool> {
    let error = |i: usize| -> f64 {
        (0..3).map(|c| metrics::rel_squared_error(image[i][c] as f64, reference[i][c] as f64, eps)).sum()
    };
    let mut order: Vec<usize> = (0..image.len()).collect();
    order.sort_by(|&a, &b| error(b).total_cmp(&error(a)));
    let mut keep = vec![true; image.len()];
    let dropped = (EDGE_SHARE * image.len() as f64).floor() as usize;
    for &i in &order[..dropped.min(order.len())] {
        keep[i] = false;
    }
    keep
}

/// Pixels whose luminance is more than 5% off the fixture's (and more than 1% of its mean).
fn pixels_off(image: &[[f32; 3]], reference: &[[f32; 3]]) -> usize {
    let floor = 0.01 * metrics::mean_value(reference);
    let y = |p: &[f32; 3]| (p[0] as f64 + p[1] as f64 + p[2] as f64) / 3.0;
    image.iter().zip(reference).filter(|(a, b)| (y(a) - y(b)).abs() > 0.05 * y(b) + floor).count()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_edge_pixel_on_another_surface_still_matches_but_a_lit_patch_does_not() {
        // A smooth image of 64×48, and another seed's error as the fixture's yardstick.
        let reference: Vec<[f32; 3]> = (0..64 * 48).map(|i| [0.2 + 0.001 * (i % 64) as f32; 3]).collect();
        let noise = 0.15;
        let mut edge = reference.clone();
        edge[100] = [0.0; 3];
        edge[200] = [3.0; 3];
        let check = compare("edge", "compute".into(), &edge, &reference, noise);
        assert!(check.passed, "{}", check.verdict);
        assert!(check.rel_mse_all > 0.0 && check.rel_mse == 0.0 && check.pixels_off == 2);
        let mut patch = reference.clone();
        for p in &mut patch[..64 * 6] {
            *p = [1.0; 3];
        }
        let check = compare("patch", "compute".into(), &patch, &reference, noise);
        assert!(!check.passed, "{}", check.verdict);
    }
}
