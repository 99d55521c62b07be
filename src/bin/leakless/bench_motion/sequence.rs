//! One sequence of `bench motion`: a renderer's frames, each judged against its references as
//! it is rendered, and the run's figures from them. Sequences are stepped a frame at a time, so
//! that two can be rendered side by side (`--budgeted`: a budget held to the mean of a fixed
//! run that shares the machine's moments with it).

use std::path::Path;
use std::time::Instant;

use leakless::Renderer;
use leakless_measure::chart::flip;
use leakless_measure::csv_table::CsvTable;
use leakless_measure::metrics;
use leakless_measure::motion::{DarkBand, ScreenFlicker, SurfaceFlicker};
use leakless_scene::{Camera, Scene};

use super::{place, seen, settle, Figures, MotionBench};

/// What every sequence of one scene is judged against.
pub(super) struct Judge<'a> {
    pub bench: &'a MotionBench,
    pub scene: &'a Scene,
    pub path: &'a Path,
    pub start: &'a Camera,
    /// Each frame's reference: the mean of its two halves, of two seeds.
    pub references: &'a [Vec<[f32; 3]>],
    pub halves: &'a [Vec<Vec<[f32; 3]>>; 2],
    /// The last frame's near-truth (`--truth-spp`).
    pub near_truth: Option<&'a Vec<[f32; 3]>>,
}

pub(super) struct Sequence {
    pub renderer: Renderer,
    /// The CSV's `reuse` column.
    label: &'static str,
    ms: f64,
    first_ms: f64,
    ratio: f64,
    less_noise: f64,
    band: DarkBand,
    errors: Vec<(f64, f64)>,
    against_truth: Option<(f64, f64)>,
    paths: Vec<u32>,
    change: ScreenFlicker,
    surface_change: SurfaceFlicker,
    frames: u32,
}

impl Sequence {
    pub fn new(renderer: Renderer, label: &'static str, bench: &MotionBench) -> Sequence {
        Sequence {
            renderer,
            label,
            ms: 0.0,
            first_ms: 0.0,
            ratio: 0.0,
            less_noise: 0.0,
            band: DarkBand::default(),
            errors: Vec::new(),
            against_truth: None,
            paths: Vec::new(),
            change: ScreenFlicker::new(settle(bench)),
            surface_change: SurfaceFlicker::new(settle(bench)),
            frames: 0,
        }
    }

    /// Renders frame `k` (the frames come in order from 0) and judges it; its errors go to `csv`.
    pub fn frame(&mut self, k: u32, judge: &Judge, csv: &mut CsvTable) -> anyhow::Result<()> {
        let bench = judge.bench;
        let r = &mut self.renderer;
        place(r, judge.scene, k, bench, judge.start)?;
        let t = Instant::now();
        let frame = r.capture_frame()?;
        let ms = t.elapsed().as_secs_f64() * 1e3;
        self.ms += ms;
        if k == 0 {
            self.first_ms = self.ms;
        }
        self.frames += 1;
        let paths = frame.splat.as_ref().map_or(0, |s| s.paths);
        self.paths.push(paths);
        let (w, h) = bench.size;
        let truth = &judge.references[k as usize];
        let eps = metrics::epsilon(truth);
        let (e, f) = (
            metrics::rel_mse(&frame.radiance, truth, None, eps).unwrap_or(0.0),
            flip::hdr_flip(&frame.radiance, truth, w, h),
        );
        self.errors.push((e, f));
        let (a, b) = (&judge.halves[0][k as usize], &judge.halves[1][k as usize]);
        let clean = metrics::rel_mse_without_reference_noise(&frame.radiance, a, b, w as usize, eps).unwrap_or(0.0);
        self.less_noise += clean;
        let time = k as f32 / bench.fps;
        let fields = [judge.path.display().to_string(), self.label.into(), k.to_string(), time.to_string()];
        let judged = [e, f, clean].map(|v| v.to_string());
        csv.row(fields.into_iter().chain(judged).chain([paths.to_string(), format!("{ms:.2}")]))?;
        self.ratio += metrics::mean_value(&frame.radiance) / metrics::mean_value(truth).max(1e-30);
        self.change.add(k, &frame.radiance);
        self.surface_change.add(k, seen(r, &frame));
        self.band.add(&frame.radiance, a, b, w, h);
        if let Some(truth) = judge.near_truth.filter(|_| k == bench.frames - 1) {
            self.against_truth = Some((
                metrics::rel_mse(&frame.radiance, truth, None, metrics::epsilon(truth)).unwrap_or(0.0),
                flip::hdr_flip(&frame.radiance, truth, w, h),
            ));
        }
        Ok(())
    }

    /// The mean frame time so far without the first frame (which compiles the pipelines).
    pub fn steady_ms(&self) -> Option<f64> {
        (self.frames > 1).then(|| (self.ms - self.first_ms) / (self.frames - 1) as f64)
    }

    /// The run's figures, and each frame's relMSE and HDR-FLIP (for the chart).
    pub fn finish(self) -> anyhow::Result<(Figures, Vec<(f64, f64)>)> {
        self.renderer.gpu().check_validation()?;
        let n = self.frames.max(1) as f64;
        let figures = Figures {
            relmse: self.errors.iter().map(|e| e.0).sum::<f64>() / n,
            relmse_less_noise: self.less_noise / n,
            flip: self.errors.iter().map(|e| e.1).sum::<f64>() / n,
            flicker: self.change.mean(),
            surface_flicker: self.surface_change.mean(),
            frame_ms: self.ms / n,
            steady_ms: self.steady_ms().unwrap_or(self.ms),
            mean_ratio: self.ratio / n,
            band: self.band.ratio(),
            band_pixels: self.band.pixels(),
            against_truth: self.against_truth,
            paths: self.paths,
        };
        Ok((figures, self.errors))
    }
}
