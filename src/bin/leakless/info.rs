//! `leakless info`: devices, the one used, and which trace backend `auto` picks and why.

use anyhow::{bail, Context};
use leakless::{BackendChoice, Gpu, GpuOptions};

#[derive(clap::Args)]
pub struct InfoArgs {
    /// Which backend to report on (`auto` shows what a render would use).
    #[arg(long, default_value = "auto", value_parser = crate::parse_backend)]
    backend: BackendChoice,
}

pub fn run(args: InfoArgs) -> anyhow::Result<()> {
    let reports = Gpu::list_devices().context("listing Vulkan devices")?;
    if reports.is_empty() {
        bail!("the Vulkan loader sees no device (install mesa-vulkan-drivers: tools/install-deps)");
    }
    let gpu =
        Gpu::new(&GpuOptions { validation: Some(false), ray_tracing: args.backend.wants_ray_queries(), window: None });
    let chosen = gpu.as_ref().ok().map(|g| g.report().index);
    for r in &reports {
        let mark = if Some(r.index) == chosen { "*" } else { " " };
        let (major, minor, patch) = r.api_version;
        println!(
            "{mark} device {}: {} ({:?}), Vulkan {major}.{minor}.{patch}, driver {}",
            r.index, r.name, r.device_type, r.driver
        );
        println!(
            "    ray queries: {}, acceleration structures: {}, subgroup size: {}, timestamp period: {} ns",
            yes(r.ray_query),
            yes(r.acceleration_structure),
            r.subgroup_size,
            r.timestamp_period_ns
        );
        if let Some(why) = &r.rejected {
            println!("    rejected: {why}");
        }
    }
    let gpu = gpu.context("opening a device")?;
    let r = gpu.report();
    println!("using device {} ({}); LEAKLESS_DEVICE=<index or name> picks another", r.index, r.name);
    match args.backend.resolve(gpu.capabilities(), r.device_type, &r.name) {
        Ok(resolved) => {
            println!("trace backend ({}): {} ({})", args.backend.name(), resolved.backend.name(), resolved.why)
        }
        Err(e) => println!("trace backend ({}): none: {e}", args.backend.name()),
    }
    Ok(())
}

fn yes(b: bool) -> &'static str {
    if b {
        "yes"
    } else {
        "no"
    }
}
