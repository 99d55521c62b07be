//! `leakless chart` end to end at a tiny size, through the command line: every file written,
//! bad flags refused in one line. The measuring itself is unit-tested in the binary
//! (`crates/measure/src/chart/tests.rs`), the metrics exactly in `metrics.rs` there.

use crate::common;

use std::path::Path;

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
    // The CSV, and an SVG and a PNG for each of the four metrics.
    assert_eq!(wrote.len(), 1 + 2 * 4, "{out}");
    for path in wrote {
        assert!(Path::new(path).is_file(), "{path}");
    }
    let csv = std::fs::read_to_string(prefix.with_file_name("run-cornell-box.csv")).expect("the CSV");
    assert_eq!(csv.lines().count(), 2, "{csv}");
    assert!(csv.lines().nth(1).unwrap().starts_with("cornell-box,splat,compute,1000,"), "{csv}");
}
