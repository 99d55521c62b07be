//! `leakless chart`: error against frame time for each method, setting and backend.

use std::path::PathBuf;

use anyhow::Context;
use leakless::{Backend, Method, Scene};
use leakless_measure::chart::{self, ChartConfig, Radii};

#[derive(clap::Args)]
pub struct ChartArgs {
    /// The scenes (.gltf or .glb); one CSV and one set of charts per scene.
    #[arg(required = true)]
    pub(crate) scenes: Vec<PathBuf>,
    /// Output prefix: writes PREFIX-<scene>.csv and PREFIX-<scene>-<metric>.svg/.png for the
    /// metrics relmse, relmse-dark, rmse and rmse-dark.
    #[arg(long)]
    pub(crate) out: PathBuf,
    /// Render size of the reference and of every method, WIDTHxHEIGHT.
    #[arg(long, default_value = "160x120", value_parser = crate::parse_size)]
    pub(crate) size: (u32, u32),
    /// Samples per pixel of the reference path tracer.
    #[arg(long, default_value_t = 1024)]
    pub(crate) ref_spp: u32,
    /// Indirect bounces, for the reference and the methods alike.
    #[arg(long, default_value_t = 8)]
    pub(crate) max_bounces: u32,
    /// Methods to chart, comma-separated [default: splat, leakless-capped, leakless — those
    /// this build has]. Series: of splat, leakless and reference [default: all three].
    #[arg(long, value_delimiter = ',')]
    pub(crate) methods: Option<Vec<Method>>,
    /// Light paths per frame, comma-separated (`k` = thousand) [default: 5k,20k,80k].
    #[arg(long, value_delimiter = ',', value_parser = parse_count)]
    paths: Option<Vec<u32>>,
    /// Gather radii in scene units, comma-separated [default: 0.5, 1 and 2 × the automatic
    /// radius, 5% of the scene's bounding radius; see --radius-scale]. Series: one radius, the
    /// first frame's [default: the photon count's, as `render`'s].
    #[arg(long, value_delimiter = ',', conflicts_with_all = ["radius_scale", "kernel_photons"])]
    pub(crate) radius: Option<Vec<f32>>,
    /// Gather radii as multiples of the automatic radius, comma-separated [default: 0.5,1,2].
    #[arg(long, value_delimiter = ',', conflicts_with = "kernel_photons")]
    radius_scale: Option<Vec<f32>>,
    /// Instead of fixed radii, the radius at which a kernel holds each of these many photons
    /// (the renderer's default radius), comma-separated: how the default K was chosen.
    /// Series: one count [default: the renderer's].
    #[arg(long, value_delimiter = ',')]
    pub(crate) kernel_photons: Option<Vec<f32>>,
    /// Trace backends, comma-separated: rayquery, compute [default: every one the device has].
    /// Series: one backend [default: the device's choice].
    #[arg(long, value_delimiter = ',')]
    pub(crate) backends: Option<Vec<Backend>>,
    /// Timed frames per setting after the warm-up frame; the fastest counts (lavapipe's
    /// times vary by tens of percent from frame to frame). Series: runs of every series, the
    /// methods taking turns, each checkpoint at its fastest time.
    #[arg(long, default_value_t = 1)]
    pub(crate) repeats: u32,
    /// Dark pixels (the second error of each chart): those whose reference indirect light is at
    /// most this fraction of its mean over the pixels with a surface [default: 0.01].
    #[arg(long)]
    dark_fraction: Option<f64>,
    /// Seed of every random sequence.
    #[arg(long, default_value_t = 0)]
    pub(crate) seed: u32,
    /// Size of each chart, WIDTHxHEIGHT pixels (the SVG's too).
    #[arg(long, default_value = "800x600", value_parser = crate::parse_size)]
    pub(crate) chart_size: (u32, u32),
    /// Convergence instead: error (relMSE, relMSE over the shaded pixels, RMSE, HDR-FLIP)
    /// against wall time while leakless, splat (photon frames) and the reference path tracer
    /// (samples) accumulate, against a jittered ground truth; writes PREFIX-<scene>-series.csv and -series-{relmse,flip}.svg/.png.
    #[arg(long)]
    pub(crate) series: bool,
    /// Series: wall time each method accumulates for, seconds [default: 10].
    #[arg(long)]
    pub(crate) budget: Option<f64>,
    /// Series: light paths per photon frame [default: 10000].
    #[arg(long)]
    pub(crate) frame_paths: Option<u32>,
    /// Series: the ground truth's jittered frames, each of --ref-spp / this many samples
    /// [default: 64].
    #[arg(long)]
    pub(crate) truth_frames: Option<u32>,
}

impl ChartArgs {
    /// The first flag given that the chosen mode has no use for: the grid's settings with
    /// `--series`, the series' without it. Ignoring it would chart something else than asked.
    fn flag_of_the_other_mode(&self) -> Option<&'static str> {
        let given = |flag: &'static str, is: bool| is.then_some(flag);
        if self.series {
            given("--paths", self.paths.is_some())
                .or(given("--radius-scale", self.radius_scale.is_some()))
                .or(given("--dark-fraction", self.dark_fraction.is_some()))
        } else {
            given("--budget", self.budget.is_some())
                .or(given("--frame-paths", self.frame_paths.is_some()))
                .or(given("--truth-frames", self.truth_frames.is_some()))
        }
    }
}

/// `20000` or `20k`.
fn parse_count(s: &str) -> Result<u32, String> {
    let bad = || format!("{s:?} is not a count such as 20000 or 20k");
    let t = s.trim();
    let (digits, scale) = match t.strip_suffix(['k', 'K']) {
        Some(d) => (d, 1000),
        None => (t, 1),
    };
    digits.parse::<u32>().ok().and_then(|n| n.checked_mul(scale)).ok_or_else(bad)
}

pub fn run(args: ChartArgs) -> anyhow::Result<()> {
    use std::io::IsTerminal;
    if let Some(flag) = args.flag_of_the_other_mode() {
        let mode = if args.series { "the grid chart, not --series" } else { "--series only" };
        anyhow::bail!("{flag} applies to {mode}");
    }
    if args.series {
        return crate::chart_series::run(&args);
    }
    let defaults = ChartConfig::default();
    let config = ChartConfig {
        width: args.size.0,
        height: args.size.1,
        ref_spp: args.ref_spp,
        max_bounces: args.max_bounces,
        seed: args.seed,
        methods: args.methods.unwrap_or_else(chart::default_methods),
        radii: match args.radius {
            Some(r) => Radii::Absolute(r),
            None => match (args.radius_scale, args.kernel_photons) {
                (Some(scales), _) => Radii::Auto(scales),
                (None, Some(ks)) => Radii::KernelPhotons(ks),
                (None, None) => defaults.radii,
            },
        },
        paths: args.paths.unwrap_or(defaults.paths),
        backends: args.backends.unwrap_or_default(),
        repeats: args.repeats,
        dark_fraction: args.dark_fraction.unwrap_or(defaults.dark_fraction),
    };
    config.validate()?;
    chart::drawing::check_size(args.chart_size)?;
    // Fail on an unwritable output directory now, not after the measurements.
    if let Some(dir) = args.out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    // Load every scene first: a typo in the last one should not wait for the first's chart.
    let scenes = args
        .scenes
        .iter()
        .map(|path| {
            let scene = Scene::load(path).with_context(|| format!("loading {}", path.display()))?;
            for w in &scene.warnings {
                eprintln!("warning: {}: {w}", path.display());
            }
            Ok(scene)
        })
        .collect::<anyhow::Result<Vec<_>>>()?;
    let wants_rayquery = config.backends.is_empty() || config.backends.contains(&Backend::RayQuery);
    let open = |ray_tracing: bool| -> leakless::Result<leakless::Gpu> {
        let options =
            leakless::GpuOptions { validation: None, ray_tracing: ray_tracing && wants_rayquery, window: None };
        Ok(leakless::Gpu::new(&options)?)
    };
    let methods: Vec<_> = config.methods.iter().map(|m| m.name()).collect();
    println!(
        "chart {} at {}x{}, reference {} spp, methods {}",
        args.scenes.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join(" "),
        config.width,
        config.height,
        config.ref_spp,
        methods.join(", ")
    );

    let start = std::time::Instant::now();
    for (path, scene) in args.scenes.iter().zip(&scenes) {
        let bar = std::io::stderr().is_terminal().then(|| {
            // Hidden until the first report gives the number of renders.
            let bar = indicatif::ProgressBar::with_draw_target(None, indicatif::ProgressDrawTarget::hidden());
            bar.set_style(
                indicatif::ProgressStyle::with_template("{prefix} [{bar:30}] {pos}/{len} renders, {elapsed} {msg}")
                    .expect("valid template")
                    .progress_chars("=> "),
            );
            bar.set_prefix(scene.name.clone());
            bar
        });
        let measured = chart::measure_with_progress(&open, scene, &config, &mut |p| {
            if let Some(bar) = &bar {
                if bar.is_hidden() {
                    bar.set_length(p.total as u64);
                    bar.set_draw_target(indicatif::ProgressDrawTarget::stderr());
                }
                bar.set_length(p.total as u64);
                bar.set_position(p.done as u64);
                bar.set_message(p.message.clone());
            }
        });
        if let Some(bar) = bar {
            bar.finish_and_clear();
        }
        let measured = measured.with_context(|| format!("charting {}", path.display()))?;
        print_table(&measured);
        let written = chart::write_outputs(&measured, &args.out, args.chart_size)?;
        for p in written {
            println!("wrote {}", p.display());
        }
    }
    println!("took {:.1} s", start.elapsed().as_secs_f64());
    Ok(())
}

fn print_table(c: &chart::SceneChart) {
    println!(
        "\n{} on {}: reference {:.1} s; auto radius {:.4}; {} dark pixels (indirect ≤ {}× mean) of {} with a surface",
        c.scene,
        c.device,
        c.reference_ms / 1e3,
        c.auto_radius,
        c.dark_pixels,
        c.dark_fraction,
        c.covered_pixels
    );
    if c.cpu_device {
        println!("frame ms: per-pass wall times of the second frame, summed; CPU time on this CPU device");
    } else {
        println!("frame ms: per-pass wall times of the second frame, summed");
    }
    println!(
        "{:<16} {:<9} {:>7} {:>8} {:>6} {:>9} {:>10} {:>10} {:>10} {:>10}",
        "method", "backend", "paths", "radius", "K", "frame ms", "relMSE", "RMSE", "relMSE dk", "RMSE dk"
    );
    let opt = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.3e}"));
    for p in &c.points {
        println!(
            "{:<16} {:<9} {:>7} {:>8} {:>6} {:>9.1} {:>10} {:>10} {:>10} {:>10}",
            p.method.name(),
            p.backend.name(),
            p.paths.map_or("-".into(), |v| v.to_string()),
            p.radius.map_or("-".into(), |v| format!("{v:.4}")),
            p.photons_per_kernel.map_or("-".into(), |v| format!("{v:.1}")),
            p.frame_ms,
            opt(p.errors.relmse),
            opt(p.errors.rmse),
            opt(p.errors.relmse_dark),
            opt(p.errors.rmse_dark)
        );
    }
}
