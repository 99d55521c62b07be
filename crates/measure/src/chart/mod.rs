//! `leakless chart`: speed against accuracy. Each method is rendered at several (paths, radius)
//! settings on each trace backend, timed, and compared with the path-traced reference; the
//! points go to a CSV and to log–log charts of error against frame time.
//!
//! The CLI and the tests drive the same three steps: [`measure_with_progress`] one scene, then [`write_csv`]
//! and [`plot::plot`] (or [`write_outputs`] for all of a scene's files).

pub mod drawing;
pub mod flip;
pub mod motion_plot;
pub mod plot;
pub mod scale_plot;
pub mod series;
pub mod series_plot;
pub mod thickness;

use std::path::{Path, PathBuf};

use leakless_device::{DeviceType, Gpu};
use leakless_scene::Scene;

use leakless::error::{RenderError, Result};

use crate::csv_table::CsvTable;
use crate::metrics;
use leakless::splatting::SplatStats;
use leakless::trace::{Backend, BackendChoice};
use leakless::{Method, RenderSettings, Renderer, SplatSettings};

pub use metrics::Errors;

/// The methods charted by default: those of docs/architecture.md §2 that this build knows.
pub fn default_methods() -> Vec<Method> {
    vec![Method::Splat, Method::LeakLessCapped, Method::LeakLess]
}

/// A radius as the renderer takes it: fixed (scene units), or `None` and photons a kernel.
pub type RadiusChoice = (Option<f32>, f32);

/// The gather radii to chart.
#[derive(Clone, Debug, PartialEq)]
pub enum Radii {
    /// Multiples of the scene's automatic radius (5% of its bounding-sphere radius).
    Auto(Vec<f32>),
    /// Radii in scene units.
    Absolute(Vec<f32>),
    /// The radius at which a kernel holds this many photons (`--kernel-photons`): the
    /// renderer's own, following the photon count.
    KernelPhotons(Vec<f32>),
}

impl Radii {
    /// The values given, radii or photon counts.
    fn values(&self) -> &[f32] {
        match self {
            Radii::Auto(v) | Radii::Absolute(v) | Radii::KernelPhotons(v) => v,
        }
    }

    /// Each setting as the renderer takes it, given the scene's automatic radius: a fixed
    /// radius in scene units, or `None` and photons a kernel.
    pub fn resolve(&self, auto: f32) -> Vec<RadiusChoice> {
        let k = leakless::splatting::DEFAULT_KERNEL_PHOTONS;
        match self {
            Radii::Auto(scales) => scales.iter().map(|s| (Some(s * auto), k)).collect(),
            Radii::Absolute(r) => r.iter().map(|&r| (Some(r), k)).collect(),
            Radii::KernelPhotons(ks) => ks.iter().map(|&k| (None, k)).collect(),
        }
    }
}

/// What to measure on each scene.
#[derive(Clone, Debug)]
pub struct ChartConfig {
    pub width: u32,
    pub height: u32,
    /// Samples per pixel of the reference.
    pub ref_spp: u32,
    /// Indirect bounces, the same for the reference and the methods.
    pub max_bounces: u32,
    pub seed: u32,
    pub methods: Vec<Method>,
    /// Light paths per frame.
    pub paths: Vec<u32>,
    pub radii: Radii,
    /// Trace backends; empty = every backend the device has (ray queries first).
    pub backends: Vec<Backend>,
    /// Timed frames after the warm-up frame; the fastest counts (1: the second frame).
    pub repeats: u32,
    /// Dark pixels: reference indirect light at most this fraction of its mean
    /// ([`metrics::dark_mask`]).
    pub dark_fraction: f64,
}

impl Default for ChartConfig {
    fn default() -> Self {
        ChartConfig {
            width: 160,
            height: 120,
            ref_spp: 1024,
            max_bounces: RenderSettings::default().max_bounces,
            seed: 0,
            methods: default_methods(),
            paths: vec![5_000, 20_000, 80_000],
            radii: Radii::Auto(vec![0.5, 1.0, 2.0]),
            backends: vec![],
            repeats: 1,
            dark_fraction: metrics::DARK_FRACTION,
        }
    }
}

impl ChartConfig {
    pub fn validate(&self) -> Result<()> {
        let bad = |m: &str| Err(RenderError::Settings(m.to_string()));
        if self.methods.is_empty() {
            return bad("no method to chart");
        }
        if self.methods.contains(&Method::Reference) {
            return bad("the reference is what the chart compares with, not a method to chart");
        }
        if self.ref_spp == 0 || self.ref_spp > leakless::settings::MAX_SPP {
            return Err(RenderError::Settings(format!(
                "--ref-spp {} must be within 1..={}",
                self.ref_spp,
                leakless::settings::MAX_SPP
            )));
        }
        if !(self.dark_fraction.is_finite() && self.dark_fraction >= 0.0) {
            return bad("--dark-fraction must be a number ≥ 0");
        }
        if !(1..=100).contains(&self.repeats) {
            return bad("--repeats must be within 1..=100");
        }
        if self.paths.is_empty() || self.paths.contains(&0) {
            return bad("--paths needs at least one count, each at least 1");
        }
        let radii = self.radii.values();
        if radii.is_empty() || radii.iter().any(|r| !(r.is_finite() && *r > 0.0)) {
            return match self.radii {
                Radii::KernelPhotons(_) => bad("--kernel-photons needs at least one count, each a positive number"),
                _ => bad("--radius needs at least one radius, each a positive number"),
            };
        }
        // The reference's and the methods' own limits.
        RenderSettings {
            width: self.width,
            height: self.height,
            spp: self.ref_spp,
            max_bounces: self.max_bounces,
            ..Default::default()
        }
        .validate()
    }

    /// Renders per scene on `backends`: the reference, then each method at each setting.
    pub fn renders_per_scene(&self, backends: usize) -> usize {
        let settings = self.paths.len() * self.radii.values().len();
        1 + backends * self.methods.iter().map(|m| if m.splats() { settings } else { 1 }).sum::<usize>()
    }
}

/// The backends a device offers, ray queries first.
pub fn available_backends(gpu: &Gpu) -> Vec<Backend> {
    if gpu.capabilities().ray_query {
        vec![Backend::RayQuery, Backend::Compute]
    } else {
        vec![Backend::Compute]
    }
}

/// One measured (method, backend, paths, radius).
#[derive(Clone, Debug)]
pub struct Point {
    pub scene: String,
    pub method: Method,
    pub backend: Backend,
    /// Light paths and gather radius (scene units); `None` for methods that do not splat.
    pub paths: Option<u32>,
    pub radius: Option<f32>,
    /// Photons a kernel was asked to hold, where the radius followed the photon count.
    pub kernel_photons: Option<f32>,
    /// Photons a kernel took on average (the gather's count).
    pub photons_per_kernel: Option<f64>,
    /// Sum of the per-pass wall times of the second frame (the fastest of frames 2 to
    /// `repeats + 1`), each pass submitted and waited for alone (on a CPU device such as
    /// lavapipe: CPU time).
    pub frame_ms: f64,
    pub errors: Errors,
    pub photons: Option<u32>,
    pub candidate_tests: Option<u64>,
    /// Share of the indirect energy removed as leaked ([`leaked_fraction`]).
    pub leaked_fraction: Option<f64>,
}

/// Everything measured on one scene.
#[derive(Clone, Debug)]
pub struct SceneChart {
    pub scene: String,
    pub device: String,
    /// A CPU device (lavapipe): frame times are CPU times.
    pub cpu_device: bool,
    pub width: u32,
    pub height: u32,
    pub ref_spp: u32,
    /// Host wall time of the reference render.
    pub reference_ms: f64,
    /// Mean of the reference's final radiance over every pixel and channel (0: black, and
    /// relative errors are undefined).
    pub reference_mean: f64,
    /// 5% of the scene's bounding radius, the unit of [`Radii::Auto`].
    pub auto_radius: f32,
    /// Pixels with a surface, and the dark ones among them ([`metrics::dark_mask`] with
    /// `dark_fraction`).
    pub covered_pixels: usize,
    pub dark_fraction: f64,
    pub dark_pixels: usize,
    pub points: Vec<Point>,
}

/// Where [`measure`] is.
#[derive(Clone, Debug)]
pub struct Progress {
    /// Renders finished, of `total` ([`ChartConfig::renders_per_scene`]).
    pub done: usize,
    pub total: usize,
    /// What runs now, e.g. `reference 256/1024 spp` or `leakless compute 20000 paths r=0.05`.
    pub message: String,
}

/// Renders the reference once, then every method at every (paths, radius) on every backend,
/// each on a fresh device from `open(ray_tracing)`: the second frame of each renderer is timed
/// (the first compiles pipelines and sizes the node lists; with `repeats` > 1 the fastest of
/// the frames after it), every pass submitted and timed on its own, and its final radiance
/// compared with the reference's.
pub fn measure_with_progress(
    open: &dyn Fn(bool) -> Result<Gpu>,
    scene: &Scene,
    config: &ChartConfig,
    progress: &mut dyn FnMut(&Progress),
) -> Result<SceneChart> {
    config.validate()?;
    let first = open(true)?;
    let available = available_backends(&first);
    let backends = if config.backends.is_empty() { available.clone() } else { config.backends.clone() };
    if let Some(b) = backends.iter().find(|b| !available.contains(b)) {
        return Err(RenderError::Settings(format!(
            "backend {}: {} has no VK_KHR_ray_query (use --backends compute)",
            b.name(),
            first.report().name
        )));
    }
    let device = first.report().name.clone();
    let cpu_device = first.report().device_type == DeviceType::Cpu;
    let total = config.renders_per_scene(backends.len());
    let mut done = 0;
    let mut report = |done: usize, message: String| progress(&Progress { done, total, message });

    // The reference, on the first backend (both give the same image).
    report(done, format!("reference 0/{} spp", config.ref_spp));
    let settings = RenderSettings {
        width: config.width,
        height: config.height,
        backend: choice(backends[0]),
        method: Method::Reference,
        spp: config.ref_spp,
        max_bounces: config.max_bounces,
        seed: config.seed,
        ..Default::default()
    };
    let start = std::time::Instant::now();
    let gpu = if backends[0] == Backend::RayQuery { first } else { open(false)? };
    let mut renderer = Renderer::new(gpu, scene, settings)?;
    renderer.set_timing(renderer.tuning().timing);
    let reference = renderer
        .render_with_progress(&mut |spp, total_spp| report(done, format!("reference {spp}/{total_spp} spp")))?;
    renderer.gpu().check_validation()?;
    let covered: Vec<bool> = renderer.capture()?.position.iter().map(|p| p[3] > 0.0).collect();
    let reference_ms = start.elapsed().as_secs_f64() * 1e3;
    drop(renderer);
    let dark = metrics::dark_mask(&reference.indirect, Some(&covered), config.dark_fraction);
    done += 1;

    let auto_radius = leakless::splatting::auto_radius(scene);
    let radii = config.radii.resolve(auto_radius);
    let mut points = Vec::new();
    for &backend in &backends {
        for &method in &config.methods {
            let settings: Vec<(Option<u32>, Option<RadiusChoice>)> = if method.splats() {
                config.paths.iter().flat_map(|&p| radii.iter().map(move |&r| (Some(p), Some(r)))).collect()
            } else {
                vec![(None, None)]
            };
            for (paths, radius_choice) in settings {
                let mut what = format!("{} {}", method.name(), backend.name());
                match (paths, radius_choice) {
                    (Some(p), Some((Some(r), _))) => what += &format!(" {p} paths r={r:.4}"),
                    (Some(p), Some((None, k))) => what += &format!(" {p} paths K={k}"),
                    _ => {}
                }
                let (radius, kernel_photons) =
                    radius_choice.map_or((None, None), |(r, k)| (r, r.is_none().then_some(k)));
                report(done, what);
                let render = RenderSettings {
                    width: config.width,
                    height: config.height,
                    backend: choice(backend),
                    method,
                    max_bounces: config.max_bounces,
                    seed: config.seed,
                    splat: SplatSettings {
                        paths: paths.unwrap_or(SplatSettings::default().paths),
                        radius,
                        kernel_photons: kernel_photons.unwrap_or(leakless::splatting::DEFAULT_KERNEL_PHOTONS),
                        ..Default::default()
                    },
                    ..Default::default()
                };
                let opener = || open(backend == Backend::RayQuery);
                let measured = crate::bench::Measured::best_of(&opener, scene, method.name(), &render, config.repeats)?;
                let (frame, frame_ms) = (&measured.frame, measured.frame_ms());
                let stats = frame.splat.as_ref();
                points.push(Point {
                    scene: scene.name.clone(),
                    method,
                    backend,
                    paths,
                    radius: stats.map(|s| s.radius).or(radius),
                    kernel_photons,
                    photons_per_kernel: stats.map(|s| s.photons_per_kernel),
                    frame_ms,
                    errors: metrics::errors(&frame.radiance, &reference.radiance, &dark),
                    photons: stats.map(|s| s.photons_stored),
                    candidate_tests: stats.map(|s| s.candidate_tests),
                    leaked_fraction: stats.and_then(leaked_fraction),
                });
                done += 1;
            }
        }
    }
    report(done, "done".into());
    Ok(SceneChart {
        scene: scene.name.clone(),
        device,
        cpu_device,
        width: config.width,
        height: config.height,
        ref_spp: config.ref_spp,
        reference_ms,
        reference_mean: metrics::mean_value(&reference.radiance),
        auto_radius,
        covered_pixels: covered.iter().filter(|c| **c).count(),
        dark_fraction: config.dark_fraction,
        dark_pixels: dark.iter().filter(|d| **d).count(),
        points,
    })
}

fn choice(backend: Backend) -> BackendChoice {
    match backend {
        Backend::RayQuery => BackendChoice::RayQuery,
        Backend::Compute => BackendChoice::Compute,
    }
}

/// The share of the indirect energy the visibility tests removed as leaked, for the methods
/// that trace them (`leaked_energy_fraction`: leaked / (leaked + kept), luminance over the
/// image); `None` for the others.
pub fn leaked_fraction(stats: &SplatStats) -> Option<f64> {
    (stats.visibility_tests > 0).then_some(stats.leaked_energy_fraction)
}

/// The columns of [`write_csv`], in order.
pub const CSV_COLUMNS: [&str; 15] = [
    "scene",
    "method",
    "backend",
    "paths",
    "radius",
    "frame_ms",
    "relmse",
    "rmse",
    "relmse_dark",
    "rmse_dark",
    "photons",
    "candidate_tests",
    "leaked_fraction",
    "kernel_photons",
    "photons_per_kernel",
];

/// One row per point, columns [`CSV_COLUMNS`]; what a point lacks is left empty.
pub fn write_csv(points: &[Point], path: &Path) -> Result<()> {
    let mut table = CsvTable::new(&CSV_COLUMNS);
    let opt = |v: Option<String>| v.unwrap_or_default();
    let float = |v: f64| if v.is_finite() { format!("{v:.6e}") } else { String::new() };
    for p in points {
        let fields = [
            p.scene.clone(),
            p.method.name().to_string(),
            p.backend.name().to_string(),
            opt(p.paths.map(|v| v.to_string())),
            opt(p.radius.map(|v| format!("{v}"))),
            format!("{:.3}", p.frame_ms),
            opt(p.errors.relmse.map(float)),
            opt(p.errors.rmse.map(float)),
            opt(p.errors.relmse_dark.map(float)),
            opt(p.errors.rmse_dark.map(float)),
            opt(p.photons.map(|v| v.to_string())),
            opt(p.candidate_tests.map(|v| v.to_string())),
            opt(p.leaked_fraction.map(float)),
            opt(p.kernel_photons.map(|v| format!("{v}"))),
            opt(p.photons_per_kernel.map(|v| format!("{v:.2}"))),
        ];
        table.row(fields)?;
    }
    table.write(path)
}

/// A scene name as a file-name part: letters, digits, `-`, `_` and `.` kept, the rest `-`.
pub fn file_stem(scene: &str) -> String {
    let s: String =
        scene.chars().map(|c| if c.is_ascii_alphanumeric() || "-_.".contains(c) { c } else { '-' }).collect();
    if s.is_empty() {
        "scene".into()
    } else {
        s
    }
}

/// Writes `PREFIX-<scene>.csv` and, for each metric of [`plot::Metric::ALL`],
/// `PREFIX-<scene>-<metric>.svg` and `.png` of `size` pixels; returns the paths written.
pub fn write_outputs(chart: &SceneChart, prefix: &Path, size: (u32, u32)) -> Result<Vec<PathBuf>> {
    let base = format!("{}-{}", prefix.display(), file_stem(&chart.scene));
    if let Some(dir) = Path::new(&base).parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .map_err(|e| RenderError::Output { path: dir.display().to_string(), message: e.to_string() })?;
    }
    let csv = PathBuf::from(format!("{base}.csv"));
    write_csv(&chart.points, &csv)?;
    let mut written = vec![csv];
    for metric in plot::Metric::ALL {
        let svg = PathBuf::from(format!("{base}-{}.svg", metric.file_suffix()));
        let png = svg.with_extension("png");
        plot::plot(chart, metric, &svg, &png, size)?;
        written.extend([svg, png]);
    }
    Ok(written)
}

#[cfg(test)]
mod tests;
