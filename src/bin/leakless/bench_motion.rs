//! `leakless bench motion`: what temporal reuse does to moving frames. Per scene, its
//! animation (or, where it has none, an orbit of its camera) rendered frame by frame as the
//! app renders it, with reuse on and off, each frame against the path tracer's image of the
//! same time and view.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::Context;
use leakless::metrics;
use leakless::{BackendChoice, Method, RenderSettings, Renderer, Scene, SplatSettings};
use leakless_scene::Camera;

use crate::measure::chart::flip;

/// What the bench renders.
pub struct MotionBench {
    pub scenes: Vec<PathBuf>,
    pub size: (u32, u32),
    pub paths: u32,
    pub frames: u32,
    pub fps: f32,
    /// Samples per pixel of each frame's reference.
    pub spp: u32,
    pub backend: BackendChoice,
    /// Each frame's errors, as CSV (`scene,reuse,frame,time,relmse,flip`): the error against
    /// frame index.
    pub csv: Option<PathBuf>,
}

/// One run's figures: means over the displayed frames.
struct Figures {
    relmse: f64,
    flip: f64,
    flicker: f64,
    frame_ms: f64,
    /// The frames' mean radiance over their references' (lag shows as a bias).
    mean_ratio: f64,
}

/// Frame `k`'s view: the scene at time k/fps, or its camera turned about the point it looks at.
fn place(r: &mut Renderer, scene: &Scene, k: u32, bench: &MotionBench, start: &Camera) -> anyhow::Result<()> {
    if scene.is_animated() {
        r.set_time(k as f32 / bench.fps)?;
        return Ok(());
    }
    // 0.1 rad a second about a pivot at the distance of the scene's centre.
    let pivot_distance = (scene.bounds().center() - start.position()).length().max(1e-3);
    let pivot = start.position() + pivot_distance * start.forward();
    let angle = 0.1 * k as f32 / bench.fps;
    let eye = pivot + glam::Quat::from_rotation_y(angle) * (start.position() - pivot);
    let camera = Camera::look_at(eye, pivot, start.up(), start.yfov, start).context("orbit camera")?;
    r.set_camera(camera);
    Ok(())
}

pub fn run(bench: &MotionBench) -> anyhow::Result<()> {
    let (w, h) = bench.size;
    println!(
        "bench motion ({w}x{h}, leakless, {} paths a frame, {} frames at {} fps; references {} spp): means over the frames",
        bench.paths, bench.frames, bench.fps, bench.spp
    );
    println!("flicker: mean |ΔY| between successive frames over mean Y, from frame {}", settle(bench));
    println!(
        "{:<22} {:>10} {:>10} {:>9} {:>10}   {:>10} {:>10} {:>10} {:>10}",
        "scene", "relMSE on", "relMSE off", "FLIP on", "FLIP off", "flicker on", "flicker off", "ms on", "ms off"
    );
    let mut csv = String::from("scene,reuse,frame,time,relmse,flip\n");
    for path in &bench.scenes {
        let scene = Scene::load(path).with_context(|| format!("loading {}", path.display()))?;
        let settings = |method, reuse| RenderSettings {
            width: w,
            height: h,
            backend: bench.backend,
            method,
            spp: bench.spp,
            reuse,
            splat: SplatSettings { paths: bench.paths, ..Default::default() },
            ..Default::default()
        };
        let open = || crate::open_gpu(bench.backend);
        let mut reference = Renderer::new(open()?, &scene, settings(Method::Reference, false))?;
        let start = reference.camera().clone();
        let mut references = Vec::new();
        for k in 0..bench.frames {
            place(&mut reference, &scene, k, bench, &start)?;
            references.push(reference.render()?.radiance);
        }
        reference.gpu().check_validation()?;
        drop(reference);
        let mut figures = Vec::new();
        for reuse in [true, false] {
            let mut r = Renderer::new(open()?, &scene, settings(Method::LeakLess, reuse))?;
            r.set_progressive(true);
            r.set_advance_seed(true);
            r.set_reuse_history_frames((0.5 * bench.fps).round().max(1.0) as u32);
            let (mut relmse, mut flip_sum, mut ms, mut ratio) = (0.0, 0.0, 0.0, 0.0);
            let (mut change, mut counted, mut last): (f64, u32, Option<Vec<f64>>) = (0.0, 0, None);
            for (k, truth) in (0..bench.frames).zip(&references) {
                place(&mut r, &scene, k, bench, &start)?;
                let t = Instant::now();
                let frame = r.capture_frame()?;
                ms += t.elapsed().as_secs_f64() * 1e3;
                let eps = metrics::epsilon(truth);
                let (e, f) = (
                    metrics::rel_mse(&frame.radiance, truth, None, eps).unwrap_or(0.0),
                    flip::hdr_flip(&frame.radiance, truth, w, h),
                );
                relmse += e;
                flip_sum += f;
                let reuse = if reuse { "on" } else { "off" };
                csv += &format!("{},{reuse},{k},{},{e},{f}\n", path.display(), k as f32 / bench.fps);
                ratio += metrics::mean_value(&frame.radiance) / metrics::mean_value(truth).max(1e-30);
                let y: Vec<f64> = frame.radiance.iter().map(leakless::flicker::luminance).collect();
                if let Some(prev) = &last {
                    let mean = y.iter().sum::<f64>() / y.len() as f64;
                    if k >= settle(bench) && mean > 0.0 {
                        change += y.iter().zip(prev).map(|(a, b)| (a - b).abs()).sum::<f64>() / y.len() as f64 / mean;
                        counted += 1;
                    }
                }
                last = Some(y);
            }
            r.gpu().check_validation()?;
            let n = bench.frames as f64;
            figures.push(Figures {
                relmse: relmse / n,
                flip: flip_sum / n,
                flicker: change / counted.max(1) as f64,
                frame_ms: ms / n,
                mean_ratio: ratio / n,
            });
        }
        let (on, off) = (&figures[0], &figures[1]);
        let name = path.file_name().map_or(String::new(), |n| n.to_string_lossy().into_owned());
        println!(
            "{:<22} {:>10.5} {:>10.5} {:>9.4} {:>10.4}   {:>10.4} {:>11.4} {:>10.1} {:>10.1}",
            name, on.relmse, off.relmse, on.flip, off.flip, on.flicker, off.flicker, on.frame_ms, off.frame_ms
        );
        println!(
            "{:<22} on/off: relMSE {:.2}×, FLIP {:.2}×, flicker {:.2}×, frame time {:.2}×; mean / reference: on {:.3}, off {:.3}",
            "",
            on.relmse / off.relmse,
            on.flip / off.flip,
            on.flicker / off.flicker.max(1e-12),
            on.frame_ms / off.frame_ms,
            on.mean_ratio,
            off.mean_ratio
        );
    }
    if let Some(path) = &bench.csv {
        std::fs::write(path, csv).with_context(|| format!("writing {}", path.display()))?;
        println!("wrote {}", path.display());
    }
    Ok(())
}

/// The first frame the flicker counts: after half a second.
fn settle(bench: &MotionBench) -> u32 {
    (0.5 * bench.fps).round() as u32
}
