//! `leakless render --sequence T0:T1:FPS`: the scene's animation as frames, rendered in order
//! by one renderer doing what the app does between frames (one photon batch a frame while
//! anything moves, accumulation while nothing does, temporal reuse unless `--reuse off`).

use std::path::Path;

use anyhow::{bail, Context};
use leakless::frame_budget::DynamicResolution;
use leakless::output::{self, OutputPaths};
use leakless::{RenderedFrame, Renderer};
use serde::Serialize;

/// `T0:T1:FPS`: frames k = 0 … round((T1 − T0)·FPS) at T0 + k/FPS.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sequence {
    pub start: f32,
    pub end: f32,
    pub fps: f32,
}

/// The most frames one sequence renders (an hour at 60 frames a second would be 216 000).
pub const MAX_FRAMES: u32 = 100_000;

impl Sequence {
    pub fn frame_count(&self) -> u32 {
        ((self.end - self.start) * self.fps).round() as u32 + 1
    }

    pub fn time(&self, k: u32) -> f32 {
        self.start + k as f32 / self.fps
    }
}

pub fn parse_sequence(s: &str) -> Result<Sequence, String> {
    let parts: Vec<&str> = s.split(':').collect();
    let [t0, t1, fps] = parts[..] else {
        return Err(format!("{s:?} is not T0:T1:FPS (start and end seconds, frames per second)"));
    };
    let num = |x: &str| x.trim().parse::<f32>().ok().filter(|v| v.is_finite());
    let (Some(start), Some(end), Some(fps)) = (num(t0), num(t1), num(fps)) else {
        return Err(format!("{s:?}: T0, T1 and FPS must be finite numbers"));
    };
    if end < start {
        return Err(format!("{s:?}: the end {end} s is before the start {start} s"));
    }
    if !(fps > 0.0 && fps <= 1000.0) {
        return Err(format!("{s:?}: FPS {fps} must be within (0, 1000]"));
    }
    let sequence = Sequence { start, end, fps };
    if (end - start) * fps > MAX_FRAMES as f32 {
        return Err(format!("{s:?}: more than {MAX_FRAMES} frames"));
    }
    Ok(sequence)
}

/// One frame's line of `sequence.json`.
#[derive(Serialize)]
struct FrameEntry {
    index: u32,
    time: f32,
    camera: CameraEntry,
    frame_ms: f64,
    /// The size the frame rendered at: `--size`, or less where dynamic resolution lowered it
    /// (the EXR is resampled to `--size`).
    render_size: [u32; 2],
    /// The photon methods: the frame's light paths and gather radius.
    #[serde(skip_serializing_if = "Option::is_none")]
    paths: Option<u32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    radius: Option<f32>,
    /// With `--frame-ms`, for a frame whose paths the budget chose: its target, its time as
    /// the budget measured it, and the next frame's paths.
    #[serde(skip_serializing_if = "Option::is_none")]
    budget: Option<leakless::renderer::BudgetReport>,
}

#[derive(Serialize)]
struct CameraEntry {
    eye: [f32; 3],
    forward: [f32; 3],
    up: [f32; 3],
    yfov_degrees: f32,
}

#[derive(Serialize)]
struct SequenceJson {
    scene: String,
    parameters: String,
    reuse: bool,
    fps: f32,
    frames: Vec<FrameEntry>,
}

/// Where a sequence goes: its frames and `sequence.json` into `dir` (made if missing), PNGs
/// beside the EXRs, the whole run's stats.
pub struct Outputs<'a> {
    pub dir: &'a Path,
    pub png: bool,
    pub stats: Option<&'a Path>,
}

/// Renders `sequence`; the renderer is set up for the view. With a frame budget, `dynamic`
/// lowers the render size as the budget advises, and each frame is resampled to the size the
/// renderer was set up with.
pub fn run(
    renderer: &mut Renderer,
    scene_path: &Path,
    sequence: Sequence,
    Outputs { dir, png, stats }: Outputs<'_>,
    mut dynamic: DynamicResolution,
) -> anyhow::Result<()> {
    let full = (renderer.settings().width, renderer.settings().height);
    if renderer.settings().frames > 1 {
        bail!("--frames {}: a sequence's frames are its times; drop --frames", renderer.settings().frames);
    }
    std::fs::create_dir_all(dir).with_context(|| format!("making {}", dir.display()))?;
    renderer.set_progressive(true);
    renderer.set_advance_seed(true);
    renderer.set_reuse_history_rate(sequence.fps as f64);
    let mut entries = Vec::new();
    let mut whole_run: Option<RenderedFrame> = None;
    let count = sequence.frame_count();
    for k in 0..count {
        let t = sequence.time(k);
        renderer.set_time(t)?;
        let frame = renderer.capture_frame().with_context(|| format!("rendering frame {k} at {t} s"))?;
        let render_size = [frame.width, frame.height];
        let frame = frame.resampled(full.0, full.1);
        let budget = renderer.last_report().and_then(|r| r.budget);
        // The first budgeted frame compiled the pipelines: its time says nothing of the size.
        let advice = budget.as_ref().filter(|b| !b.warm_up).map(|b| b.resolution_factor as f32);
        let paths = OutputPaths {
            exr: dir.join(format!("{k:04}.exr")),
            png: png.then(|| dir.join(format!("{k:04}.png"))),
            stats: None,
        };
        output::write_render(&paths, scene_path, renderer, &frame, None)?;
        let c = renderer.camera();
        entries.push(FrameEntry {
            index: k,
            time: t,
            camera: CameraEntry {
                eye: c.position().to_array(),
                forward: c.forward().to_array(),
                up: c.up().to_array(),
                yfov_degrees: c.yfov.to_degrees(),
            },
            frame_ms: frame.wall_ms,
            render_size,
            paths: frame.splat.as_ref().map(|s| s.paths),
            radius: frame.splat.as_ref().map(|s| s.radius),
            budget,
        });
        if advice.and_then(|factor| dynamic.follow(factor)).is_some() {
            let (w, h) = dynamic.size(full);
            renderer.set_size(w, h).with_context(|| format!("rendering at {w}x{h} (dynamic resolution)"))?;
        }
        // The stats are the last frame's, with the times of the whole run.
        whole_run = Some(match whole_run {
            None => frame,
            Some(mut run) => {
                run.add_times(&frame);
                RenderedFrame { timings: run.timings, gpu_span_ms: run.gpu_span_ms, wall_ms: run.wall_ms, ..frame }
            }
        });
    }
    // The parameters name the output's size, whatever the last frame rendered at.
    renderer.set_size(full.0, full.1)?;
    let json = SequenceJson {
        scene: scene_path.display().to_string(),
        parameters: renderer.settings().describe(),
        reuse: renderer.settings().reuse,
        fps: sequence.fps,
        frames: entries,
    };
    let path = dir.join("sequence.json");
    std::fs::write(&path, serde_json::to_string_pretty(&json)? + "\n")
        .with_context(|| format!("writing {}", path.display()))?;
    println!("wrote {count} frames and {}", path.display());
    if let (Some(stats), Some(run)) = (stats, &whole_run) {
        output::stats::write(stats, &output::stats::Stats::new(renderer, run, None))?;
        println!("wrote {}", stats.display());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sequence_spans_its_ends_at_its_rate() {
        let s = parse_sequence("0:2:30").unwrap();
        assert_eq!(s.frame_count(), 61);
        assert_eq!(s.time(60), 2.0);
        assert_eq!(parse_sequence("1.5:1.5:24").unwrap().frame_count(), 1);
        for bad in ["0:2", "2:1:30", "0:1:0", "0:1:-5", "a:1:30", "0:1:inf", "0:1e9:60"] {
            assert!(parse_sequence(bad).is_err(), "{bad}");
        }
    }
}
