//! `leakless bench`: ratios measured in one process, printed, never asserted.

use std::path::PathBuf;

use anyhow::Context;
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
        #[arg(long, default_value_t = 3)]
        repeats: u32,
    },
}

pub fn run(cmd: BenchCommand) -> anyhow::Result<()> {
    match cmd {
        BenchCommand::Rays { scene, size, repeats } => rays(scene, size, repeats),
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
    let rates = leakless::bench::rays(&gpu, &scene, size.0, size.1, repeats)?;
    println!("{:<9} {:<11} {:<9} {:>9} {:>10} {:>9}", "backend", "rays", "query", "count", "ms", "Mrays/s");
    for r in &rates {
        println!(
            "{:<9} {:<11} {:<9} {:>9} {:>10.2} {:>9.2}",
            r.backend.name(),
            r.set,
            r.query,
            r.rays,
            r.best_ms,
            r.mrays_per_s()
        );
    }
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
