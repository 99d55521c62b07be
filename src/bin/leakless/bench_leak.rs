//! `leakless bench leak`: what leak removal costs against the leaky splat it corrects, per
//! scene, in one process; and how fast its tracing passes run against the device's own limits.

use leakless::passes::disk_smooth::DISK_SMOOTH;
use leakless::passes::names::group;
use leakless::passes::photon_clearance::PHOTON_CLEARANCE;
use leakless::passes::sample_clearance::SAMPLE_CLEARANCE;
use std::path::PathBuf;

use anyhow::Context;
use leakless::{Backend, BackendChoice, Method, RenderSettings, Scene, SplatSettings};
use leakless_measure::bench::{Measured, RayRate};

/// One scene's outcome, for the summary table.
struct Row {
    scene: String,
    splat_ms: f64,
    leakless_ms: f64,
    /// leakless / splat with the visible disk's extra time taken away: what the rest costs.
    without_disk: f64,
    every_pair_ms: f64,
    proven: f64,
    photon_rate: f64,
    photon_limit: Option<f64>,
    /// None where leakless's gather is too close to splat's to time the rays apart.
    visibility_rate: Option<f64>,
    occlusion_limit: Option<f64>,
}

pub fn run(
    scenes: &[PathBuf],
    (w, h): (u32, u32),
    paths: u32,
    radius: (Option<f32>, crate::options::FixedRadius),
    backend: BackendChoice,
    repeats: u32,
) -> anyhow::Result<()> {
    let open = || {
        Ok(leakless::Gpu::new(&leakless::GpuOptions {
            validation: None,
            ray_tracing: backend.wants_ray_queries(),
            window: None,
        })?)
    };
    let gpu = open()?;
    let report = gpu.report();
    let resolved = backend.resolve(gpu.capabilities(), report.device_type, &report.name)?;
    println!(
        "bench leak ({w}x{h}, {paths} paths, best of {repeats}) on {}, {} backend ({}); {}",
        report.name,
        resolved.backend.name(),
        resolved.why,
        leakless_measure::bench::timing_phrase(&gpu)
    );
    let mut rows = Vec::new();
    for path in scenes {
        let scene = Scene::load(path).with_context(|| format!("loading {}", path.display()))?;
        rows.push(one_scene(&gpu, &open, &scene, (w, h), paths, radius, backend, resolved.backend, repeats)?);
    }
    println!();
    println!(
        "{:<14} {:>9} {:>12} {:>9} {:>13} {:>17} {:>9} {:>22} {:>22}",
        "scene",
        "splat ms",
        "leakless ms",
        "ratio",
        "no-disk ratio",
        "every pair ratio",
        "proven",
        "photons Mrays/s (lim)",
        "visibility Mrays/s (lim)"
    );
    let limit = |x: Option<f64>| x.map_or("-".to_string(), |v| format!("{v:.2}"));
    for r in &rows {
        println!(
            "{:<14} {:>9.1} {:>12.1} {:>8.2}x {:>12.2}x {:>16.2}x {:>8.1}% {:>13.2} ({:>6}) {:>13} ({:>6})",
            r.scene,
            r.splat_ms,
            r.leakless_ms,
            r.leakless_ms / r.splat_ms,
            r.without_disk,
            r.every_pair_ms / r.splat_ms,
            100.0 * r.proven,
            r.photon_rate,
            limit(r.photon_limit),
            limit(r.visibility_rate),
            limit(r.occlusion_limit)
        );
    }
    println!(
        "(no-disk ratio: leakless / splat with the visible disk's extra time taken away; lim: the device's incoherent closest-hit / occlusion rate from `bench rays` on the same scene and backend)"
    );
    Ok(())
}

#[allow(clippy::too_many_arguments)]
fn one_scene(
    gpu: &leakless::Gpu,
    open: &dyn Fn() -> leakless::Result<leakless::Gpu>,
    scene: &Scene,
    (w, h): (u32, u32),
    paths: u32,
    (radius, fixed): (Option<f32>, crate::options::FixedRadius),
    backend: BackendChoice,
    resolved: Backend,
    repeats: u32,
) -> anyhow::Result<Row> {
    let radius = radius.or(fixed.radius(scene));
    let settings = |method, trivial_accept, prove_clear| RenderSettings {
        width: w,
        height: h,
        backend,
        method,
        splat: SplatSettings { paths, radius, trivial_accept, prove_clear, ..Default::default() },
        ..Default::default()
    };
    let runs = [
        ("splat", settings(Method::Splat, true, true)),
        ("leakless-capped", settings(Method::LeakLessCapped, false, true)),
        ("leakless", settings(Method::LeakLess, true, true)),
        ("leakless, every pair traced", settings(Method::LeakLess, true, false)),
        ("leakless, no trivial accept", settings(Method::LeakLess, false, true)),
    ];
    let rows = runs
        .iter()
        .map(|(label, s)| Measured::best_of(open, scene, label, s, repeats))
        .collect::<leakless::Result<Vec<_>>>()?;
    println!("\n{}:", scene.name);
    println!(
        "{:<28} {:>8} {:>8} {:>8} {:>9} {:>8} {:>8} {:>10} {:>7} {:>10} {:>9} {:>7}",
        "method",
        "frame ms",
        "photons",
        "splat",
        "clearance",
        "disk",
        "gather",
        "vis. tests",
        "proven",
        "rays",
        "culled",
        "leaked"
    );
    for r in &rows {
        let s = r.stats();
        println!(
            "{:<28} {:>8.1} {:>8.1} {:>8.1} {:>9.1} {:>8.1} {:>8.1} {:>10} {:>6.1}% {:>10} {:>9} {:>6.2}%",
            r.label,
            r.frame_ms(),
            r.photons_ms(),
            r.splat_ms(),
            r.pass_ms(PHOTON_CLEARANCE.name),
            r.group_ms(group::VISIBLE_DISK),
            r.gather_ms(),
            s.visibility_tests,
            100.0 * s.proven_clear as f64 / s.visibility_tests.max(1) as f64,
            s.visibility_rays,
            s.leaks_culled,
            100.0 * s.leaked_energy_fraction
        );
    }
    let (splat, capped, ours, every, no_ta) = (&rows[0], &rows[1], &rows[2], &rows[3], &rows[4]);
    let identical =
        |a: &Measured, b: &Measured| a.frame.radiance == b.frame.radiance && a.frame.leaked == b.frame.leaked;
    println!(
        "frame time: leakless / splat = {:.2}, leakless-capped / splat = {:.2}, every pair traced / splat = {:.2}",
        ours.frame_ms() / splat.frame_ms(),
        capped.frame_ms() / splat.frame_ms(),
        every.frame_ms() / splat.frame_ms()
    );
    println!(
        "images identical: proofs vs every pair traced {}, trivial accept vs none {}",
        yes(identical(ours, every)),
        yes(identical(ours, no_ta))
    );
    // The visibility rays' share of the gather: leakless's gather beyond splat's (the same
    // gather without visibility), over the rays it traced. Where that is under a tenth of
    // splat's gather (a GPU tracing few rays), it is within the two runs' timing noise, and
    // a rate from it would be noise (one H200 run printed 68510% of the device's rate).
    let vis_ms = ours.gather_ms() - splat.gather_ms();
    let vis_rate = (vis_ms > 0.1 * splat.gather_ms() && vis_ms > 0.0)
        .then(|| ours.stats().visibility_rays as f64 / (vis_ms * 1e3));
    let photon_rate = ours.stats().photon_rays as f64 / (ours.photons_ms().max(1e-3) * 1e3);
    let rates = leakless_measure::bench::rays(gpu, scene, w, h, repeats)?;
    let limit = |query: &str| find(&rates, resolved, "incoherent", query);
    let (closest, occluded) = (limit("closest"), limit("occluded"));
    let pct = |rate: f64, lim: Option<f64>| {
        lim.map_or(String::new(), |l| format!(" = {:.0}% of the device's {l:.2}", 100.0 * rate / l))
    };
    println!(
        "photon pass: {} rays in {:.1} ms = {photon_rate:.2} Mrays/s{}",
        ours.stats().photon_rays,
        ours.photons_ms(),
        pct(photon_rate, closest)
    );
    match vis_rate {
        Some(rate) => println!(
            "visibility: {} rays in {vis_ms:.1} ms of gather beyond splat's = {rate:.2} Mrays/s{}",
            ours.stats().visibility_rays,
            pct(rate, occluded)
        ),
        None => println!(
            "visibility: {} rays; leakless's gather is within a tenth of splat's ({vis_ms:+.2} ms), too close to time the rays apart",
            ours.stats().visibility_rays
        ),
    }
    let disk_ms = ours.group_ms(group::VISIBLE_DISK);
    println!(
        "visible disk (the kernel's mass where the surface is, seen): {disk_ms:.1} ms = {:.0}% of the leakless frame, of it {:.1} ms smoothing it over the surfaces",
        100.0 * disk_ms / ours.frame_ms(),
        ours.pass_ms(DISK_SMOOTH.name)
    );
    let parts = removal_parts(splat, ours);
    let extra = ours.frame_ms() - splat.frame_ms();
    let named: f64 = parts.iter().map(|(_, ms)| ms).sum();
    let listed: Vec<String> = parts.iter().map(|(name, ms)| format!("{name} {ms:+.1}")).collect();
    let without_disk = (ours.frame_ms() - parts[1].1) / splat.frame_ms();
    println!(
        "leak removal: {extra:+.1} ms over splat's frame ({:.0}% of it): {}, the rest {:+.1}; with the visible disk free, leakless / splat would be {without_disk:.2}",
        100.0 * extra / splat.frame_ms(),
        listed.join(", "),
        extra - named
    );
    Ok(Row {
        scene: scene.name.clone(),
        splat_ms: splat.frame_ms(),
        leakless_ms: ours.frame_ms(),
        without_disk,
        every_pair_ms: every.frame_ms(),
        proven: ours.stats().proven_clear as f64 / ours.stats().visibility_tests.max(1) as f64,
        photon_rate,
        photon_limit: closest,
        visibility_rate: vis_rate,
        occlusion_limit: occluded,
    })
}

/// Where leak removal's time goes: each part's time in the leakless frame less its time in the
/// splat frame (splat runs the same passes with visibility and the visible disk off), in ms.
/// The visible disk is second: `without_disk` takes it away.
fn removal_parts(splat: &Measured, ours: &Measured) -> [(&'static str, f64); 5] {
    let more = |f: &dyn Fn(&Measured) -> f64| f(ours) - f(splat);
    [
        ("gather (visibility rays, grown disks)", more(&|m| m.gather_ms())),
        ("visible disk", more(&|m| m.group_ms(group::VISIBLE_DISK))),
        ("photon clearance", more(&|m| m.pass_ms(PHOTON_CLEARANCE.name))),
        ("sample clearance", more(&|m| m.pass_ms(SAMPLE_CLEARANCE.name))),
        ("splat (grown partial disks)", more(&|m| m.splat_ms())),
    ]
}

fn find(rates: &[RayRate], backend: Backend, set: &str, query: &str) -> Option<f64> {
    rates.iter().find(|r| r.backend == backend && r.set == set && r.query == query).map(|r| r.mrays_per_s())
}

fn yes(b: bool) -> &'static str {
    if b {
        "yes (bit for bit)"
    } else {
        "NO"
    }
}
