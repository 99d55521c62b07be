//! The `leakless` command: render a scene to EXR (+ PNG, stats), or report the device.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{bail, Context};
use clap::{Parser, Subcommand};
use leakless::output::{self, exr::ExrLayer, stats::Stats};
use leakless::{Gpu, GpuOptions, RenderSettings, Renderer, Scene};

#[derive(Parser)]
#[command(
    name = "leakless",
    version,
    about = "Diffuse global illumination by photon splatting, without light leaks"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a glTF scene to a layered EXR (and optionally a PNG and a stats file).
    Render(RenderArgs),
    /// Print the Vulkan devices, which one is used, and what it can do.
    Info,
}

#[derive(clap::Args)]
struct RenderArgs {
    /// The scene (.gltf or .glb).
    scene: PathBuf,
    /// Output EXR (default: <scene name>.exr in the current directory).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Also write a tonemapped PNG.
    #[arg(long)]
    png: Option<PathBuf>,
    /// Output size, WIDTHxHEIGHT.
    #[arg(long, default_value = "640x480", value_parser = parse_size)]
    size: (u32, u32),
    /// Write per-pass GPU times and counts as JSON.
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

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("{s:?} is not WIDTHxHEIGHT"))?;
    let parse = |v: &str| {
        v.trim()
            .parse::<u32>()
            .map_err(|_| format!("{s:?} is not WIDTHxHEIGHT"))
    };
    Ok((parse(w)?, parse(h)?))
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render(args) => render(args),
        Command::Info => info(),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // One line: the context chain joined, the way a user reads it.
            eprintln!("error: {}", format!("{e:#}").replace('\n', " "));
            ExitCode::FAILURE
        }
    }
}

fn render(args: RenderArgs) -> anyhow::Result<()> {
    let settings = RenderSettings {
        width: args.size.0,
        height: args.size.1,
    };
    settings.validate()?;
    let scene =
        Scene::load(&args.scene).with_context(|| format!("loading {}", args.scene.display()))?;
    for w in &scene.warnings {
        eprintln!("warning: {}: {w}", args.scene.display());
    }
    let gpu = Gpu::new(&GpuOptions {
        validation: None,
        ray_tracing: false,
    })
    .context("opening the Vulkan device")?;
    let report = gpu.report().clone();
    let mut renderer = Renderer::new(gpu, &scene, settings).context("setting up the renderer")?;
    let cpu_device = report.device_type == leakless_device::DeviceType::Cpu;
    if args.timing == "per-pass" || (args.timing == "auto" && cpu_device) {
        renderer.set_timing(leakless_graph::Timing::PerPassSubmit);
    }
    let frame = renderer.render().context("rendering")?;

    let out = args
        .out
        .unwrap_or_else(|| PathBuf::from(format!("{}.exr", scene.name)));
    let params = format!("size={}x{}", frame.width, frame.height);
    output::exr::write(
        &out,
        frame.width,
        frame.height,
        &[
            ExrLayer {
                name: "",
                pixels: &frame.radiance,
            },
            ExrLayer {
                name: "direct",
                pixels: &frame.direct,
            },
        ],
        &[
            ("leakless.scene", args.scene.display().to_string()),
            ("leakless.method", "direct".into()),
            ("leakless.parameters", params),
            ("leakless.device", report.name.clone()),
        ],
    )?;
    println!("wrote {}", out.display());
    if let Some(png) = &args.png {
        output::png::write(
            png,
            frame.width,
            frame.height,
            &frame.radiance,
            args.exposure,
        )?;
        println!("wrote {}", png.display());
    }
    if let Some(path) = &args.stats {
        let stats = Stats {
            scene: scene.name.clone(),
            device: report.name.clone(),
            driver: report.driver.clone(),
            backend: "raster".into(),
            width: frame.width,
            height: frame.height,
            triangles: scene.triangle_count(),
            lights: scene.lights.len(),
            frame_gpu_ms: frame.timings.iter().map(|t| t.ms).sum(),
            frame_wall_ms: frame.wall_ms,
            passes: frame
                .timings
                .iter()
                .map(|t| output::stats::PassTime {
                    pass: t.name.clone(),
                    gpu_ms: t.ms,
                    wall_ms: t.wall_ms,
                })
                .collect(),
        };
        output::stats::write(path, &stats)?;
        println!("wrote {}", path.display());
    }
    check_written(&out)
}

fn check_written(path: &Path) -> anyhow::Result<()> {
    if !path.exists() {
        bail!("{} was not written", path.display());
    }
    Ok(())
}

fn info() -> anyhow::Result<()> {
    let reports = Gpu::list_devices().context("listing Vulkan devices")?;
    if reports.is_empty() {
        bail!("the Vulkan loader sees no device (install mesa-vulkan-drivers: tools/install-deps)");
    }
    let gpu = Gpu::new(&GpuOptions {
        validation: Some(false),
        ray_tracing: true,
    });
    let chosen = gpu.as_ref().ok().map(|g| g.report().index);
    for r in &reports {
        let mark = if Some(r.index) == chosen { "*" } else { " " };
        println!(
            "{mark} device {}: {} ({:?}), Vulkan {}.{}.{}, driver {}",
            r.index,
            r.name,
            r.device_type,
            r.api_version.0,
            r.api_version.1,
            r.api_version.2,
            r.driver
        );
        println!("    ray queries: {}, acceleration structures: {}, subgroup size: {}, timestamp period: {} ns",
            yes(r.ray_query), yes(r.acceleration_structure), r.subgroup_size, r.timestamp_period_ns);
        if let Some(why) = &r.rejected {
            println!("    rejected: {why}");
        }
    }
    match gpu {
        Ok(g) => {
            let r = g.report();
            println!(
                "using device {} ({}); LEAKLESS_DEVICE=<index or name> picks another",
                r.index, r.name
            );
            let caps = g.capabilities();
            println!(
                "trace backend for --backend auto: {}",
                if caps.ray_query {
                    "rayquery (VK_KHR_ray_query present)"
                } else {
                    "compute (no VK_KHR_ray_query: compute-shader BVH traversal)"
                }
            );
            Ok(())
        }
        Err(e) => Err(e).context("opening a device"),
    }
}

fn yes(b: bool) -> &'static str {
    if b {
        "yes"
    } else {
        "no"
    }
}
