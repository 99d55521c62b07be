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
    let why = match (args.backend, gpu.capabilities().ray_query) {
        (BackendChoice::Compute, _) => "compute (forced by --backend compute)",
        (_, true) => "rayquery (VK_KHR_ray_query and VK_KHR_acceleration_structure present)",
        (BackendChoice::RayQuery, false) => "none: --backend rayquery, but the device has no VK_KHR_ray_query",
        (BackendChoice::Auto, false) => "compute (no VK_KHR_ray_query: compute-shader BVH traversal)",
    };
    println!(
        "trace backend ({}): {why}",
        match args.backend {
            BackendChoice::Auto => "auto",
            BackendChoice::RayQuery => "rayquery",
            BackendChoice::Compute => "compute",
        }
    );
    Ok(())
}

fn yes(b: bool) -> &'static str {
    if b {
        "yes"
    } else {
        "no"
    }
}
