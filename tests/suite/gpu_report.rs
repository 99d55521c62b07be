//! `tools/gpu-report --quick` and `tools/gpu-benches --quick` run end to end on this device,
//! so the command a GPU session runs in its one call cannot rot: every section, every tuning
//! variant's pipelines (with validation on), and the correctness fixtures, which on the device
//! that made them must match bit for bit; then every bench step.

use std::path::PathBuf;
use std::process::{Command, Output};

use crate::common;

/// Runs `tools/<tool> OUT --quick` with this build's binary; returns OUT and what it printed.
fn quick(tool: &str) -> (PathBuf, Output) {
    let out = common::tmp_path(&format!("{tool}-quick"));
    let _ = std::fs::remove_dir_all(&out);
    let run = Command::new(common::root().join("tools").join(tool))
        .arg(&out)
        .arg("--quick")
        .env("LEAKLESS_BIN", env!("CARGO_BIN_EXE_leakless"))
        .current_dir(common::root())
        .output()
        .unwrap_or_else(|e| panic!("run tools/{tool}: {e}"));
    (out, run)
}

#[test]
fn the_quick_gpu_report_runs_end_to_end() {
    if common::gpu().is_none() {
        return;
    }
    let (out, run) = quick("gpu-report");
    let (stdout, stderr) = (String::from_utf8_lossy(&run.stdout), String::from_utf8_lossy(&run.stderr));
    assert!(run.status.success(), "tools/gpu-report failed:\n{stdout}\n{stderr}");
    assert!(!stderr.contains("validation error"), "{stderr}");

    let md = std::fs::read_to_string(out.join("gpu-report.md")).expect("gpu-report.md");
    for section in ["## Correctness", "## Frames", "## Rays", "## Branching factor", "## The device tuning's choices"] {
        assert!(md.contains(section), "gpu-report.md lacks {section:?}:\n{md}");
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("gpu-report.json")).expect("json")).expect("valid json");
    assert_eq!(json["failures"].as_array().map(Vec::len), Some(0), "{}", json["failures"]);
    assert!(json["validation"].as_bool().unwrap(), "the correctness renders run with validation on");

    // Every shipped scene checked, each passing; on the fixtures' own device, bit for bit.
    let checks = json["correctness"].as_array().expect("correctness");
    let scenes = std::fs::read_dir(common::root().join("scenes"))
        .unwrap()
        .filter(|e| e.as_ref().unwrap().path().extension().is_some_and(|x| x == "gltf"))
        .count();
    assert_eq!(checks.len(), scenes);
    let fixture = leakless::output::exr::read(&common::root().join("tests/fixtures/gpu-report/cornell-box.exr"))
        .expect("fixture");
    let gpu = common::gpu().unwrap();
    let same_device = fixture.attribute("leakless.device") == Some(gpu.report().name.as_str())
        && fixture.attribute("leakless.driver") == Some(gpu.report().driver.as_str());
    for c in checks {
        assert!(c["passed"].as_bool().unwrap(), "{c}");
        if same_device {
            let verdict = c["verdict"].as_str().unwrap();
            assert!(
                verdict == "bit-identical" || verdict.starts_with("black"),
                "{c}: images changed on the fixtures' device (leakless gpu-report --make-fixtures records them anew)"
            );
        }
    }

    // The matrix: each method once, timed, counted; leakless traces visibility rays.
    let frames = json["frames"].as_array().expect("frames");
    let methods: Vec<&str> = frames.iter().map(|f| f["method"].as_str().unwrap()).collect();
    assert_eq!(methods, ["splat", "leakless-capped", "leakless"]);
    for f in frames {
        assert!(f["frame_ms"].as_f64().unwrap() > 0.0, "{f}");
        assert!(f["photons_stored"].as_u64().unwrap() > 0 && f["list_entries"].as_u64().unwrap() > 0, "{f}");
    }
    assert_eq!(frames[0]["visibility_rays"].as_u64(), Some(0), "splat traces no visibility ray");
    assert!(frames[2]["visibility_rays"].as_u64().unwrap() + frames[2]["proven_clear"].as_u64().unwrap() > 0);
    assert!(!json["rays"].as_array().unwrap().is_empty());
    assert_eq!(json["branching"].as_array().unwrap().len(), 3);
    // The view samples rasterised and by rays: the same photons, stored and listed.
    let primary = json["primary"].as_array().unwrap();
    assert_eq!(primary.len(), 2);
    assert_eq!(primary[1]["variant"].as_str(), Some("view samples: rays"));
    assert_eq!(primary[0]["photons_stored"], primary[1]["photons_stored"]);
    // The device's tuning and each choice changed alone (subgroup counters where the device has
    // them): the same photons and lists in every variant, but for the wide leaves' test, which
    // lists fewer photons (none that a sample gathers) and traces the same rays.
    let sweep = json["tuning_sweep"].as_array().unwrap();
    assert!(sweep.len() >= 8, "{}", sweep.len());
    let mut leaf_variants = 0;
    for v in sweep {
        let leaf = v["variant"].as_str().unwrap().starts_with("leaf samples tested");
        leaf_variants += leaf as u32;
        for counter in ["photons_stored", "list_entries", "candidate_tests", "visibility_rays", "proven_clear"] {
            if leaf && (counter == "list_entries" || counter == "candidate_tests") {
                let (got, all) = (v[counter].as_u64().unwrap(), sweep[0][counter].as_u64().unwrap());
                assert!(got <= all, "{counter} of {}: {got} above the device tuning's {all}", v["variant"]);
                continue;
            }
            assert_eq!(v[counter], sweep[0][counter], "{counter} of {} differs from the device tuning's", v["variant"]);
        }
    }
    assert_eq!(leaf_variants, 1, "one variant toggles the wide leaves' test");
}

/// `tools/gpu-benches --quick` runs end to end here too, so the benches that follow the report
/// in a GPU session's one call cannot rot: every step runs and exits 0, the reuse passes' share
/// is printed for both sequences, the frame budget's summary for its walk, and the scale figures
/// come back as a CSV and a chart. What it
/// checks is what the steps produce, never how fast: `--quick` runs them with no time cap (the
/// caps are for the GPU run, where one slow step must not take the others' results with it), so
/// a slow or busy machine passes as a fast one does.
#[test]
fn the_quick_gpu_benches_run_end_to_end() {
    if common::gpu().is_none() {
        return;
    }
    let (out, run) = quick("gpu-benches");
    let log = std::fs::read_to_string(out.join("benches.log")).expect("benches.log");
    assert!(run.status.success(), "tools/gpu-benches failed:\n{log}\n{}", String::from_utf8_lossy(&run.stderr));
    let steps = log.lines().filter(|l| l.starts_with("$ ")).count();
    let passed = log.lines().filter(|l| l.starts_with("[rc 0 in ")).count();
    assert_eq!((steps, passed), (7, 7), "every step runs and exits 0:\n{log}");
    assert_eq!(log.matches(", no cap (--quick)]").count(), 7, "--quick caps no step:\n{log}");
    assert_eq!(log.matches("% of the rest").count(), 2, "{log}");
    assert_eq!(log.matches("frame budget 16.7 ms: ").count(), 1, "{log}");
    let csv = std::fs::read_to_string(out.join("scale.csv")).expect("scale.csv");
    assert_eq!(csv.lines().count(), 1 + 2 * common::choices().len(), "{csv}");
    assert!(out.join("scale.svg").is_file() && out.join("scale.png").is_file());
}
