//! `--stats FILE.json`: what the frame cost and what it counted.

use std::path::Path;

use serde::Serialize;

use crate::error::{RenderError, Result};
use crate::{RenderedFrame, Renderer};

#[derive(Clone, Debug, Serialize)]
pub struct PassTime {
    pub pass: String,
    /// GPU timestamp difference around the pass.
    pub gpu_ms: f64,
    /// Host time of the pass's own submission (`--timing per-pass` only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub wall_ms: Option<f64>,
}

/// What building the trace structures cost.
#[derive(Clone, Debug, Serialize)]
pub struct TraceBuild {
    pub backend: String,
    pub build_ms: f64,
    pub bytes: u64,
    pub detail: String,
}

/// One frame's pass times and their sum.
#[derive(Clone, Debug, Serialize)]
pub struct FrameTimes {
    pub gpu_ms: f64,
    pub passes: Vec<PassTime>,
}

impl FrameTimes {
    fn of(timings: &[leakless_graph::PassTiming]) -> FrameTimes {
        FrameTimes { gpu_ms: timings.iter().map(|t| t.ms).sum(), passes: pass_times(timings) }
    }
}

fn pass_times(timings: &[leakless_graph::PassTiming]) -> Vec<PassTime> {
    timings.iter().map(|t| PassTime { pass: t.name.clone(), gpu_ms: t.ms, wall_ms: t.wall_ms }).collect()
}

#[derive(Clone, Debug, Serialize)]
pub struct Stats {
    pub scene: String,
    pub device: String,
    pub driver: String,
    pub backend: String,
    /// Why that backend (`auto`'s choice, or the flag that forced it).
    pub backend_why: String,
    /// What the renderer tuned to the device.
    pub tuning: crate::tuning::DeviceTuning,
    pub method: String,
    pub parameters: String,
    pub width: u32,
    pub height: u32,
    pub triangles: usize,
    /// Punctual lights.
    pub lights: usize,
    /// Emissive triangles (area lights).
    pub emitters: usize,
    pub trace_build: TraceBuild,
    /// Photon counts, for methods that splat.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub splat: Option<crate::splatting::SplatStats>,
    /// Each pass's time summed over the frames of the render (`accumulated` of them).
    pub passes: Vec<PassTime>,
    /// The last frame's own: what `splat` counted took this long.
    pub last_frame: FrameTimes,
    /// What the frame budget measured and chose for the last frame, where it chose its paths.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub frame_budget: Option<crate::renderer::BudgetReport>,
    /// The passes' GPU times summed.
    pub frame_gpu_ms: f64,
    /// The frames' GPU time from first pass start to last pass end (`tuning.timing` =
    /// timestamps: the frame's time on the device).
    pub frame_gpu_span_ms: f64,
    /// Host wall-clock time of the whole render (submission to completion).
    pub frame_wall_ms: f64,
    /// Reference samples (or photon frames) in the image.
    pub accumulated: u32,
    /// Photon batches (of `paths` paths) in the image: frames grow while accumulating.
    pub batches: u32,
    /// The seed of the image's photons.
    pub seed: u32,
    /// Seconds on the scene's animation clock.
    pub time: f32,
    /// Animated instances in the scene (each its own BLAS and top-level instance).
    pub instances: usize,
    /// Host milliseconds of the last instance update (transforms, world-space vertices, the
    /// compute backend's top level); the GPU's part is in `passes` (`instance vertices`,
    /// `tlas rebuild`) in the frame that follows a change.
    pub instance_update_ms: f64,
    /// The `leakless render` command that renders this image again (captures).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub command: Option<String>,
}

impl Stats {
    pub fn new(renderer: &Renderer, frame: &RenderedFrame, command: Option<String>) -> Stats {
        let t = renderer.trace_stats();
        let settings = renderer.settings();
        let (scene, device) = (renderer.scene(), renderer.gpu().report());
        Stats {
            scene: scene.name.clone(),
            device: device.name.clone(),
            driver: device.driver.clone(),
            backend: renderer.backend().name().into(),
            backend_why: renderer.backend_why().into(),
            tuning: renderer.tuning().clone(),
            method: settings.method.name().into(),
            parameters: settings.describe(),
            width: frame.width,
            height: frame.height,
            triangles: scene.triangle_count(),
            lights: scene.lights.len(),
            emitters: renderer.emitter_count(),
            trace_build: TraceBuild {
                backend: t.backend.name().into(),
                build_ms: t.build_ms,
                bytes: t.bytes,
                detail: t.detail.clone(),
            },
            splat: frame.splat.clone(),
            frame_budget: renderer.last_report().and_then(|r| r.budget),
            frame_gpu_ms: frame.timings.iter().map(|t| t.ms).sum(),
            frame_gpu_span_ms: frame.gpu_span_ms,
            frame_wall_ms: frame.wall_ms,
            accumulated: frame.accumulated,
            batches: frame.batches,
            seed: frame.seed,
            time: renderer.time(),
            instances: scene.instances.len(),
            instance_update_ms: renderer.pose_update_ms(),
            command,
            passes: pass_times(&frame.timings),
            last_frame: FrameTimes::of(&frame.last_frame_timings),
        }
    }
}

pub fn write(path: &Path, stats: &Stats) -> Result<()> {
    let json = serde_json::to_string_pretty(stats).expect("stats serialise");
    std::fs::write(path, json + "\n")
        .map_err(|e| RenderError::Output { path: path.display().to_string(), message: e.to_string() })
}
