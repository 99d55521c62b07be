//! The chart's measurement and outputs at a tiny size, on the local device (a binary's unit
//! tests: the measuring code lives in the CLI, not the renderer library).

use std::path::Path;

use leakless::{Backend, Gpu, GpuOptions, Scene};

use super::plot::Metric;
use super::{ChartConfig, Radii, CSV_COLUMNS};

fn scene() -> Scene {
    Scene::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cornell-box.gltf")).expect("the Cornell box")
}

/// A device as the tests open one: validation on unless LEAKLESS_VALIDATION=0.
fn open(ray_tracing: bool) -> leakless::Result<Gpu> {
    let validation = std::env::var("LEAKLESS_VALIDATION").map_or(true, |v| v != "0");
    Ok(Gpu::new(&GpuOptions { validation: Some(validation), ray_tracing, window: None })?)
}

/// No device: a loud skip, or a failure where one is required (CI).
fn no_device() {
    if std::env::var("LEAKLESS_REQUIRE_DEVICE").as_deref() == Ok("1") {
        panic!("LEAKLESS_REQUIRE_DEVICE=1 but no Vulkan device");
    }
    eprintln!("\n*** SKIPPED: no Vulkan device ***\n");
}

#[test]
fn chart_smoke_compute_backend() {
    // Skips (loudly) without a device; the measurement opens its own devices.
    if open(false).is_err() {
        return no_device();
    }
    let scene = scene();
    let method = *super::default_methods().last().expect("the splat method at least");
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
    let measured = super::measure_with_progress(&open, &scene, &config, &mut |p| reports.push((p.done, p.total)))
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

    let prefix = std::env::temp_dir().join(format!("leakless-chart-smoke-{}/cb", std::process::id()));
    let _ = std::fs::remove_dir_all(prefix.parent().unwrap());
    let written = super::write_outputs(&measured, &prefix, (400, 300)).expect("write outputs");
    assert_eq!(written.len(), 1 + 2 * Metric::ALL.len());
    for path in &written {
        let size = std::fs::metadata(path).unwrap_or_else(|e| panic!("{}: {e}", path.display())).len();
        assert!(size > 100, "{} has {size} bytes", path.display());
    }

    let csv = std::fs::read_to_string(prefix.with_file_name("cb-cornell-box.csv")).expect("the CSV");
    let rows: Vec<csv::StringRecord> = csv::ReaderBuilder::new()
        .has_headers(false)
        .from_reader(csv.as_bytes())
        .records()
        .collect::<Result<_, _>>()
        .expect("a CSV");
    assert_eq!(rows[0], CSV_COLUMNS[..]);
    assert_eq!(rows.len(), 3, "{csv}");
    let col = |name| CSV_COLUMNS.iter().position(|c| *c == name).unwrap();
    for row in &rows[1..] {
        assert_eq!(row.len(), CSV_COLUMNS.len(), "{row:?}");
        assert_eq!(
            (&row[col("scene")], &row[col("method")], &row[col("backend")], &row[col("paths")]),
            ("cornell-box", method.name(), "compute", "2000")
        );
        for name in ["radius", "frame_ms", "relmse", "rmse"] {
            let v: f64 = row[col(name)].parse().unwrap_or_else(|e| panic!("{name} {:?}: {e}", &row[col(name)]));
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
    // The outputs were read back: the run leaves nothing in the temporary directory.
    std::fs::remove_dir_all(prefix.parent().unwrap()).expect("remove the outputs");
}

#[test]
fn chart_rejects_bad_configs() {
    let scene = scene();
    let no_gpu = |_: bool| -> leakless::Result<Gpu> { panic!("a bad config must fail before opening a device") };
    let bad = |config: ChartConfig| {
        let e = super::measure_with_progress(&no_gpu, &scene, &config, &mut |_| {}).expect_err("refused").to_string();
        assert!(e.starts_with("invalid setting"), "{e}");
        e
    };
    assert!(bad(ChartConfig { paths: vec![], ..Default::default() }).contains("--paths"));
    assert!(bad(ChartConfig { radii: Radii::Absolute(vec![-1.0]), ..Default::default() }).contains("--radius"));
    assert!(bad(ChartConfig { methods: vec![], ..Default::default() }).contains("method"));
    assert!(bad(ChartConfig { methods: vec![leakless::Method::Reference], ..Default::default() }).contains("reference"));
    assert!(bad(ChartConfig { ref_spp: 0, ..Default::default() }).contains("--ref-spp"));
}
