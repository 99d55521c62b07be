//! `leakless chart` end to end at a tiny size: measure, CSV, SVG and PNG charts. The metric
//! functions have exact unit tests in `src/chart/metrics.rs`.

use crate::common;

use std::path::Path;

use leakless::chart::{self, plot::Metric, ChartConfig, Radii, CSV_COLUMNS};
use leakless::{Backend, Gpu, GpuOptions};

#[test]
fn chart_smoke_compute_backend() {
    // Skips (loudly) without a device; the measurement opens its own devices.
    if common::gpu_with(false).is_none() {
        return;
    }
    let validation = std::env::var("LEAKLESS_VALIDATION").map_or(true, |v| v != "0");
    let open = |ray_tracing: bool| {
        Gpu::new(&GpuOptions { validation: Some(validation), ray_tracing, window: None }).map_err(Into::into)
    };
    let scene = common::scene("scenes/cornell-box.gltf");
    let method = *chart::default_methods().last().expect("the splat method at least");
    let config = ChartConfig {
        width: 32,
        height: 24,
        ref_spp: 64,
        methods: vec![method],
        paths: vec![2000],
        radii: Radii::Auto(vec![1.0, 2.0]),
        backends: vec![Backend::Compute],
        ..Default::default()
    };
    assert_eq!(config.renders_per_scene(1), 3);
    let mut reports = Vec::new();
    let measured = chart::measure_with_progress(&open, &scene, &config, &mut |p| reports.push((p.done, p.total)))
        .expect("measure");
    assert_eq!(reports.last(), Some(&(3, 3)), "progress ends at every render done: {reports:?}");
    assert!(reports.windows(2).all(|w| w[0].0 <= w[1].0), "progress never goes back: {reports:?}");

    assert_eq!(measured.points.len(), 2);
    assert!(measured.covered_pixels > 32 * 24 / 2 && measured.covered_pixels <= 32 * 24, "{}", measured.covered_pixels);
    assert!(measured.dark_pixels <= measured.covered_pixels);
    assert!(measured.reference_mean > 0.0);
    let auto = measured.auto_radius;
    for (p, scale) in measured.points.iter().zip([1.0, 2.0]) {
        assert_eq!((p.method, p.backend, p.paths), (method, Backend::Compute, Some(2000)));
        let r = p.radius.expect("a splat method's radius");
        assert!((r - scale * auto).abs() <= 1e-6 * auto, "radius {r} vs {scale} × {auto}");
        assert!(p.frame_ms.is_finite() && p.frame_ms > 0.0, "{p:?}");
        for e in [p.errors.relmse, p.errors.rmse] {
            let e = e.expect("defined over the whole image");
            assert!(e.is_finite() && e > 0.0, "{p:?}");
        }
        assert!(p.photons.unwrap() > 0 && p.candidate_tests.unwrap() > 0, "{p:?}");
    }

    let prefix = Path::new(env!("CARGO_TARGET_TMPDIR")).join("chart-smoke/cb");
    let _ = std::fs::remove_dir_all(prefix.parent().unwrap());
    let written = chart::write_outputs(&measured, &prefix, (400, 300)).expect("write outputs");
    assert_eq!(written.len(), 1 + 2 * Metric::ALL.len());
    for path in &written {
        let size = std::fs::metadata(path).unwrap_or_else(|e| panic!("{}: {e}", path.display())).len();
        assert!(size > 100, "{} has {size} bytes", path.display());
    }

    let csv = std::fs::read_to_string(prefix.with_file_name("cb-cornell-box.csv")).expect("the CSV");
    let rows: Vec<Vec<&str>> = csv.lines().map(|l| l.split(',').collect()).collect();
    assert_eq!(rows[0], CSV_COLUMNS);
    assert_eq!(rows.len(), 3, "{csv}");
    let col = |name| CSV_COLUMNS.iter().position(|c| *c == name).unwrap();
    for row in &rows[1..] {
        assert_eq!(row.len(), CSV_COLUMNS.len(), "{row:?}");
        assert_eq!(
            (row[col("scene")], row[col("method")], row[col("backend")], row[col("paths")]),
            ("cornell-box", method.name(), "compute", "2000")
        );
        for name in ["radius", "frame_ms", "relmse", "rmse"] {
            let v: f64 = row[col(name)].parse().unwrap_or_else(|e| panic!("{name} {:?}: {e}", row[col(name)]));
            assert!(v.is_finite() && v > 0.0, "{name} = {v}");
        }
        assert!(row[col("photons")].parse::<u32>().unwrap() > 0);
    }

    let png = prefix.with_file_name("cb-cornell-box-relmse.png");
    assert_eq!(image::image_dimensions(&png).expect("a PNG"), (400, 300));
    let pixels = image::open(&png).expect("decodes").to_rgb8();
    let non_white = pixels.pixels().filter(|p| p.0 != [255, 255, 255]).count();
    assert!(non_white > 2000, "something is drawn: {non_white} non-white pixels");
    let svg = std::fs::read_to_string(prefix.with_file_name("cb-cornell-box-relmse.svg")).expect("the SVG");
    assert!(svg.starts_with("<svg") && svg.contains("width=\"400\"") && svg.contains("relMSE"), "{}", &svg[..200]);
    assert!(svg.contains(&format!("{} (compute)", method.name())), "the legend names the series");
}

#[test]
fn chart_rejects_bad_configs() {
    let scene = common::scene("scenes/cornell-box.gltf");
    let no_gpu = |_: bool| -> leakless::Result<Gpu> { panic!("a bad config must fail before opening a device") };
    let bad = |config: ChartConfig| {
        let e = chart::measure(&no_gpu, &scene, &config).expect_err("refused").to_string();
        assert!(e.starts_with("invalid setting"), "{e}");
        e
    };
    assert!(bad(ChartConfig { paths: vec![], ..Default::default() }).contains("--paths"));
    assert!(bad(ChartConfig { radii: Radii::Absolute(vec![-1.0]), ..Default::default() }).contains("--radius"));
    assert!(bad(ChartConfig { methods: vec![], ..Default::default() }).contains("method"));
    assert!(bad(ChartConfig { methods: vec![leakless::Method::Reference], ..Default::default() }).contains("reference"));
    assert!(bad(ChartConfig { ref_spp: 0, ..Default::default() }).contains("--ref-spp"));
}

#[test]
fn chart_command_writes_every_file_and_fails_in_one_line() {
    let exe = env!("CARGO_BIN_EXE_leakless");
    let run = |args: &[&str]| {
        let out = std::process::Command::new(exe).args(args).current_dir(common::root()).output().expect("runs");
        (
            out.status.success(),
            String::from_utf8_lossy(&out.stdout).into_owned(),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        )
    };
    let (ok, _, err) = run(&["chart", "scenes/cornell-box.gltf", "--out", "/tmp/x", "--paths", "0"]);
    assert!(!ok && err.trim().lines().count() == 1 && err.contains("--paths"), "{err}");
    let (ok, _, err) = run(&["chart", "scenes/cornell-box.gltf", "--series", "--out", "/tmp/x", "--frame-paths", "0"]);
    assert!(!ok && err.trim().lines().count() == 1 && err.contains("--frame-paths 0"), "{err}");
    // A flag of the other mode is refused rather than ignored (a series once ran at the
    // automatic radius whatever --radius said).
    let (ok, _, err) = run(&["chart", "scenes/cornell-box.gltf", "--series", "--out", "/tmp/x", "--paths", "5k"]);
    assert!(!ok && err.trim().lines().count() == 1 && err.contains("--paths applies to the grid"), "{err}");
    let (ok, _, err) = run(&["chart", "scenes/cornell-box.gltf", "--out", "/tmp/x", "--budget", "5"]);
    assert!(!ok && err.trim().lines().count() == 1 && err.contains("--budget applies to --series only"), "{err}");
    let (ok, _, err) = run(&["chart", "scenes/cornell-box.gltf", "--series", "--out", "/tmp/x", "--radius", "0.1,0.2"]);
    assert!(!ok && err.trim().lines().count() == 1 && err.contains("one radius"), "{err}");

    if common::gpu_with(false).is_none() {
        return;
    }
    let prefix = Path::new(env!("CARGO_TARGET_TMPDIR")).join("chart-cli/run");
    let _ = std::fs::remove_dir_all(prefix.parent().unwrap());
    let prefix_arg = prefix.to_str().unwrap();
    #[rustfmt::skip]
    let args = ["chart", "scenes/cornell-box.gltf", "--out", prefix_arg, "--size", "16x12", "--ref-spp", "4",
        "--paths", "1k", "--radius-scale", "1", "--methods", "splat", "--backends", "compute"];
    let (ok, out, err) = run(&args);
    assert!(ok, "{out}\n{err}");
    assert!(out.contains("CPU time") || !out.contains("llvmpipe"), "lavapipe times are CPU times: {out}");
    let wrote: Vec<&str> = out.lines().filter_map(|l| l.strip_prefix("wrote ")).collect();
    assert_eq!(wrote.len(), 1 + 2 * Metric::ALL.len(), "{out}");
    for path in wrote {
        assert!(Path::new(path).is_file(), "{path}");
    }
    let csv = std::fs::read_to_string(prefix.with_file_name("run-cornell-box.csv")).expect("the CSV");
    assert_eq!(csv.lines().count(), 2, "{csv}");
    assert!(csv.lines().nth(1).unwrap().starts_with("cornell-box,splat,compute,1000,"), "{csv}");
}
