//! `leakless chart --series`: convergence — error against wall time while each method
//! accumulates, and the equal-time comparison at 1 s and at the budget.

use std::time::Duration;

use anyhow::Context;
use leakless::{Backend, BackendChoice, Method, Scene};
use leakless_measure::chart::series::{
    measure_series, write_series_csv, SceneSeries, SeriesConfig, SERIES_METHODS, SHADED_FRACTION,
};
use leakless_measure::chart::series_plot::{plot_series, SeriesMetric};
use leakless_measure::chart::{drawing, file_stem};

use crate::chart::ChartArgs;

pub fn run(args: &ChartArgs) -> anyhow::Result<()> {
    drawing::check_size(args.chart_size)?;
    let defaults = SeriesConfig::default();
    let budget = args.budget.unwrap_or(defaults.budget.as_secs_f64());
    if !(budget.is_finite() && budget > 0.0 && budget <= 3600.0) {
        anyhow::bail!("--budget {budget} must be within (0, 3600] seconds");
    }
    if !(1..=100).contains(&args.repeats) {
        anyhow::bail!("--repeats {} must be within 1..=100", args.repeats);
    }
    let frame_paths = args.frame_paths.unwrap_or(defaults.paths);
    if frame_paths == 0 {
        anyhow::bail!("--frame-paths 0: a photon frame must trace at least one light path");
    }
    let truth_frames = args.truth_frames.unwrap_or(defaults.truth_frames);
    if truth_frames == 0 || args.ref_spp < truth_frames {
        anyhow::bail!("--truth-frames {truth_frames} must be within 1..=--ref-spp ({})", args.ref_spp);
    }
    let radius = match args.radius.as_deref() {
        None => None,
        Some(&[r]) if r.is_finite() && r > 0.0 => Some(r),
        Some(&[r]) => anyhow::bail!("--radius {r} must be a positive length"),
        Some(_) => anyhow::bail!("--radius: a series starts from one radius, not several"),
    };
    let backend = match args.backends.as_deref() {
        None => BackendChoice::Auto,
        Some(&[Backend::RayQuery]) => BackendChoice::RayQuery,
        Some(&[Backend::Compute]) => BackendChoice::Compute,
        Some(_) => anyhow::bail!("--backends: a series runs on one backend, not several"),
    };
    if let Some(dir) = args.out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let kernel_photons = match args.kernel_photons.as_deref() {
        None => leakless::splatting::DEFAULT_KERNEL_PHOTONS,
        Some(&[k]) => k,
        Some(_) => anyhow::bail!("--kernel-photons: a series starts from one count, not several"),
    };
    let methods = args.methods.clone().unwrap_or_else(|| SERIES_METHODS.to_vec());
    if let Some(m) = methods.iter().find(|m| !SERIES_METHODS.contains(m)) {
        anyhow::bail!("--methods: a series runs splat, leakless and reference, not {}", m.name());
    }
    let config = SeriesConfig {
        width: args.size.0,
        height: args.size.1,
        backend,
        paths: frame_paths,
        radius,
        kernel_photons,
        methods,
        max_bounces: args.max_bounces,
        seed: args.seed,
        budget: Duration::from_secs_f64(budget),
        repeats: args.repeats,
        truth_frames,
        truth_spp: args.ref_spp / truth_frames,
    };
    // A compute-only series opens the device as `render --backend compute` does.
    let ray_tracing = backend.wants_ray_queries();
    let open = || Ok(leakless::Gpu::new(&leakless::GpuOptions { validation: None, ray_tracing, window: None })?);
    for path in &args.scenes {
        let scene = Scene::load(path).with_context(|| format!("loading {}", path.display()))?;
        let series = measure_series(&open, &scene, &config, &mut |what| eprintln!("{}: {what}", scene.name))
            .with_context(|| format!("charting {}", path.display()))?;
        print_table(&series, budget * 1e3);
        let base = format!("{}-{}-series", args.out.display(), file_stem(&series.scene));
        let csv = std::path::PathBuf::from(format!("{base}.csv"));
        write_series_csv(&series, &csv)?;
        println!("wrote {}", csv.display());
        for metric in SeriesMetric::ALL {
            let (svg, png) =
                (format!("{base}-{}.svg", metric.file_suffix()), format!("{base}-{}.png", metric.file_suffix()));
            plot_series(&series, metric, svg.as_ref(), png.as_ref(), args.chart_size)?;
            println!("wrote {svg}, {png}");
        }
    }
    Ok(())
}

fn print_table(s: &SceneSeries, budget_ms: f64) {
    println!(
        "{} ({}x{}, photon batches of {} paths from {}, ground truth {} frames x {} spp in {:.1} s; \
         errors at exactly each time, interpolated on log-log axes between the checkpoints around it; \
         shaded: the relMSE over the pixels at most {:.0}% of the ground truth's mean):",
        s.scene,
        s.width,
        s.height,
        s.paths,
        s.radius_label(),
        s.truth_frames,
        s.truth_spp,
        s.truth_ms / 1e3,
        100.0 * SHADED_FRACTION
    );
    println!(
        "{:>8} {:<10} {:>8} {:>10} {:>10} {:>9} {:>8}",
        "time", "method", "frames", "relMSE", "shaded", "HDR-FLIP", "flicker"
    );
    // 1 s, then the budget (once when they are the same).
    let times = if budget_ms == 1000.0 { vec![1000.0] } else { vec![1000.0, budget_ms] };
    for t in times {
        let time = seconds_label(t / 1e3);
        for m in SERIES_METHODS.into_iter().filter(|m| s.points.iter().any(|p| p.method == *m)) {
            let Some(e) = s.at(m, t) else {
                println!("{time:>8} {:<10} (the series does not bracket this time)", m.name());
                continue;
            };
            let flicker = s.points.iter().find(|p| p.method == m).and_then(|p| p.flicker);
            println!(
                "{time:>8} {:<10} {:>7}+ {:>10.5} {:>10.5} {:>9.4} {:>8}",
                m.name(),
                e.frames,
                e.relmse.unwrap_or(f64::NAN),
                e.shaded_relmse.unwrap_or(f64::NAN),
                e.flip,
                flicker.map_or("-".into(), |f| format!("{f:.4}"))
            );
        }
        if let (Some(ours), Some(reference)) = (s.at(Method::LeakLess, t), s.at(Method::Reference, t)) {
            let ratio = |a: Option<f64>, b: Option<f64>| a.unwrap_or(f64::NAN) / b.unwrap_or(f64::NAN);
            println!(
                "{:>8} leakless / reference: relMSE {:.2}x, shaded relMSE {:.2}x, HDR-FLIP {:.2}x",
                "",
                ratio(ours.relmse, reference.relmse),
                ratio(ours.shaded_relmse, reference.shaded_relmse),
                ours.flip / reference.flip
            );
        }
    }
}

/// A time in seconds as the table shows it: "1s", "10s", "0.5s" (a budget below a second
/// printed as "0s" before).
fn seconds_label(seconds: f64) -> String {
    let text = format!("{seconds:.3}");
    let text = text.trim_end_matches('0').trim_end_matches('.');
    format!("{text}s")
}

#[cfg(test)]
mod tests {
    use super::seconds_label;

    #[test]
    fn times_below_a_second_keep_their_digits() {
        assert_eq!([seconds_label(1.0), seconds_label(10.0), seconds_label(0.5)], ["1s", "10s", "0.5s"]);
        assert_eq!(seconds_label(0.125), "0.125s");
    }
}
