//! `leakless info`: devices, the one used, and which trace backend `auto` picks and why.

use anyhow::{bail, Context};
use leakless::{BackendChoice, Gpu, GpuOptions};

#[derive(clap::Args)]
pub struct InfoArgs {
    /// Which backend to report on (`auto` shows what a render would use).
    #[arg(long, default_value = "auto")]
    backend: BackendChoice,
    /// Which tuning to report on (`auto`: the device's own).
    #[arg(long, default_value = "auto")]
    tuning: leakless::TuningChoice,
}

pub fn run(args: InfoArgs) -> anyhow::Result<()> {
    print!("{}", describe(args.backend, args.tuning)?);
    Ok(())
}

/// What `leakless info` prints.
pub fn describe(backend: BackendChoice, tuning: leakless::TuningChoice) -> anyhow::Result<String> {
    use std::fmt::Write;
    let mut out = String::new();
    let reports = Gpu::list_devices().context("listing Vulkan devices")?;
    if reports.is_empty() {
        bail!("the Vulkan loader sees no device (install mesa-vulkan-drivers: tools/install-deps)");
    }
    let gpu = Gpu::new(&GpuOptions { validation: Some(false), ray_tracing: backend.wants_ray_queries(), window: None });
    let chosen = gpu.as_ref().ok().map(|g| g.report().index);
    for r in &reports {
        let mark = if Some(r.index) == chosen { "*" } else { " " };
        let (major, minor, patch) = r.api_version;
        writeln!(
            out,
            "{mark} device {}: {} ({:?}), Vulkan {major}.{minor}.{patch}, driver {}",
            r.index, r.name, r.device_type, r.driver
        )?;
        writeln!(
            out,
            "    vendor: {}, ray queries: {}, acceleration structures: {}, subgroup size: {} (ballot, arithmetic and shuffle: {}), timestamp period: {} ns",
            r.vendor(),
            yes(r.ray_query),
            yes(r.acceleration_structure),
            r.subgroup_size,
            yes(r.subgroup_arithmetic),
            r.timestamp_period_ns
        )?;
        if let Some(why) = &r.rejected {
            writeln!(out, "    rejected: {why}")?;
        }
    }
    let gpu = gpu.context("opening a device")?;
    let r = gpu.report();
    writeln!(out, "using device {} ({}); LEAKLESS_DEVICE=<index or name> picks another", r.index, r.name)?;
    match backend.resolve(gpu.capabilities(), r.device_type, &r.name) {
        Ok(resolved) => {
            writeln!(out, "trace backend ({}): {} ({})", backend.name(), resolved.backend.name(), resolved.why)?
        }
        Err(e) => writeln!(out, "trace backend ({}): none: {e}", backend.name())?,
    }
    let chosen = leakless::DeviceTuning::choose(r, tuning);
    writeln!(out, "tuning ({}): {}", tuning.name(), chosen.summary())?;
    Ok(out)
}

fn yes(b: bool) -> &'static str {
    if b {
        "yes"
    } else {
        "no"
    }
}
