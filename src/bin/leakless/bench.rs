//! `leakless bench`: ratios measured in one process, printed, never asserted.

use leakless::passes::names::group;
use leakless::passes::photon_clearance::PHOTON_CLEARANCE;
use leakless_measure::bench::{self, Measured};
use std::path::PathBuf;

use anyhow::Context;
use leakless::settings::MAX_FRAMES;
use leakless::{Backend, BackendChoice, Scene};

#[derive(clap::Subcommand)]
pub enum BenchCommand {
    /// Occlusion and closest-hit rays per second, coherent and incoherent, on every backend.
    Rays {
        /// The scene (.gltf or .glb).
        scene: PathBuf,
        /// Camera rays: one per pixel of WIDTHxHEIGHT (the incoherent set starts at their hits).
        #[arg(long, default_value = "512x512", value_parser = crate::parse_size)]
        size: (u32, u32),
        /// Timed repeats per measurement (the best counts).
        #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..=100))]
        repeats: u32,
    },
    /// Leakage removal, per scene: frame time of splat, leakless-capped and leakless at the
    /// same settings (best of --repeats), the visibility tests proven clear without a ray,
    /// what trivial accept saves, and the photon and visibility passes' rays per second
    /// against the device's own closest-hit and occlusion rates (`bench rays`).
    Leak {
        /// The scenes (.gltf or .glb).
        #[arg(required = true)]
        scenes: Vec<PathBuf>,
        #[arg(long, default_value = "320x240", value_parser = crate::parse_size)]
        size: (u32, u32),
        #[arg(long, default_value_t = 10_000)]
        paths: u32,
        /// Gather radius (default: the photon count's, --kernel-photons a kernel).
        #[arg(long)]
        radius: Option<f32>,
        /// Trace backend.
        #[arg(long, default_value = "auto")]
        backend: BackendChoice,
        /// Timed frames per configuration after a warm-up frame (the fastest counts).
        #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..=100))]
        repeats: u32,
        #[command(flatten)]
        fixed: crate::options::FixedRadius,
    },
    /// Temporal stability, per scene: flicker of splat, leakless-capped and leakless (a still
    /// view, fresh photons every frame, no accumulation), how much each frame of a leakless
    /// accumulation still changes the image, and the grain (pixel-scale noise) of the single
    /// frames.
    Flicker {
        /// The scenes (.gltf or .glb).
        #[arg(required = true)]
        scenes: Vec<PathBuf>,
        #[arg(long, default_value = "160x120", value_parser = crate::parse_size)]
        size: (u32, u32),
        #[arg(long, default_value_t = 10_000)]
        paths: u32,
        /// Trace backend.
        #[arg(long, default_value = "auto")]
        backend: BackendChoice,
        /// Frames of the accumulation whose changes are printed (from frame 2, the first change).
        #[arg(long, default_value_t = 32, value_parser = clap::value_parser!(u32).range(2..=MAX_FRAMES as i64))]
        frames: u32,
        #[command(flatten)]
        fixed: crate::options::FixedRadius,
    },
    /// Scenes that move: a leakless frame whose animation advances every frame against the
    /// same frame of the scene frozen, per backend, with the instance update's own costs.
    Animation {
        /// An animated scene (.gltf or .glb), e.g. scenes/door.gltf.
        scene: PathBuf,
        #[arg(long, default_value = "320x240", value_parser = crate::parse_size)]
        size: (u32, u32),
        #[arg(long, default_value_t = 10_000)]
        paths: u32,
        /// Timed frames per configuration, at frames/3 times through the animation.
        #[arg(long, default_value_t = 15, value_parser = clap::value_parser!(u32).range(1..=MAX_FRAMES as i64))]
        frames: u32,
        #[command(flatten)]
        fixed: crate::options::FixedRadius,
    },
    /// Temporal reuse in motion, per scene: its animation (or an orbit of its camera) rendered
    /// frame by frame with reuse on, on without its spatial filter, and off, against the path
    /// tracer at each frame: mean relMSE and HDR-FLIP, flicker on the screen and on the
    /// surfaces, the dark band beside lit regions, frame time, and the references' own noise.
    Motion(crate::bench_motion::MotionBench),
    /// Scene size, per scene (the same scene tessellated finer: `tools/gen-scenes --basilica
    /// DETAIL`): triangles, the load, each backend's setup and trace-structure build, the
    /// device memory held and a leakless frame.
    Scale(crate::bench_scale::ScaleBench),
    /// Photon splatting: per-pass times, hierarchy tests against brute force, growth with
    /// paths and resolution, and the branching factor B.
    Splat {
        /// The scene (.gltf or .glb).
        scene: PathBuf,
        /// Base image size (the resolution sweep halves and doubles it).
        #[arg(long, default_value = "320x240", value_parser = crate::parse_size)]
        size: (u32, u32),
        /// Base number of light paths.
        #[arg(long, default_value_t = 10_000)]
        paths: u32,
    },
}

pub fn run(cmd: BenchCommand) -> anyhow::Result<()> {
    match cmd {
        BenchCommand::Rays { scene, size, repeats } => rays(scene, size, repeats),
        BenchCommand::Splat { scene, size, paths } => splat(scene, size, paths),
        BenchCommand::Flicker { scenes, size, paths, backend, frames, fixed } => {
            crate::bench_flicker::run(&scenes, size, paths, backend, frames, fixed)
        }
        BenchCommand::Animation { scene, size, paths, frames, fixed } => {
            crate::bench_animation::run(&scene, size, paths, frames, fixed)
        }
        BenchCommand::Motion(bench) => crate::bench_motion::run(&bench),
        BenchCommand::Scale(bench) => crate::bench_scale::run(&bench),
        BenchCommand::Leak { scenes, size, paths, radius, backend, repeats, fixed } => {
            crate::bench_leak::run(&scenes, size, paths, (radius, fixed), backend, repeats)
        }
    }
}

fn rays(path: PathBuf, size: (u32, u32), repeats: u32) -> anyhow::Result<()> {
    let scene = Scene::load(&path).with_context(|| format!("loading {}", path.display()))?;
    let gpu = crate::open_gpu(BackendChoice::Auto)?;
    println!(
        "bench rays {} ({} triangles) on {}; best of {repeats}, host time of the trace submission",
        path.display(),
        scene.triangle_count(),
        gpu.report().name
    );
    let rates = bench::rays(&gpu, &scene, size.0, size.1, repeats)?;
    println!(
        "{:<9} {:<11} {:<9} {:>9} {:>10} {:>9} {:>11} {:>11}",
        "backend", "rays", "query", "count", "ms", "Mrays/s", "nodes/ray", "tris/ray"
    );
    for r in &rates {
        let (nodes, tris) =
            r.work_per_ray.map_or(("-".into(), "-".into()), |(n, t)| (format!("{n:.1}"), format!("{t:.1}")));
        println!(
            "{:<9} {:<11} {:<9} {:>9} {:>10.2} {:>9.2} {:>11} {:>11}",
            r.backend.name(),
            r.set,
            r.query,
            r.rays,
            r.best_ms,
            r.mrays_per_s(),
            nodes,
            tris
        );
    }
    println!("(nodes/ray, tris/ray: the compute traversal's bottom-level nodes processed and triangles tested, counted by a pass of its own outside the timed one; hits are written to device memory and copied after the timed pass)");
    let find = |b, set, q| rates.iter().find(|r| r.backend == b && r.set == set && r.query == q);
    let mut ratios = Vec::new();
    for set in ["coherent", "incoherent"] {
        for q in ["occluded", "closest"] {
            if let (Some(c), Some(rq)) = (find(Backend::Compute, set, q), find(Backend::RayQuery, set, q)) {
                ratios.push(format!("{set} {q} {:.2}", c.mrays_per_s() / rq.mrays_per_s()));
            }
        }
    }
    if ratios.is_empty() {
        println!("no ray queries on this device: compute backend only");
    } else {
        println!("speed ratio compute/rayquery: {}", ratios.join(", "));
    }
    Ok(())
}

fn splat(path: PathBuf, (w, h): (u32, u32), paths: u32) -> anyhow::Result<()> {
    use leakless::{Method, RenderSettings, SplatSettings};
    let scene = Scene::load(&path).with_context(|| format!("loading {}", path.display()))?;
    let auto = leakless::splatting::auto_radius(&scene);
    let open = || Ok(leakless::Gpu::new(&leakless::GpuOptions { validation: None, ray_tracing: true, window: None })?);
    let s = |paths, radius: f32, branching| SplatSettings {
        paths,
        radius: Some(radius),
        branching: Some(branching),
        ..Default::default()
    };
    let gpu = open()?;
    let (gpu_name, timing) = (gpu.report().name.clone(), leakless_measure::bench::timing_phrase(&gpu));
    drop(gpu);
    println!("bench splat {} on {gpu_name}; {timing}, second frame", path.display());

    let table = |title: &str, configs: Vec<(u32, u32, SplatSettings)>| -> anyhow::Result<Vec<Measured>> {
        let rows = configs
            .iter()
            .map(|(width, height, splat)| {
                let settings = RenderSettings {
                    width: *width,
                    height: *height,
                    method: Method::Splat,
                    splat: splat.clone(),
                    ..Default::default()
                };
                Measured::run(&open, &scene, "splat", &settings)
            })
            .collect::<leakless::Result<Vec<_>>>()?;
        println!("\n{title}");
        println!(
            "{:>9} {:>7} {:>7} {:>2} {:>8} {:>9} {:>9} {:>9} {:>9} {:>9} {:>11} {:>8}",
            "size",
            "paths",
            "radius",
            "B",
            "photons",
            "photon ms",
            "hier. ms",
            "splat ms",
            "gather ms",
            "entries",
            "tests",
            "vs brute"
        );
        for r in &rows {
            let st = r.stats();
            println!(
                "{:>9} {:>7} {:>7.4} {:>2} {:>8} {:>9.1} {:>9.1} {:>9.1} {:>9.1} {:>9} {:>11} {:>7.3}%",
                format!("{}x{}", r.settings.width, r.settings.height),
                st.paths,
                st.radius,
                st.branching,
                st.photons_stored,
                r.photons_ms(),
                r.hierarchy_ms(),
                r.splat_ms(),
                r.gather_ms(),
                st.list_entries,
                st.candidate_tests,
                100.0 * st.candidate_tests as f64 / st.brute_force_tests.max(1) as f64
            );
            if st.list_entries_dropped > 0 {
                println!("          ({} list entries dropped: raise --list-capacity)", st.list_entries_dropped);
            }
        }
        Ok(rows)
    };
    table(
        "(paths, radius): gather tests against a brute-force splat",
        vec![
            (w, h, s(paths, auto, 8)),
            (w, h, s(paths, 2.0 * auto, 8)),
            (w, h, s(4 * paths, auto, 8)),
            (w, h, s(4 * paths, 0.5 * auto, 8)),
        ],
    )?;
    let grow = table("growth with paths", (0..4).map(|i| (w, h, s(paths << i, auto, 8))).collect())?;
    let ratio = |a: f64, b: f64| if a > 0.0 { b / a } else { f64::NAN };
    println!(
        "splat time x{:.2} and gather time x{:.2} for x8 paths",
        ratio(grow[0].splat_ms(), grow[3].splat_ms()),
        ratio(grow[0].gather_ms(), grow[3].gather_ms())
    );
    let res = table(
        "growth with resolution",
        [(w / 2, h / 2), (w, h), (2 * w, 2 * h)].into_iter().map(|(a, b)| (a, b, s(paths, auto, 8))).collect(),
    )?;
    println!(
        "hierarchy x{:.2}, splat x{:.2}, gather x{:.2} for x16 pixels",
        ratio(res[0].hierarchy_ms(), res[2].hierarchy_ms()),
        ratio(res[0].splat_ms(), res[2].splat_ms()),
        ratio(res[0].gather_ms(), res[2].gather_ms())
    );
    let b = table("branching factor B", [4, 8, 16, 32].into_iter().map(|b| (w, h, s(paths, auto, b))).collect())?;
    let best = b
        .iter()
        .min_by(|x, y| {
            (x.hierarchy_ms() + x.splat_ms() + x.gather_ms())
                .total_cmp(&(y.hierarchy_ms() + y.splat_ms() + y.gather_ms()))
        })
        .expect("four rows");
    println!("fastest hierarchy + splat + gather: B = {}", best.stats().branching);
    photon_order(&open, &scene, (w, h), paths)
}

/// `leakless` on an accumulation's full frame (8 batches), with the photons ordered by cell
/// before the splat and in the order the trace stored them: the same image (tests/suite/splat.rs),
/// and what the order saves in the passes that walk a structure per photon.
fn photon_order(
    open: &dyn Fn() -> leakless::Result<leakless::Gpu>,
    scene: &Scene,
    (width, height): (u32, u32),
    paths: u32,
) -> anyhow::Result<()> {
    use leakless::{Method, RenderSettings, SplatSettings};
    println!("\nphoton order: leakless, {} paths (an accumulating frame's 8 batches), best of 3", 8 * paths);
    println!(
        "{:<10} {:>9} {:>9} {:>12} {:>9} {:>9} {:>9}",
        "photons", "order ms", "splat ms", "clearance ms", "gather ms", "frame ms", "entries"
    );
    let mut rows = Vec::new();
    for (label, order_photons) in [("ordered", true), ("as traced", false)] {
        let splat = SplatSettings { paths: 8 * paths, order_photons, ..Default::default() };
        let settings = RenderSettings { width, height, method: Method::LeakLess, splat, ..Default::default() };
        let r = Measured::best_of(open, scene, label, &settings, 3)?;
        println!(
            "{:<10} {:>9.1} {:>9.1} {:>12.1} {:>9.1} {:>9.1} {:>9}",
            label,
            r.group_ms(group::PHOTON_ORDER),
            r.splat_ms(),
            r.pass_ms(PHOTON_CLEARANCE.name),
            r.gather_ms(),
            r.frame_ms(),
            r.stats().list_entries
        );
        rows.push(r);
    }
    let x = |f: fn(&Measured) -> f64| f(&rows[1]) / f(&rows[0]).max(1e-9);
    println!(
        "ordered is faster by x{:.2} in the splat, x{:.2} in the clearance, x{:.2} in the gather, x{:.2} over the frame",
        x(|r| r.splat_ms()),
        x(|r| r.pass_ms(PHOTON_CLEARANCE.name)),
        x(|r| r.gather_ms()),
        x(|r| r.frame_ms())
    );
    Ok(())
}
