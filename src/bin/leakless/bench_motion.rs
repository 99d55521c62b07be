//! `leakless bench motion`: what temporal reuse does to moving frames. Per scene, its
//! animation (or, where it has none, an orbit of its camera) rendered frame by frame as the
//! app renders it, with reuse on, on without its spatial filter, and off, each frame against
//! the path tracer's image of the same time and view.

use std::path::PathBuf;

use anyhow::Context;
use leakless::{BackendChoice, Method, RenderSettings, Renderer, Scene, SplatSettings};
use leakless_measure::metrics;
use leakless_scene::Camera;

use leakless_measure::chart::flip;
use leakless_measure::chart::motion_plot::{plot_motion, MotionRun};
use leakless_measure::csv_table::CsvTable;
use leakless_measure::motion::{ScreenFlicker, SeenFrame, SurfaceFlicker, BAND_PIXELS, DARK};

mod sequence;
use sequence::{Judge, Sequence};

/// What the bench renders (`leakless bench motion`'s options). Its CSV holds each frame's
/// errors (`scene,reuse,frame,time,relmse,flip,relmse_less_noise`), its chart them against the
/// frame index.
#[derive(clap::Args)]
pub struct MotionBench {
    /// The scenes (.gltf or .glb).
    #[arg(required = true)]
    pub scenes: Vec<PathBuf>,
    #[arg(long, default_value = "256x144", value_parser = crate::parse_size)]
    pub size: (u32, u32),
    #[arg(long, default_value_t = 10_000)]
    pub paths: u32,
    /// Frames rendered, from time 0.
    #[arg(long, default_value_t = 24, value_parser = clap::value_parser!(u32).range(2..=10_000))]
    pub frames: u32,
    /// Frames per second of the animation's clock.
    #[arg(long, default_value_t = 30.0)]
    pub fps: f32,
    /// Samples per pixel of each frame's reference, in two halves of two seeds (an odd count is rounded up).
    #[arg(long, default_value_t = 64, value_parser = clap::value_parser!(u32).range(1..=65_536))]
    pub spp: u32,
    /// Also judge each scene's last frame against one reference of this many samples per
    /// pixel (0: none): a near-truth, for scenes whose per-frame references are noisier than
    /// the frames they judge.
    #[arg(long, default_value_t = 0, value_parser = clap::value_parser!(u32).range(0..=65_536))]
    pub truth_spp: u32,
    /// Trace backend.
    #[arg(long, default_value = "auto")]
    pub backend: BackendChoice,
    /// Also render each scene with reuse on under a frame budget, beside a second fixed run
    /// (reuse on, --paths a frame; a frame of each in turn) whose mean frame time so far is the
    /// budget's target, so that the two compare at equal mean time on the same moments of the
    /// machine: the budget moves the paths from costly frames to cheap ones.
    #[arg(long)]
    pub budgeted: bool,
    #[command(flatten)]
    pub out: crate::options::FigureFiles,
    #[command(flatten)]
    pub fixed: crate::options::FixedRadius,
}

/// One run's figures: means over the displayed frames.
struct Figures {
    relmse: f64,
    /// relMSE less the references' own noise (`metrics::rel_mse_without_reference_noise`).
    relmse_less_noise: f64,
    flip: f64,
    flicker: f64,
    frame_ms: f64,
    /// The mean without the first frame (which compiles the pipelines).
    steady_ms: f64,
    /// The frames' mean radiance over their references' (lag shows as a bias).
    mean_ratio: f64,
    /// Flicker on the surfaces (`SurfaceFlicker`).
    surface_flicker: f64,
    /// The dark band's mean over the reference's (light carried into shadow shows above 1), and
    /// its pixels over the frames.
    band: Option<f64>,
    band_pixels: usize,
    /// The last frame's relMSE and HDR-FLIP against the near-truth.
    against_truth: Option<(f64, f64)>,
    /// Each frame's light paths.
    paths: Vec<u32>,
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
    if !(bench.fps > 0.0 && bench.fps <= 1000.0) {
        anyhow::bail!("--fps {} must be within (0, 1000]", bench.fps);
    }
    let (w, h) = bench.size;
    // Each frame's reference is the mean of two halves of its samples (below).
    let half_spp = bench.spp.div_ceil(2);
    println!(
        "bench motion ({w}x{h}, leakless, {} paths a frame, {} frames at {} fps; references 2 x {half_spp} spp): means over the frames",
        bench.paths, bench.frames, bench.fps
    );
    println!(
        "flicker: mean |ΔY| between successive frames over mean Y, from frame {}: the moving view's change counts too",
        settle(bench)
    );
    println!(
        "surface flicker: the same, each pixel against its surface point in the frame before (0 for a perfect image of still light)"
    );
    println!(
        "dark band: pixels under {DARK} of a reference half's mean within {BAND_PIXELS} pixels of one above it; its mean over the other half's there"
    );
    println!(
        "{:<22} {:>10} {:>10} {:>9} {:>10}   {:>10} {:>10} {:>10} {:>10}",
        "scene", "relMSE on", "relMSE off", "FLIP on", "FLIP off", "flicker on", "flicker off", "ms on", "ms off"
    );
    let mut csv =
        CsvTable::new(&["scene", "reuse", "frame", "time", "relmse", "flip", "relmse_less_noise", "paths", "ms"]);
    let (mut runs, mut device) = (Vec::new(), String::new());
    for path in &bench.scenes {
        let scene = Scene::load(path).with_context(|| format!("loading {}", path.display()))?;
        let name = path.file_name().map_or(String::new(), |n| n.to_string_lossy().into_owned());
        let settings = |method, reuse, seed| RenderSettings {
            width: w,
            height: h,
            backend: bench.backend,
            method,
            spp: half_spp,
            reuse,
            seed,
            splat: SplatSettings { paths: bench.paths, radius: bench.fixed.radius(&scene), ..Default::default() },
            ..Default::default()
        };
        let open = || crate::open_gpu(bench.backend);
        // Each frame's reference is the mean of two halves of its samples, of two seeds: the
        // halves' difference is the reference's own noise, which every error against it
        // includes, and their product removes it (`metrics::rel_mse_without_reference_noise`).
        let mut halves: [Vec<Vec<[f32; 3]>>; 2] = [Vec::new(), Vec::new()];
        // Each frame's surfaces and camera, for the references' surface flicker.
        let (mut start, mut views) = (None, Vec::new());
        for (seed, half) in halves.iter_mut().enumerate() {
            let mut reference = Renderer::new(open()?, &scene, settings(Method::Reference, false, seed as u32))?;
            let start = start.get_or_insert_with(|| reference.camera().clone()).clone();
            device.clone_from(&reference.gpu().report().name);
            for k in 0..bench.frames {
                place(&mut reference, &scene, k, bench, &start)?;
                let frame = reference.render()?;
                if seed == 0 {
                    views.push((frame.surface.clone(), reference.view_proj(), reference.camera().position()));
                }
                half.push(frame.radiance);
            }
            reference.gpu().check_validation()?;
        }
        let start = start.expect("two halves rendered");
        let references: Vec<Vec<[f32; 3]>> = halves[0]
            .iter()
            .zip(&halves[1])
            .map(|(a, b)| a.iter().zip(b).map(|(a, b)| std::array::from_fn(|c| 0.5 * (a[c] + b[c]))).collect())
            .collect();
        let mut reference_change = ScreenFlicker::new(settle(bench));
        let mut reference_surface_change = SurfaceFlicker::new(settle(bench));
        let mut noise = (0.0, 0.0);
        for (k, (truth, (surface, view_proj, camera))) in (0..bench.frames).zip(references.iter().zip(&views)) {
            reference_change.add(k, truth);
            let (view_proj, camera, width, height) = (*view_proj, *camera, w, h);
            reference_surface_change.add(k, SeenFrame { image: truth, surface, view_proj, camera, width, height });
            let (a, b) = (&halves[0][k as usize], &halves[1][k as usize]);
            noise.0 += metrics::reference_noise(a, b, w as usize, metrics::epsilon(truth)).unwrap_or(0.0);
            noise.1 += flip::hdr_flip(a, b, w, h);
        }
        let reference_noise = (noise.0 / bench.frames as f64, noise.1 / bench.frames as f64);
        let last = bench.frames - 1;
        let near_truth = if bench.truth_spp > 0 {
            let settings = RenderSettings { spp: bench.truth_spp, ..settings(Method::Reference, false, 2) };
            let mut reference = Renderer::new(open()?, &scene, settings)?;
            place(&mut reference, &scene, last, bench, &start)?;
            let image = reference.render()?.radiance;
            reference.gpu().check_validation()?;
            Some(image)
        } else {
            None
        };
        let judge = Judge {
            bench,
            scene: &scene,
            path,
            start: &start,
            references: &references,
            halves: &halves,
            near_truth: near_truth.as_ref(),
        };
        let renderer = |reuse: bool, filter: bool| -> anyhow::Result<Renderer> {
            let mut r = Renderer::new(open()?, &scene, settings(Method::LeakLess, reuse, 0))?;
            r.set_spatial_reuse(filter);
            r.set_progressive(true);
            r.set_advance_seed(true);
            r.set_reuse_history_rate(bench.fps as f64);
            Ok(r)
        };
        let mut figures: Vec<Figures> = Vec::new();
        // Reuse on, on without its spatial filter (the same photons: what the filter alone
        // does), and off.
        for (reuse, filter, label) in [(true, true, "on"), (true, false, "on-unfiltered"), (false, true, "off")] {
            let mut sequence = Sequence::new(renderer(reuse, filter)?, label, bench);
            for k in 0..bench.frames {
                sequence.frame(k, &judge, &mut csv)?;
            }
            let (f, errors) = sequence.finish()?;
            figures.push(f);
            if filter {
                runs.push(MotionRun { scene: name.clone(), reuse, errors });
            }
        }
        // `--budgeted`: reuse on within the mean frame time of a fixed run (reuse on, --paths a
        // frame) rendered beside it, a frame of each in turn, its target that run's mean so far
        // (after its first frame; before, the first run's): the two meet the machine's speed,
        // which drifts between runs here, at the same moments, and compare at equal time.
        if bench.budgeted {
            let mut fixed = Sequence::new(renderer(true, true)?, "on-beside-budgeted", bench);
            let mut budgeted = renderer(true, true)?;
            budgeted.set_frame_budget(Some(figures[0].steady_ms))?;
            let mut budgeted = Sequence::new(budgeted, "on-budgeted", bench);
            for k in 0..bench.frames {
                fixed.frame(k, &judge, &mut csv)?;
                if let Some(target) = fixed.steady_ms() {
                    budgeted.renderer.set_frame_budget_target(target)?;
                }
                budgeted.frame(k, &judge, &mut csv)?;
            }
            figures.push(fixed.finish()?.0);
            figures.push(budgeted.finish()?.0);
        }
        let (on, unfiltered, off) = (&figures[0], &figures[1], &figures[2]);
        println!(
            "{:<22} {:>10.5} {:>10.5} {:>9.4} {:>10.4}   {:>10.4} {:>11.4} {:>10.1} {:>10.1}",
            name, on.relmse, off.relmse, on.flip, off.flip, on.flicker, off.flicker, on.frame_ms, off.frame_ms
        );
        println!(
            "{:<22} on/off: relMSE {:.2}×, FLIP {:.2}×, flicker {:.2}×, surface flicker {:.4}/{:.4} = {:.2}×, frame time {:.2}×; mean / reference: on {:.3}, off {:.3}",
            "",
            on.relmse / off.relmse,
            on.flip / off.flip,
            on.flicker / off.flicker.max(1e-12),
            on.surface_flicker,
            off.surface_flicker,
            on.surface_flicker / off.surface_flicker.max(1e-12),
            on.frame_ms / off.frame_ms,
            on.mean_ratio,
            off.mean_ratio
        );
        println!(
            "{:<22} relMSE less the references' noise: on {:.5}, off {:.5}, on/off {:.2}×",
            "",
            on.relmse_less_noise,
            off.relmse_less_noise,
            on.relmse_less_noise / off.relmse_less_noise
        );
        let band = |f: &Figures| f.band.map_or("-".into(), |b| format!("{b:.3}"));
        println!(
            "{:<22} without the spatial filter: relMSE {:.5}, FLIP {:.4}, flicker {:.4}, surface flicker {:.4}; dark band ({} pixels over the frames) / reference: on {}, on unfiltered {}, off {}",
            "",
            unfiltered.relmse,
            unfiltered.flip,
            unfiltered.flicker,
            unfiltered.surface_flicker,
            on.band_pixels,
            band(on),
            band(unfiltered),
            band(off),
        );
        if let (Some(t_on), Some(t_off)) = (on.against_truth, off.against_truth) {
            println!(
                "{:<22} frame {last} against {} spp: relMSE on {:.5}, off {:.5} ({:.2}×); FLIP on {:.4}, off {:.4} ({:.2}×)",
                "",
                bench.truth_spp,
                t_on.0,
                t_off.0,
                t_on.0 / t_off.0,
                t_on.1,
                t_off.1,
                t_on.1 / t_off.1
            );
        }
        println!(
            "{:<22} references' own: flicker {:.4}, surface flicker {:.4}; noise (from the halves of two seeds, each frame): relMSE {:.5}; FLIP between the halves {:.4}",
            "",
            reference_change.mean(),
            reference_surface_change.mean(),
            reference_noise.0,
            reference_noise.1,
        );
        // A moving view's or light's own change counts as flicker by this measure, so an image
        // that follows it flickers about as much as a perfect one: the references' ratio to the
        // baseline is about the lowest a correct image reaches (a little above it: their noise
        // adds change of its own).
        println!(
            "{:<22} references' flicker / the baseline's: {:.2}× (the view's and light's own change, with the references' noise)",
            "",
            reference_change.mean() / off.flicker.max(1e-12),
        );
        // What reuse is judged by: the flicker beyond what a correct image has.
        let screen = Excess::of(on.flicker, off.flicker, reference_change.mean());
        let surface = Excess::of(on.surface_flicker, off.surface_flicker, reference_surface_change.mean());
        println!(
            "{:<22} flicker in excess of the references': on {:.4}, off {:.4} ({:.2}×); surface flicker: on {:.4}, off {:.4} ({:.2}×)",
            "", screen.on, screen.off, screen.ratio, surface.on, surface.off, surface.ratio,
        );
        if let (Some(fixed), Some(budgeted)) = (figures.get(3), figures.get(4)) {
            let excess = Excess::of(budgeted.flicker, off.flicker, reference_change.mean());
            let fixed_excess = Excess::of(fixed.flicker, off.flicker, reference_change.mean());
            let mut paths = budgeted.paths.clone();
            paths.sort_unstable();
            println!(
                "{:<22} budgeted beside a fixed run (reuse on, {} paths, a frame of each in turn), to its mean after its first frame, {:.1} ms: mean {:.1} ms ({:.2}×), paths {}–{} (median {}); relMSE less the references' noise {:.5} against {:.5} ({:.2}×); flicker in excess of the references' {:.4} against {:.4} ({:.2}× and {:.2}× off's)",
                "",
                bench.paths,
                fixed.steady_ms,
                budgeted.steady_ms,
                budgeted.steady_ms / fixed.steady_ms,
                paths[0],
                paths[paths.len() - 1],
                paths[paths.len() / 2],
                budgeted.relmse_less_noise,
                fixed.relmse_less_noise,
                budgeted.relmse_less_noise / fixed.relmse_less_noise,
                excess.on,
                fixed_excess.on,
                excess.ratio,
                fixed_excess.ratio,
            );
        }
    }
    if let Some(path) = &bench.out.csv {
        csv.write(path)?;
        println!("wrote {}", path.display());
    }
    if let Some(svg) = &bench.out.chart {
        let png = svg.with_extension("png");
        let caption = format!(
            "{} · leakless {w}×{h}, {} paths a frame, {} fps, history {} frames; references 2 × {half_spp} spp · `leakless bench motion`",
            device,
            bench.paths,
            bench.fps,
            (0.5 * bench.fps).round().max(1.0),
        );
        plot_motion(&runs, &caption, svg, &png).with_context(|| format!("writing {}", svg.display()))?;
        println!("wrote {} and {}", svg.display(), png.display());
    }
    Ok(())
}

/// Flicker beyond the references' own (the view's and the light's change, which a correct image
/// has too), with reuse on and off, and on's over off's. Negative where an image changes less
/// than the references (which have noise of their own); the ratio is 0 where off has no excess.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Excess {
    on: f64,
    off: f64,
    ratio: f64,
}

impl Excess {
    fn of(on: f64, off: f64, reference: f64) -> Excess {
        let (on, off) = (on - reference, off - reference);
        Excess { on, off, ratio: if off > 0.0 { on / off } else { 0.0 } }
    }
}

/// The first frame the flicker counts: after half a second.
fn settle(bench: &MotionBench) -> u32 {
    (0.5 * bench.fps).round() as u32
}

/// What `SurfaceFlicker` needs of a frame the renderer `r` just rendered.
fn seen<'a>(r: &Renderer, frame: &'a leakless::RenderedFrame) -> SeenFrame<'a> {
    SeenFrame {
        image: &frame.radiance,
        surface: &frame.surface,
        view_proj: r.view_proj(),
        camera: r.camera().position(),
        width: frame.width,
        height: frame.height,
    }
}

#[cfg(test)]
mod tests {
    use super::Excess;

    #[test]
    fn excess_flicker_is_measured_from_the_references_own() {
        // The doorway walk of stop 48: references 0.0268, reuse on 0.0264, off 0.0322. Raw, on is
        // 0.82× off; beyond what a correct image changes, on has none left.
        let e = Excess::of(0.0264, 0.0322, 0.0268);
        assert!((e.on - -0.0004).abs() < 1e-12 && (e.off - 0.0054).abs() < 1e-12, "{e:?}");
        assert!(e.ratio < 0.0, "{e:?}");
        // The Cornell orbit: on 0.0090, off 0.0109, references 0.0056: 0.83× raw, 0.64× in excess.
        let e = Excess::of(0.0090, 0.0109, 0.0056);
        assert!((e.ratio - 0.0034 / 0.0053).abs() < 1e-9, "{e:?}");
        assert_eq!(Excess::of(0.02, 0.01, 0.02).ratio, 0.0, "off with no excess");
    }
}
