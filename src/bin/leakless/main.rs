//! The `leakless` command: render a scene, benchmark the trace backends, report the device.
//! Every subcommand drives the `leakless` library the same way the tests do.

mod bench;
mod bench_animation;
mod bench_flicker;
mod bench_leak;
mod bench_motion;
mod bench_scale;
mod chart;
mod chart_series;
mod gpu_report;
mod info;
mod options;
mod render;
mod sequence;
mod stability;
mod view;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(name = "leakless", version, about = "Diffuse global illumination by photon splatting, without light leaks")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a glTF scene to a layered EXR (and optionally a PNG and a stats file).
    Render(render::RenderArgs),
    /// Open the scene in a window: fly camera, keyboard toggles, overlay, captures (F12).
    View(view::ViewArgs),
    /// Measure: `bench rays SCENE` (rays per second per backend).
    #[command(subcommand)]
    Bench(bench::BenchCommand),
    /// Chart speed against accuracy: each method at several (paths, radius) settings on each
    /// backend, error against the path-traced reference over frame time (CSV, SVG, PNG).
    Chart(chart::ChartArgs),
    /// Where methods fail: each scene × method × backend against the reference (dark-room
    /// light, relMSE, RMSE, HDR-FLIP, NaN/Inf, flicker, frame time) as a Markdown report, a
    /// CSV and a chart of leaks against wall thickness.
    Stability(stability::StabilityArgs),
    /// Print the Vulkan devices, which one is used, what it can do, the trace backend and the
    /// device tuning.
    Info(info::InfoArgs),
    /// The standard matrix a GPU is judged by (device, correctness against lavapipe, per-pass
    /// times, rays, tuning sweeps) as gpu-report.md and gpu-report.json (tools/gpu-report).
    GpuReport(gpu_report::GpuReportArgs),
}

fn main() -> ExitCode {
    leakless::stderr_log::install();
    let result = match Cli::parse().command {
        Command::Render(args) => render::run(args),
        Command::View(args) => view::run(args),
        Command::Bench(cmd) => bench::run(cmd),
        Command::Chart(args) => chart::run(args),
        Command::Stability(args) => stability::run(args),
        Command::Info(args) => info::run(args),
        Command::GpuReport(args) => gpu_report::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // One line: the context chain joined, the way a user reads it. A lost device is
            // the whole story (where it was lost), whatever the command was doing.
            let line = match e.chain().find(|c| device_lost(*c)) {
                Some(lost) => lost.to_string(),
                None => format!("{e:#}"),
            };
            eprintln!("error: {}", line.replace('\n', " "));
            ExitCode::FAILURE
        }
    }
}

fn device_lost(e: &(dyn std::error::Error + 'static)) -> bool {
    use leakless_device::DeviceError;
    matches!(e.downcast_ref::<DeviceError>(), Some(DeviceError::DeviceLost { .. }))
        || matches!(
            e.downcast_ref::<leakless::RenderError>(),
            Some(leakless::RenderError::Device(DeviceError::DeviceLost { .. }))
        )
}

/// `WIDTHxHEIGHT`.
pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let bad = || format!("{s:?} is not WIDTHxHEIGHT");
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    Ok((w.trim().parse().map_err(|_| bad())?, h.trim().parse().map_err(|_| bad())?))
}

/// `auto|rayquery|compute`.
/// Opens the device the way a backend choice needs it (ray tracing unless `compute`).
pub fn open_gpu(backend: leakless::BackendChoice) -> anyhow::Result<leakless::Gpu> {
    use anyhow::Context;
    let options = leakless::GpuOptions { validation: None, ray_tracing: backend.wants_ray_queries(), window: None };
    leakless::Gpu::new(&options).context("opening the Vulkan device")
}
