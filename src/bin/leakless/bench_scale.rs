//! `leakless bench scale`: what a scene's size costs. Per scene (the same scene tessellated
//! finer: `tools/gen-scenes --basilica DETAIL`), the load, the trace structure's build, the
//! device memory and a leakless frame, per backend, in one process.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Context;
use leakless::{Backend, BackendChoice, Method, RenderSettings, Renderer, Scene, SplatSettings};

use leakless_measure::chart::scale_plot::{plot_scale, ScalePoint};
use leakless_measure::csv_table::CsvTable;

/// What the bench renders (`leakless bench scale`'s options).
#[derive(clap::Args)]
pub struct ScaleBench {
    /// The scenes (.gltf or .glb), e.g. the basilica at several details.
    #[arg(required = true)]
    pub scenes: Vec<PathBuf>,
    #[arg(long, default_value = "320x240", value_parser = crate::parse_size)]
    pub size: (u32, u32),
    #[arg(long, default_value_t = 10_000)]
    pub paths: u32,
    /// Timed frames per scene and backend after a warm-up frame (the fastest counts).
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u32).range(1..=100))]
    pub repeats: u32,
    /// Trace backend (`auto`: both where the device has ray queries).
    #[arg(long, default_value = "auto")]
    pub backend: BackendChoice,
    #[command(flatten)]
    pub out: crate::options::FigureFiles,
    #[command(flatten)]
    pub fixed: crate::options::FixedRadius,
}

pub fn run(bench: &ScaleBench) -> anyhow::Result<()> {
    let (w, h) = bench.size;
    let gpu = crate::open_gpu(bench.backend)?;
    let backends: Vec<(BackendChoice, Backend)> = match bench.backend {
        BackendChoice::Auto if gpu.capabilities().ray_query => {
            vec![(BackendChoice::Compute, Backend::Compute), (BackendChoice::RayQuery, Backend::RayQuery)]
        }
        BackendChoice::Auto | BackendChoice::Compute => vec![(BackendChoice::Compute, Backend::Compute)],
        BackendChoice::RayQuery => vec![(BackendChoice::RayQuery, Backend::RayQuery)],
    };
    let device = gpu.report().name.clone();
    drop(gpu);
    println!(
        "bench scale on {device}: leakless {w}x{h}, {} paths, best of {} frames after a warm-up",
        bench.paths, bench.repeats
    );
    println!("load: glTF to world-space triangles on the host; setup: upload and trace structure (build: its part);");
    println!("memory: what the renderer has allocated after the frames (buffers, images, acceleration structures)");
    println!(
        "{:<22} {:>10} {:>9} {:<8} {:>10} {:>10} {:>11} {:>10}",
        "scene", "triangles", "load ms", "backend", "setup ms", "build ms", "memory MiB", "frame ms"
    );
    let mut points = Vec::new();
    for path in &bench.scenes {
        let start = Instant::now();
        let scene = Scene::load(path).with_context(|| format!("loading {}", path.display()))?;
        let load_ms = start.elapsed().as_secs_f64() * 1e3;
        for &(choice, backend) in &backends {
            let settings = RenderSettings {
                width: w,
                height: h,
                backend: choice,
                method: Method::LeakLess,
                splat: SplatSettings { paths: bench.paths, radius: bench.fixed.radius(&scene), ..Default::default() },
                ..Default::default()
            };
            let start = Instant::now();
            let mut renderer = Renderer::new(crate::open_gpu(choice)?, &scene, settings)
                .with_context(|| format!("{}: the {} backend", path.display(), backend.name()))?;
            let setup_ms = start.elapsed().as_secs_f64() * 1e3;
            let build_ms = renderer.trace_stats().build_ms;
            renderer.render_frame(None)?;
            renderer.wait_idle()?;
            let mut frame_ms = f64::INFINITY;
            for _ in 0..bench.repeats {
                let start = Instant::now();
                renderer.render_frame(None)?;
                renderer.wait_idle()?;
                frame_ms = frame_ms.min(start.elapsed().as_secs_f64() * 1e3);
            }
            renderer.gpu().check_validation()?;
            let (allocated, _) = renderer.gpu().memory_in_use();
            let point = ScalePoint {
                scene: file_name(path),
                triangles: scene.triangle_count() as u64,
                load_ms,
                backend,
                setup_ms,
                build_ms,
                memory_mib: allocated as f64 / (1 << 20) as f64,
                frame_ms,
            };
            println!(
                "{:<22} {:>10} {:>9.0} {:<8} {:>10.0} {:>10.0} {:>11.0} {:>10.1}",
                point.scene,
                point.triangles,
                point.load_ms,
                backend.name(),
                point.setup_ms,
                point.build_ms,
                point.memory_mib,
                point.frame_ms
            );
            points.push(point);
        }
    }
    if let Some(csv) = &bench.out.csv {
        write_csv(csv, &points)?;
        println!("wrote {}", csv.display());
    }
    if let Some(svg) = &bench.out.chart {
        let png = svg.with_extension("png");
        plot_scale(&points, &device, bench.size, svg, &png).with_context(|| format!("writing {}", svg.display()))?;
        println!("wrote {} and {}", svg.display(), png.display());
    }
    Ok(())
}

fn file_name(path: &Path) -> String {
    path.file_name().map_or_else(|| path.display().to_string(), |n| n.to_string_lossy().into_owned())
}

fn write_csv(path: &Path, points: &[ScalePoint]) -> anyhow::Result<()> {
    let header = ["scene", "triangles", "load_ms", "backend", "setup_ms", "build_ms", "memory_mib", "frame_ms"];
    let mut table = CsvTable::new(&header);
    for p in points {
        table.row([
            p.scene.clone(),
            p.triangles.to_string(),
            format!("{:.1}", p.load_ms),
            p.backend.name().to_string(),
            format!("{:.1}", p.setup_ms),
            format!("{:.1}", p.build_ms),
            format!("{:.1}", p.memory_mib),
            format!("{:.2}", p.frame_ms),
        ])?;
    }
    Ok(table.write(path)?)
}
