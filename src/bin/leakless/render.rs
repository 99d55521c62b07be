//! `leakless render`: one frame to a layered EXR, optionally a PNG and stats.

use std::path::PathBuf;

use anyhow::Context;
use leakless::output::{self, exr::ExrLayer, stats::Stats};
use leakless::{BackendChoice, Method, RenderSettings, Renderer, Scene, SplatSettings};
use leakless_graph::Timing;

#[derive(clap::Args)]
pub struct RenderArgs {
    /// The scene (.gltf or .glb).
    scene: PathBuf,
    /// Output EXR (default: <scene name>.exr in the current directory).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Also write a tonemapped PNG.
    #[arg(long)]
    png: Option<PathBuf>,
    /// Output size, WIDTHxHEIGHT.
    #[arg(long, default_value = "640x480", value_parser = crate::parse_size)]
    size: (u32, u32),
    /// `leakless` (ours: splatting with a visibility ray to every photon), `leakless-capped`
    /// (the thesis: no trivial accept, at most --cap photons per pixel), `splat` (Moreau et
    /// al., leaks), `reference` (path-traced indirect light) or `direct` (direct light only).
    #[arg(long, default_value = "leakless", value_parser = ["leakless", "leakless-capped", "splat", "reference", "direct"])]
    method: String,
    /// Photons gathered per pixel at most by `leakless-capped` (the thesis used 25).
    #[arg(long)]
    cap: Option<u32>,
    /// Light paths traced per frame by the photon methods.
    #[arg(long, default_value_t = 10_000)]
    paths: u32,
    /// Photon gather radius in scene units (default: 5% of the scene's bounding radius).
    #[arg(long)]
    radius: Option<f32>,
    /// Branching factor of the view-sample hierarchy.
    #[arg(long, default_value_t = 8)]
    branching: u32,
    /// Walk to the leaves instead of listing photons on enveloped nodes (same image).
    #[arg(long)]
    no_trivial_accept: bool,
    /// Node-list entries per frame (default: 16 per photon); more are dropped and reported.
    #[arg(long)]
    list_capacity: Option<u32>,
    /// Trace backend: ray queries, the compute-shader BVH, or `auto` (ray queries if present).
    #[arg(long, default_value = "auto", value_parser = crate::parse_backend)]
    backend: BackendChoice,
    /// Samples per pixel of the reference path tracer.
    #[arg(long, default_value_t = 64)]
    spp: u32,
    /// Indirect bounces after the first surface.
    #[arg(long, default_value_t = 8)]
    max_bounces: u32,
    /// Seed of every random sequence (a fixed seed gives an identical frame).
    #[arg(long, default_value_t = 0)]
    seed: u32,
    /// Write per-pass GPU times, build costs and counts as JSON.
    #[arg(long)]
    stats: Option<PathBuf>,
    /// How passes are timed: `timestamps` (one submission, GPU timestamps), `per-pass` (one
    /// waited submission per pass, also timed on the host), or `auto`: per-pass on CPU devices
    /// such as lavapipe, whose timestamps inside one submission do not bracket compute work.
    #[arg(long, default_value = "auto", value_parser = ["auto", "timestamps", "per-pass"])]
    timing: String,
    /// PNG exposure multiplier (default: automatic).
    #[arg(long)]
    exposure: Option<f32>,
}

pub fn run(args: RenderArgs) -> anyhow::Result<()> {
    let settings = RenderSettings {
        width: args.size.0,
        height: args.size.1,
        backend: args.backend,
        method: Method::parse(&args.method).expect("clap checked the value"),
        spp: args.spp,
        max_bounces: args.max_bounces,
        seed: args.seed,
        splat: SplatSettings {
            paths: args.paths,
            radius: args.radius,
            branching: args.branching,
            trivial_accept: !args.no_trivial_accept,
            list_capacity: args.list_capacity,
            // Both follow from the method (RenderSettings::photon_settings).
            visibility: false,
            cap: args.cap,
        },
    };
    settings.validate()?;
    let scene = Scene::load(&args.scene).with_context(|| format!("loading {}", args.scene.display()))?;
    for w in &scene.warnings {
        eprintln!("warning: {}: {w}", args.scene.display());
    }
    let gpu = crate::open_gpu(settings.backend)?;
    let report = gpu.report().clone();
    let mut renderer = Renderer::new(gpu, &scene, settings.clone()).context("setting up the renderer")?;
    let cpu_device = report.device_type == leakless_device::DeviceType::Cpu;
    if args.timing == "per-pass" || (args.timing == "auto" && cpu_device) {
        renderer.set_timing(Timing::PerPassSubmit);
    }
    let frame = render_with_bar(&mut renderer, settings.method)?;
    if let Some(s) = &frame.splat {
        if s.photons_dropped > 0 || s.list_entries_dropped > 0 {
            eprintln!(
                "warning: capacity exceeded: {} photons and {} node-list entries dropped (raise --list-capacity); the indirect light is incomplete",
                s.photons_dropped, s.list_entries_dropped
            );
        }
    }

    let out = args.out.unwrap_or_else(|| PathBuf::from(format!("{}.exr", scene.name)));
    let layers = [
        ExrLayer { name: "", pixels: &frame.radiance },
        ExrLayer { name: "direct", pixels: &frame.direct },
        ExrLayer { name: "indirect", pixels: &frame.indirect },
        ExrLayer { name: "leaked", pixels: &frame.leaked },
    ];
    let attributes = [
        ("leakless.scene", args.scene.display().to_string()),
        ("leakless.method", settings.method.name().to_string()),
        ("leakless.parameters", format!("{} backend={}", settings.describe(), renderer.backend().name())),
        ("leakless.device", report.name.clone()),
    ];
    output::exr::write(&out, frame.width, frame.height, &layers, &attributes)?;
    println!("wrote {}", out.display());
    if let Some(png) = &args.png {
        output::png::write(png, frame.width, frame.height, &frame.radiance, args.exposure)?;
        println!("wrote {}", png.display());
    }
    if let Some(path) = &args.stats {
        let stats = Stats::new(&scene, &report, &renderer, &frame);
        output::stats::write(path, &stats)?;
        println!("wrote {}", path.display());
    }
    Ok(())
}

/// Renders, with a progress bar on a terminal while reference samples accumulate.
fn render_with_bar(renderer: &mut Renderer, method: Method) -> anyhow::Result<leakless::RenderedFrame> {
    use std::io::IsTerminal;
    let bar = (method == Method::Reference && std::io::stderr().is_terminal()).then(|| {
        let bar = indicatif::ProgressBar::new(renderer.settings().spp as u64);
        bar.set_style(
            indicatif::ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} spp, {elapsed} (eta {eta})")
                .expect("valid template")
                .progress_chars("=> "),
        );
        bar.set_message("reference");
        bar
    });
    let frame = renderer.render_with_progress(&mut |done, _| {
        if let Some(bar) = &bar {
            bar.set_position(done as u64);
        }
    });
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    frame.context("rendering")
}
