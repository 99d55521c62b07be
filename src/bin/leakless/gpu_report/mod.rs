//! `leakless gpu-report --out DIR`: the standard matrix a GPU is judged by, in one command
//! with no network, written as `gpu-report.md` and `gpu-report.json` (tools/gpu-report wraps
//! it). Sections, in order, each written out as soon as it is done so that a run cut short
//! still leaves what it measured:
//!
//! 1. the device (`leakless info`) and its tuning;
//! 2. correctness: every shipped scene rendered with validation on, against the same render
//!    made on lavapipe's compute backend and kept in `tests/fixtures/gpu-report/`;
//! 3. per-pass GPU times of `splat`, `leakless-capped` and `leakless` at 10k / 50k / 200k paths,
//!    1280×720 and 1920×1080, on the atrium and the doorway, with the photon counters;
//! 4. `bench rays` at 2048×2048;
//! 5. branching factors 8 / 16 / 32, and each choice of the device tuning toggled, on the
//!    atrium at 1080p and 200k paths (what the GPU preset should be).
//!
//! `--quick` runs the same sections at small sizes (the test suite runs it on lavapipe, so it
//! cannot rot).

mod correctness;
mod timing;
mod write;

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Context;
use serde::Serialize;

use leakless::{BackendChoice, Gpu, GpuOptions, TuningChoice};

#[derive(clap::Args)]
pub struct GpuReportArgs {
    /// Folder for gpu-report.md and gpu-report.json (made if missing).
    #[arg(long)]
    out: PathBuf,
    /// Small sizes and few paths: the whole matrix in under a minute on lavapipe.
    #[arg(long)]
    quick: bool,
    /// Instead of a report: render the correctness fixtures (on a CPU device's compute
    /// backend) into tests/fixtures/gpu-report/.
    #[arg(long)]
    make_fixtures: bool,
}

/// What the report holds (the JSON, and the Markdown made from it).
#[derive(Serialize, Default)]
pub struct Report {
    pub quick: bool,
    pub info: String,
    pub tuning: Option<leakless::DeviceTuning>,
    pub validation: bool,
    pub correctness: Vec<correctness::Check>,
    pub frames: Vec<timing::FrameRow>,
    pub rays: Vec<timing::RayRow>,
    pub branching: Vec<timing::FrameRow>,
    /// The sweep's frame with its view samples rasterised, then found by rays (`--primary`).
    pub primary: Vec<timing::FrameRow>,
    pub tuning_sweep: Vec<timing::FrameRow>,
    /// Sections that failed, with their error (the others still ran).
    pub failures: Vec<String>,
    pub seconds: f64,
}

/// One section of the report: it adds its rows to the report.
type Section<'a> = dyn Fn(&mut Report) -> anyhow::Result<()> + 'a;

/// The matrix's sizes.
pub struct Matrix {
    pub sizes: Vec<(u32, u32)>,
    pub paths: Vec<u32>,
    pub scenes: Vec<&'static str>,
    pub ray_size: u32,
    /// Size and paths of the branching and tuning sweeps.
    pub sweep: ((u32, u32), u32),
    /// Validation on in the timed sections too (`--quick`: every code path checked; a full
    /// run times without the layers).
    pub validate: bool,
}

impl Matrix {
    fn new(quick: bool) -> Matrix {
        if quick {
            Matrix {
                sizes: vec![(64, 36)],
                paths: vec![2_000],
                scenes: vec!["scenes/atrium.gltf"],
                ray_size: 64,
                sweep: ((64, 36), 2_000),
                validate: true,
            }
        } else {
            Matrix {
                sizes: vec![(1280, 720), (1920, 1080)],
                paths: vec![10_000, 50_000, 200_000],
                scenes: vec!["scenes/atrium.gltf", "scenes/doorway.gltf"],
                ray_size: 2048,
                sweep: ((1920, 1080), 200_000),
                validate: false,
            }
        }
    }
}

/// Opens the device, validation as asked.
pub fn open(validation: bool) -> leakless::Result<Gpu> {
    Ok(Gpu::new(&GpuOptions { validation: Some(validation), ray_tracing: true, window: None })?)
}

pub fn run(args: GpuReportArgs) -> anyhow::Result<()> {
    let root = repository_root()?;
    if args.make_fixtures {
        return correctness::make_fixtures(&root);
    }
    std::fs::create_dir_all(&args.out).with_context(|| format!("making {}", args.out.display()))?;
    let start = Instant::now();
    let matrix = Matrix::new(args.quick);
    let mut report = Report { quick: args.quick, ..Default::default() };
    report.info = crate::info::describe(BackendChoice::Auto, TuningChoice::Auto)?;
    print!("{}", report.info);
    let gpu = open(false)?;
    report.tuning = Some(leakless::DeviceTuning::choose(gpu.report(), TuningChoice::Auto));
    drop(gpu);
    let save = |report: &mut Report| -> anyhow::Result<()> {
        report.seconds = start.elapsed().as_secs_f64();
        write::write(report, &args.out)
    };
    save(&mut report)?;

    let sections: [(&str, &Section); 4] = [
        ("correctness", &|r| correctness::run(r, &root)),
        ("frames", &|r| timing::frames(r, &root, &matrix)),
        ("rays", &|r| timing::rays(r, &root, &matrix)),
        ("sweeps", &|r| timing::sweeps(r, &root, &matrix)),
    ];
    for (name, section) in sections {
        println!("[{:6.1} s] {name}", start.elapsed().as_secs_f64());
        if let Err(e) = section(&mut report) {
            eprintln!("gpu-report: {name} failed: {e:#}");
            report.failures.push(format!("{name}: {e:#}"));
        }
        save(&mut report)?;
    }
    println!("[{:6.1} s] wrote {}", start.elapsed().as_secs_f64(), args.out.join("gpu-report.md").display());
    if !report.failures.is_empty() {
        anyhow::bail!("{} section(s) failed: {}", report.failures.len(), report.failures.join("; "));
    }
    if let Some(bad) = report.correctness.iter().find(|c| !c.passed) {
        anyhow::bail!("correctness: {} differs from its lavapipe render ({})", bad.scene, bad.verdict);
    }
    Ok(())
}

/// The repository's root (the scenes and fixtures are found from there): the working
/// directory when it holds `scenes/`, else the one the binary was built in.
fn repository_root() -> anyhow::Result<PathBuf> {
    let here = std::env::current_dir()?;
    if here.join("scenes").is_dir() {
        return Ok(here);
    }
    let built = Path::new(env!("CARGO_MANIFEST_DIR"));
    if built.join("scenes").is_dir() {
        return Ok(built.to_path_buf());
    }
    anyhow::bail!("run gpu-report from the repository's root (no scenes/ in {})", here.display())
}
