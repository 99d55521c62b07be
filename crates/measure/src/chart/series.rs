//! `leakless chart --series`: error against wall time while an image accumulates — photon
//! frames for `leakless` and `splat`, jittered frames of samples for the built-in reference
//! path tracer, read at 1, 2, 4, … frames; frames of every method grow alike, 1, 2, 4 and then
//! `max_batches` batches of photons or samples (docs/architecture.md §1) — on the same axes, against a
//! ground truth that integrates the same pixel footprint (a jittered reference of many
//! frames). Errors: relMSE, RMSE and HDR-FLIP.

use std::path::Path;
use std::time::{Duration, Instant};

use leakless_device::Gpu;
use leakless_scene::Scene;

use super::flip;
use crate::csv_table::CsvTable;
use crate::flicker::{flicker, FLICKER_FRAMES};
use crate::metrics;
use leakless::error::Result;
use leakless::settings::MAX_FRAMES;
use leakless::trace::BackendChoice;
use leakless::{Method, RenderSettings, RenderedFrame, Renderer, SplatSettings};

/// What the series are measured with.
#[derive(Clone, Debug)]
pub struct SeriesConfig {
    pub width: u32,
    pub height: u32,
    pub backend: BackendChoice,
    /// Light paths per photon frame.
    pub paths: u32,
    /// First frame's gather radius (`None`: the photon count's, `SplatSettings::radius`).
    pub radius: Option<f32>,
    /// Photons a kernel where `radius` is `None`.
    pub kernel_photons: f32,
    /// The methods to run, of [`SERIES_METHODS`].
    pub methods: Vec<Method>,
    pub max_bounces: u32,
    pub seed: u32,
    /// Each series stops at the first checkpoint past this much wall time.
    pub budget: Duration,
    /// Runs of every series, the methods taking turns; each checkpoint keeps its fastest time
    /// (lavapipe's speed drifts by tens of percent over minutes, which one run would charge
    /// to whichever method ran then).
    pub repeats: u32,
    /// Ground truth: a reference of `truth_frames` jittered frames of `truth_spp` samples.
    pub truth_frames: u32,
    pub truth_spp: u32,
}

impl Default for SeriesConfig {
    fn default() -> Self {
        SeriesConfig {
            width: 160,
            height: 120,
            backend: BackendChoice::Auto,
            paths: 10_000,
            radius: None,
            kernel_photons: leakless::splatting::DEFAULT_KERNEL_PHOTONS,
            methods: SERIES_METHODS.to_vec(),
            max_bounces: 8,
            seed: 0,
            budget: Duration::from_secs(10),
            repeats: 1,
            // `chart --series`' defaults: 64 frames of 16 samples (--ref-spp 1024).
            truth_frames: 64,
            truth_spp: 16,
        }
    }
}

/// One checkpoint of one series.
#[derive(Clone, Debug)]
pub struct SeriesPoint {
    pub method: Method,
    /// Frames (photon methods) or samples per pixel (reference) in the image.
    pub frames: u32,
    /// Host wall time from the start of the accumulation to this image, not counting the
    /// error metrics computed at earlier checkpoints.
    pub wall_ms: f64,
    pub relmse: Option<f64>,
    /// The relMSE over the shaded pixels ([`SHADED_FRACTION`]).
    pub shaded_relmse: Option<f64>,
    pub rmse: Option<f64>,
    pub flip: f64,
    /// Flicker of the method's single frames ([`crate::flicker`]), the same on every row of a
    /// method; `None` for the reference.
    pub flicker: Option<f64>,
}

/// Every series of one scene.
#[derive(Clone, Debug)]
pub struct SceneSeries {
    pub scene: String,
    pub device: String,
    pub width: u32,
    pub height: u32,
    /// Light paths per photon batch, and the radius the photon methods' first frame gathers
    /// with (`None`: the one at which a kernel holds `kernel_photons`): a chart says which.
    pub paths: u32,
    pub radius: Option<f32>,
    pub kernel_photons: f32,
    pub truth_frames: u32,
    pub truth_spp: u32,
    pub truth_ms: f64,
    pub points: Vec<SeriesPoint>,
}

/// A method's errors at one wall time, read off its series.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ErrorAt {
    /// Frames (or spp) of the last checkpoint within the time.
    pub frames: u32,
    pub relmse: Option<f64>,
    pub shaded_relmse: Option<f64>,
    pub flip: f64,
}

impl SceneSeries {
    /// The first frame's radius as a chart says it.
    pub fn radius_label(&self) -> String {
        match self.radius {
            Some(r) => format!("radius {r:.4}"),
            None => format!("the radius of {} photons a kernel", self.kernel_photons),
        }
    }

    /// `method`'s errors at exactly `ms` of wall time: interpolated linearly in log error
    /// against log time between the last checkpoint within `ms` and the first after it.
    ///
    /// Why not the last checkpoint within `ms`: checkpoints double, so that one can stand at
    /// anywhere from half the time to all of it, and methods compared "at 10 s" got 5.2 s and
    /// 8.7 s. Error falls as a power of time, a straight line on log–log axes, so the line
    /// between the two checkpoints that bracket `ms` is the honest reading. `None` when the
    /// series does not reach `ms` or has no checkpoint within it.
    pub fn at(&self, method: Method, ms: f64) -> Option<ErrorAt> {
        let mut points = self.points.iter().filter(|p| p.method == method);
        let before = points.clone().rfind(|p| p.wall_ms <= ms)?;
        if before.wall_ms == ms {
            return Some(ErrorAt {
                frames: before.frames,
                relmse: before.relmse,
                shaded_relmse: before.shaded_relmse,
                flip: before.flip,
            });
        }
        let after = points.find(|p| p.wall_ms > ms)?;
        let f = (ms.ln() - before.wall_ms.ln()) / (after.wall_ms.ln() - before.wall_ms.ln());
        let lerp = |a: f64, b: f64| {
            if a > 0.0 && b > 0.0 {
                (a.ln() + f * (b.ln() - a.ln())).exp()
            } else {
                a + f * (b - a)
            }
        };
        Some(ErrorAt {
            frames: before.frames,
            relmse: before.relmse.zip(after.relmse).map(|(a, b)| lerp(a, b)),
            shaded_relmse: before.shaded_relmse.zip(after.shaded_relmse).map(|(a, b)| lerp(a, b)),
            flip: lerp(before.flip, after.flip),
        })
    }
}

/// The methods of the series, in plotting order.
pub const SERIES_METHODS: [Method; 3] = [Method::Splat, Method::LeakLess, Method::Reference];

/// Renders the ground truth, then each method's accumulation on a fresh device from `open`,
/// with images read back at 1, 2, 4, … frames until the budget is spent.
pub fn measure_series(
    open: &dyn Fn() -> Result<Gpu>,
    scene: &Scene,
    config: &SeriesConfig,
    progress: &mut dyn FnMut(&str),
) -> Result<SceneSeries> {
    let base = RenderSettings {
        width: config.width,
        height: config.height,
        backend: config.backend,
        max_bounces: config.max_bounces,
        seed: config.seed,
        splat: SplatSettings {
            paths: config.paths,
            radius: config.radius,
            kernel_photons: config.kernel_photons,
            ..Default::default()
        },
        ..Default::default()
    };
    progress(&format!("ground truth: {} frames × {} spp", config.truth_frames, config.truth_spp));
    let start = Instant::now();
    // Its own seed: sharing the series' samples would flatter the reference series.
    let truth_settings = RenderSettings {
        method: Method::Reference,
        spp: config.truth_spp,
        frames: config.truth_frames,
        max_batches: 1,
        seed: config.seed ^ 0x9e37_79b9,
        ..base.clone()
    };
    let mut renderer = Renderer::new(open()?, scene, truth_settings)?;
    let truth = renderer.render()?;
    let device = renderer.gpu().report().name.clone();
    renderer.gpu().check_validation()?;
    drop(renderer);
    let truth_ms = start.elapsed().as_secs_f64() * 1e3;
    let eps = metrics::epsilon(&truth.radiance);
    let lit: Vec<bool> = truth.radiance.iter().map(|p| *p != [0.0; 3]).collect();
    let shaded = metrics::dark_mask(&truth.radiance, Some(&lit), SHADED_FRACTION);
    let truth = Truth { image: &truth, eps, shaded: &shaded };

    let mut points: Vec<SeriesPoint> = Vec::new();
    for repeat in 0..config.repeats.max(1) {
        for &method in &config.methods {
            progress(&format!("{} (run {} of {})", method.name(), repeat + 1, config.repeats.max(1)));
            let run = measure_method(open, scene, &base, method, config, &truth)?;
            merge_run(&mut points, run);
        }
    }
    Ok(SceneSeries {
        scene: scene.name.clone(),
        device,
        width: config.width,
        height: config.height,
        paths: config.paths,
        radius: config.radius,
        kernel_photons: config.kernel_photons,
        truth_frames: config.truth_frames,
        truth_spp: config.truth_spp,
        truth_ms,
        points,
    })
}

/// Adds one run of a method's series to `points`: the same frames (fixed seeds) as an earlier
/// run, so only the time can differ, and each checkpoint keeps the faster one; a faster run may
/// reach one checkpoint more (each run ends at the first past the budget), which is added.
fn merge_run(points: &mut Vec<SeriesPoint>, run: Vec<SeriesPoint>) {
    let Some(method) = run.first().map(|p| p.method) else { return };
    let mine: Vec<&mut SeriesPoint> = points.iter_mut().filter(|p| p.method == method).collect();
    let known = mine.len();
    for (kept, again) in mine.into_iter().zip(&run) {
        debug_assert_eq!(kept.frames, again.frames);
        kept.wall_ms = kept.wall_ms.min(again.wall_ms);
    }
    points.extend(run.into_iter().skip(known));
    // Each method's checkpoints together, in plotting order.
    points.sort_by_key(|p| (SERIES_METHODS.iter().position(|m| *m == p.method), p.frames));
}

/// One run of `method`'s series: the warm-up, its flicker (photon methods), then frames
/// read back at 1, 2, 4, … until the budget is spent.
fn measure_method(
    open: &dyn Fn() -> Result<Gpu>,
    scene: &Scene,
    base: &RenderSettings,
    method: Method,
    config: &SeriesConfig,
    truth: &Truth,
) -> Result<Vec<SeriesPoint>> {
    // Warm-up: pipelines compiled, node lists sized, before the clock starts. Photon methods
    // warm up on three accumulated frames: their second holds the accumulation's largest
    // radius, whose lists would otherwise grow, and restart the image, on the clock.
    let spp = 1;
    let mut settings = RenderSettings { method, spp, ..base.clone() };
    let warm_up = RenderSettings { frames: if method.splats() { 3 } else { 1 }, ..settings.clone() };
    let mut renderer = Renderer::new(open()?, scene, warm_up)?;
    renderer.render()?;
    let flicker = if method.splats() { Some(flicker(&mut renderer, FLICKER_FRAMES)?) } else { None };
    // Frames without end: each photon frame further along the sequence with a smaller
    // radius; each reference frame more jittered samples (1, 2, 4, then 8).
    settings.frames = MAX_FRAMES;
    renderer.set_settings(settings)?;
    renderer.set_advance_seed(false);
    let start = Instant::now();
    let mut excluded = Duration::ZERO;
    let mut checkpoint = 1u32;
    let mut points = Vec::new();
    for n in 1..=MAX_FRAMES {
        if n < checkpoint {
            renderer.render_frame(None)?;
            continue;
        }
        let frame = renderer.capture_frame()?;
        let wall_ms = (start.elapsed() - excluded).as_secs_f64() * 1e3;
        let measuring = Instant::now();
        // The reference's frames grow in batches of `spp` samples: its count is samples.
        // (The renderer's own count: a restart could never mislabel a checkpoint.)
        let count = if method == Method::Reference { frame.batches.saturating_mul(spp) } else { frame.accumulated };
        points.push(point(method, count, wall_ms, &frame, truth, flicker));
        excluded += measuring.elapsed();
        if wall_ms >= config.budget.as_secs_f64() * 1e3 {
            break;
        }
        checkpoint *= 2;
    }
    renderer.gpu().check_validation()?;
    Ok(points)
}

/// The shaded pixels, whose errors the series also reports: lit in the ground truth, at most this
/// share of its mean radiance (a scene's aisles and the undersides of its galleries, where a
/// path tracer is noisiest and photons are fewest).
pub const SHADED_FRACTION: f64 = 0.3;

/// The ground truth and what the errors against it need.
struct Truth<'a> {
    image: &'a RenderedFrame,
    eps: f64,
    shaded: &'a [bool],
}

fn point(
    method: Method,
    frames: u32,
    wall_ms: f64,
    frame: &RenderedFrame,
    truth: &Truth,
    flicker: Option<f64>,
) -> SeriesPoint {
    let reference = &truth.image.radiance;
    SeriesPoint {
        method,
        frames,
        wall_ms,
        relmse: metrics::rel_mse(&frame.radiance, reference, None, truth.eps),
        shaded_relmse: metrics::rel_mse(&frame.radiance, reference, Some(truth.shaded), truth.eps),
        rmse: metrics::rmse(&frame.radiance, reference, None),
        flip: flip::hdr_flip(&frame.radiance, reference, frame.width, frame.height),
        flicker,
    }
}

/// The columns of [`write_series_csv`].
pub const SERIES_COLUMNS: [&str; 9] =
    ["scene", "method", "frames_or_spp", "wall_ms", "relmse", "relmse_shaded", "rmse", "hdr_flip", "flicker"];

pub fn write_series_csv(series: &SceneSeries, path: &Path) -> Result<()> {
    let mut table = CsvTable::new(&SERIES_COLUMNS);
    let float = |v: Option<f64>| v.filter(|v| v.is_finite()).map(|v| format!("{v:.6e}")).unwrap_or_default();
    for p in &series.points {
        let fields = [
            series.scene.clone(),
            p.method.name().to_string(),
            p.frames.to_string(),
            format!("{:.3}", p.wall_ms),
            float(p.relmse),
            float(p.shaded_relmse),
            float(p.rmse),
            float(Some(p.flip)),
            float(p.flicker),
        ];
        table.row(fields)?;
    }
    table.write(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(frames: u32, wall_ms: f64, error: f64) -> SeriesPoint {
        SeriesPoint {
            method: Method::LeakLess,
            frames,
            wall_ms,
            relmse: Some(error),
            shaded_relmse: None,
            rmse: None,
            flip: error,
            flicker: None,
        }
    }

    fn series(points: Vec<SeriesPoint>) -> SceneSeries {
        SceneSeries {
            scene: "s".into(),
            device: "d".into(),
            width: 1,
            height: 1,
            paths: 1,
            radius: Some(1.0),
            kernel_photons: 32.0,
            truth_frames: 1,
            truth_spp: 1,
            truth_ms: 0.0,
            points,
        }
    }

    #[test]
    fn runs_merge_to_each_checkpoints_fastest_time_and_keep_a_checkpoint_only_one_reached() {
        let mut points = vec![point(1, 100.0, 0.2), point(2, 300.0, 0.1), point(4, 11_000.0, 0.05)];
        points.push(SeriesPoint { method: Method::Splat, ..point(1, 50.0, 0.3) });
        merge_run(
            &mut points,
            vec![point(1, 120.0, 0.2), point(2, 250.0, 0.1), point(4, 9_000.0, 0.05), point(8, 12_000.0, 0.02)],
        );
        let times: Vec<(Method, u32, f64)> = points.iter().map(|p| (p.method, p.frames, p.wall_ms)).collect();
        assert_eq!(
            times,
            [
                (Method::Splat, 1, 50.0),
                (Method::LeakLess, 1, 100.0),
                (Method::LeakLess, 2, 250.0),
                (Method::LeakLess, 4, 9_000.0),
                (Method::LeakLess, 8, 12_000.0),
            ]
        );
        // Still past a 10 s budget, so the series can be read at 10 s.
        assert!(series(points).at(Method::LeakLess, 10_000.0).is_some());
    }

    #[test]
    fn the_error_at_a_time_lies_on_the_power_law_through_its_bracketing_checkpoints() {
        // error = 0.1 · (t / 1000 ms)^-1: 0.1 at 1 s, 0.025 at 4 s; at 2 s the power law gives 0.05,
        // which neither checkpoint (0.1 nor 0.025) nor a straight line in linear axes
        // (0.075) would.
        let s = series(vec![point(1, 500.0, 0.2), point(2, 1000.0, 0.1), point(8, 4000.0, 0.025)]);
        let at = s.at(Method::LeakLess, 2000.0).expect("bracketed");
        assert_eq!(at.frames, 2);
        assert!((at.flip - 0.05).abs() < 1e-12, "{at:?}");
        assert!((at.relmse.expect("relmse") - 0.05).abs() < 1e-12);
        // On a checkpoint, the last one included: its own value.
        assert_eq!(
            s.at(Method::LeakLess, 1000.0),
            Some(ErrorAt { frames: 2, relmse: Some(0.1), shaded_relmse: None, flip: 0.1 })
        );
        assert_eq!(s.at(Method::LeakLess, 4000.0).map(|e| e.frames), Some(8));
        // Outside the series, or another method: nothing.
        assert_eq!(s.at(Method::LeakLess, 4000.5), None);
        assert_eq!(s.at(Method::LeakLess, 400.0), None);
        assert_eq!(s.at(Method::Splat, 2000.0), None);
    }
}
