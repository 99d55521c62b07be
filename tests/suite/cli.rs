//! The command line: bad input gives one clear line on stderr and a non-zero exit, never a
//! panic; a good render writes what it says.

use crate::common;

use std::process::{Command, Output};

fn leakless(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_leakless"));
    cmd.args(args).current_dir(common::root());
    for (k, v) in env {
        cmd.env(k, v);
    }
    cmd.output().expect("run leakless")
}

fn assert_one_line_error(out: &Output, needle: &str) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "expected failure, stderr: {stderr}");
    assert_eq!(out.status.code(), Some(1), "a clean error exit, not a panic (101): {stderr}");
    let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(errors.len(), 1, "exactly one error line: {stderr}");
    assert!(errors[0].contains(needle), "{:?} should mention {needle:?}", errors[0]);
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn missing_file_is_one_line() {
    let out = leakless(&["render", "no/such/scene.gltf"], &[]);
    assert_one_line_error(&out, "no/such/scene.gltf");
}

#[test]
fn malformed_gltf_is_one_line() {
    assert_one_line_error(&leakless(&["render", "tests/scenes/malformed.gltf"], &[]), "malformed.gltf");
    assert_one_line_error(&leakless(&["render", "tests/scenes/truncated.glb"], &[]), "truncated.glb");
}

#[test]
fn scene_without_light_says_so() {
    assert_one_line_error(&leakless(&["render", "tests/scenes/no-light.gltf"], &[]), "light");
}

#[test]
fn bad_size_is_rejected() {
    let out = leakless(&["render", "scenes/cornell-box.gltf", "--size", "0x10"], &[]);
    assert_one_line_error(&out, "size");
    let out = leakless(&["render", "scenes/cornell-box.gltf", "--size", "big"], &[]);
    assert!(!out.status.success());
}

/// Settings that would render nonsense are refused before a device is opened: no light paths
/// (each photon carries the light's power over the paths: this rendered NaN), and an exposure
/// that is not a positive multiplier.
#[test]
fn settings_without_meaning_are_refused() {
    let out = leakless(&["render", "scenes/cornell-box.gltf", "--paths", "0", "--out", "/dev/null"], &[]);
    assert_one_line_error(&out, "--paths 0");
    for exposure in ["--exposure=0", "--exposure=-1", "--exposure=nan"] {
        let out = leakless(&["render", "scenes/cornell-box.gltf", exposure, "--out", "/dev/null"], &[]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success() && stderr.contains("positive number"), "{exposure}: {stderr}");
        assert!(!stderr.contains("panicked"), "{stderr}");
    }
    for (flag, needle) in
        [("--light-samples=0", "--light-samples 0"), ("--light-candidates=1000", "--light-candidates 1000")]
    {
        let out = leakless(&["render", "scenes/cornell-panel.gltf", flag, "--out", "/dev/null"], &[]);
        assert_one_line_error(&out, needle);
    }
    // A scene lit only by emissive geometry has no punctual light to move.
    let out = leakless(
        &["render", "scenes/cornell-panel.gltf", "--light-position", "0,0,0", "--size", "8x8", "--out", "/dev/null"],
        &[],
    );
    assert_one_line_error(&out, "no punctual light to move");
}

/// A benchmark's counts are held to what it can measure: a best of no repeats, and changes of
/// an accumulation of fewer than two frames, were printed as measurements.
#[test]
fn bench_counts_outside_their_range_are_refused() {
    let cases: [&[&str]; 3] = [
        &["bench", "leak", "scenes/cornell-box.gltf", "--repeats", "0"],
        &["bench", "rays", "scenes/cornell-box.gltf", "--repeats", "0"],
        &["bench", "flicker", "scenes/cornell-box.gltf", "--frames", "1"],
    ];
    for args in cases {
        let out = leakless(args, &[]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && stderr.contains(args[4]) && stderr.contains("is not in"),
            "{args:?}: {stderr}"
        );
        assert!(!stderr.contains("panicked"), "{stderr}");
    }
}

/// Device limits are checked before anything is allocated, and named with their values: 10⁸
/// paths need a 51 GB photon buffer, beyond any device's maxStorageBufferRange (at most 4 GiB).
#[test]
fn a_device_limit_is_one_line_naming_it() {
    if common_device_missing() {
        return;
    }
    let out = leakless(&["render", "scenes/cornell-box.gltf", "--paths", "100000000", "--out", "/dev/null"], &[]);
    assert_one_line_error(&out, "maxStorageBufferRange (");
    let out =
        leakless(&["render", "scenes/cornell-box.gltf", "--list-capacity", "2000000000", "--out", "/dev/null"], &[]);
    assert_one_line_error(&out, "--list-capacity 2000000000");
}

/// A pass that never completes (debug builds' fault injection, `LEAKLESS_FAULT_HANG`) ends as
/// a lost device named after the pass, once `LEAKLESS_GPU_TIMEOUT` expires: one line, status
/// 1, and the process ends (the stall is released before the device is torn down). Both
/// backends, and a pass early in the frame and one late.
#[test]
fn a_stalled_pass_is_a_lost_device_naming_it() {
    if common_device_missing() {
        return;
    }
    if !cfg!(debug_assertions) {
        eprintln!("\n*** SKIPPED: fault injection exists in debug builds only ***\n");
        return;
    }
    let ray_query = String::from_utf8_lossy(&leakless(&["info"], &[]).stdout).contains("ray queries: yes");
    for (pass, backend) in [("photons", "compute"), ("gather", "rayquery"), ("tonemap", "compute")] {
        if backend == "rayquery" && !ray_query {
            continue;
        }
        let started = std::time::Instant::now();
        let out = leakless(
            &[
                "render",
                "scenes/cornell-box.gltf",
                "--size",
                "32x24",
                "--paths",
                "2000",
                "--backend",
                backend,
                "--out",
                "/dev/null",
            ],
            &[("LEAKLESS_FAULT_HANG", pass), ("LEAKLESS_GPU_TIMEOUT", "1"), ("LEAKLESS_VALIDATION", "1")],
        );
        assert_one_line_error(&out, &format!("device lost during pass {pass} ("));
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.lines().any(|l| l.starts_with(&format!("error: device lost during pass {pass}"))), "{stderr}");
        assert!(!stderr.contains("validation error"), "{stderr}");
        // The default timeout is 600 s: a process that ends well before it ended by the 1 s
        // one. The render itself takes seconds, so only an ignored LEAKLESS_GPU_TIMEOUT nears
        // this bound, never a busy machine.
        assert!(started.elapsed().as_secs() < 400, "the process ended once the 1 s timeout expired");
    }
}

/// Whether this machine has no Vulkan device (the test is then skipped, loudly, as elsewhere).
fn common_device_missing() -> bool {
    let out = leakless(&["info"], &[]);
    let missing = !out.status.success();
    if missing && std::env::var("LEAKLESS_REQUIRE_DEVICE").as_deref() == Ok("1") {
        panic!("LEAKLESS_REQUIRE_DEVICE=1 but `leakless info` failed");
    }
    if missing {
        eprintln!("\n*** SKIPPED: no Vulkan device ***\n");
    }
    missing
}

#[test]
fn no_vulkan_device_is_one_line() {
    // Point the loader at a driver manifest that does not exist: no device at all.
    let env = [("VK_DRIVER_FILES", "/nonexistent/icd.json"), ("VK_ICD_FILENAMES", "/nonexistent/icd.json")];
    let out = leakless(&["render", "scenes/cornell-box.gltf", "--out", "/dev/null"], &env);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_one_line_error(&out, "device");
    assert!(!stderr.contains("panicked"));
}

#[test]
fn render_writes_exr_png_and_stats() {
    if common::gpu().is_none() {
        return;
    }
    let exr = common::tmp_path("cli-cornell.exr");
    let png = common::tmp_path("cli-cornell.png");
    let stats = common::tmp_path("cli-cornell.json");
    let out = leakless(
        &[
            "render",
            "scenes/cornell-box.gltf",
            "--size",
            "40x30",
            "--frames",
            "2",
            "--out",
            exr.to_str().unwrap(),
            "--png",
            png.to_str().unwrap(),
            "--stats",
            stats.to_str().unwrap(),
        ],
        &[("LEAKLESS_VALIDATION", "1")],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(!stderr.contains("validation error"), "{stderr}");
    let read = leakless::output::exr::read(&exr).unwrap();
    assert_eq!((read.width, read.height), (40, 30));
    assert!(read.channel("direct.R").is_some());
    assert!(read.attribute("leakless.scene").unwrap().contains("cornell-box"));
    let img = image::open(&png).unwrap();
    assert_eq!((img.width(), img.height()), (40, 30));
    let json: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
    assert!(json["passes"].as_array().unwrap().iter().any(|p| p["pass"] == "gbuffer"));
    // The passes sum the render's two frames; `last_frame` is the last one's own, the frame
    // the counters counted: part of the whole, each of its passes at most that pass's sum.
    assert_eq!(json["accumulated"], 2);
    let run = json["frame_gpu_ms"].as_f64().unwrap();
    let last = json["last_frame"]["gpu_ms"].as_f64().unwrap();
    assert!(last > 0.0 && last < run, "the last frame {last} ms of a run of {run} ms");
    let summed = json["passes"].as_array().unwrap();
    let own = json["last_frame"]["passes"].as_array().unwrap();
    assert!(own.iter().any(|p| p["pass"] == "gather"), "{own:?}");
    for p in own {
        let sum = summed.iter().find(|q| q["pass"] == p["pass"]).expect("every pass of the last frame is summed");
        assert!(p["gpu_ms"].as_f64().unwrap() <= sum["gpu_ms"].as_f64().unwrap(), "{p} against {sum}");
    }
}

/// `render` finds its view samples as the app does (`--primary auto`): by a ray a pixel where
/// the CPU tuning says a scene of more triangles than pixels rasterises slowly, rasterised on
/// the GPU tuning and where told.
#[test]
fn render_finds_view_samples_as_the_app_does() {
    if common::gpu().is_none() {
        return;
    }
    // The sphere's 5120 triangles are more than 64×48 pixels.
    let (rays, raster) = ("primary rays", "gbuffer");
    for (tuning, primary, pass, not) in
        [("cpu", None, rays, raster), ("gpu", None, raster, rays), ("cpu", Some("raster"), raster, rays)]
    {
        let stats = common::tmp_path(&format!("cli-primary-{tuning}-{}.json", primary.unwrap_or("auto")));
        let stats_arg = stats.to_str().unwrap();
        let mut args = vec!["render", "scenes/sphere.gltf", "--size", "64x48", "--method", "direct"];
        args.extend(["--tuning", tuning, "--out", "/dev/null", "--stats", stats_arg]);
        if let Some(p) = primary {
            args.extend(["--primary", p]);
        }
        let out = leakless(&args, &[("LEAKLESS_VALIDATION", "1")]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{stderr}");
        assert!(!stderr.contains("validation error"), "{stderr}");
        let json: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
        let passes: Vec<&str> = json["passes"].as_array().unwrap().iter().filter_map(|p| p["pass"].as_str()).collect();
        let why = format!("--tuning {tuning} --primary {primary:?}: {passes:?}");
        assert!(passes.contains(&pass) && !passes.contains(&not), "{why}");
    }
}

#[test]
fn info_reports_the_device() {
    if common::gpu().is_none() {
        return;
    }
    let out = leakless(&["info"], &[]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(stdout.contains("using device"), "{stdout}");
    assert!(stdout.contains("ray queries:"), "{stdout}");
}

/// `render --sequence` writes every frame's EXR and PNG, and sequence.json with each frame's
/// index, time, camera and frame_ms, the door shutting in its last frame; with `--frame-ms`,
/// each frame's paths, time and target; a range that runs backwards, `--frames` with a
/// sequence, and `--frame-ms` without one or out of range, are refused.
#[test]
fn a_sequence_writes_its_frames_and_their_times() {
    if common::gpu().is_none() {
        return;
    }
    let dir = common::tmp_path("cli-sequence");
    let _ = std::fs::remove_dir_all(&dir);
    let base = ["render", "scenes/door.gltf", "--size", "32x24", "--paths", "2000", "--out", dir.to_str().unwrap()];
    let stats = common::tmp_path("cli-sequence-stats.json");
    let out =
        leakless(&[&base[..], &["--sequence", "1.9:2:20", "--png", "--stats", stats.to_str().unwrap()]].concat(), &[]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stats.is_file(), "the run's stats");
    for k in 0..3 {
        for ext in ["exr", "png"] {
            assert!(dir.join(format!("{k:04}.{ext}")).is_file(), "frame {k}'s {ext}");
        }
    }
    assert!(!dir.join("0003.exr").exists(), "one frame too many");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("sequence.json")).expect("sequence.json")).unwrap();
    let frames = json["frames"].as_array().expect("frames");
    let times: Vec<f64> = frames.iter().map(|f| f["time"].as_f64().unwrap()).collect();
    assert_eq!(frames.len(), 3);
    assert!((times[1] - 1.95).abs() < 1e-6 && (times[2] - 2.0).abs() < 1e-6, "{times:?}");
    for (k, f) in frames.iter().enumerate() {
        assert_eq!(f["index"].as_u64(), Some(k as u64));
        assert!(f["frame_ms"].as_f64().unwrap() > 0.0 && f["camera"]["eye"].as_array().unwrap().len() == 3);
    }
    assert_eq!(json["reuse"].as_bool(), Some(true));
    let shut = leakless::output::exr::read(&dir.join("0002.exr")).expect("the last frame");
    assert!(shut.channel("R").unwrap().iter().all(|&v| v == 0.0), "the shut door's frame is not black");

    // With a frame budget, each frame that starts an accumulation records the paths the budget
    // chose, its time and its target. Submitted at once (`--timing timestamps`), the budget's
    // first measured frame is still timed pass by pass where timestamps do not bracket the
    // work (lavapipe), so that the budget splits it by its passes (a GPU times every frame).
    let budgeted = common::tmp_path("cli-sequence-budget");
    let mut args = base.to_vec();
    args[7] = budgeted.to_str().unwrap();
    let sequence = ["--sequence", "1.9:2.1:20", "--frame-ms", "40", "--timing", "timestamps"];
    let out = leakless(&[&args[..], &sequence].concat(), &[]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(budgeted.join("sequence.json")).expect("sequence.json")).unwrap();
    let frames = json["frames"].as_array().expect("frames");
    assert!(frames[0].get("budget").is_some(), "the first frame starts an accumulation: {}", frames[0]);
    for f in frames.iter().filter(|f| f.get("budget").is_some()) {
        let b = &f["budget"];
        assert_eq!(b["target_ms"].as_f64(), Some(40.0), "{f}");
        assert!(b["measured_ms"].as_f64().unwrap() > 0.0, "{f}");
        assert_eq!(b["paths"], f["paths"], "{f}");
        assert!(f["radius"].as_f64().unwrap() > 0.0, "{f}");
    }
    // The first frame and the first moving frame run passes for the first time (warm-up
    // frames, not measured); the first measured frame is timed.
    let budget = |k: usize| &frames[k]["budget"];
    let share = |k: usize| budget(k)["photon_share"].as_f64();
    assert_eq!(frames.len(), 5);
    assert!(budget(0)["warm_up"].as_bool().unwrap() && budget(1)["warm_up"].as_bool().unwrap(), "{}", frames[1]);
    assert_eq!(budget(2)["warm_up"].as_bool(), Some(false), "{}", frames[2]);
    assert!(share(2).is_some_and(|s| s > 0.0 && s < 1.0), "the first measured frame timed: {}", frames[2]);
    // Timed pass by pass among frames submitted at once, its time is not a budgeted frame's:
    // it gives the split only, and the frame after it is the budget's first estimate.
    let split_only = |k: usize| budget(k)["split_only"].as_bool();
    assert_eq!(split_only(2), Some(share(0).is_none()), "{}", frames[2]);
    for k in (0..frames.len()).filter(|&k| k != 2 && frames[k].get("budget").is_some()) {
        assert_eq!(split_only(k), Some(false), "{}", frames[k]);
    }
    // Where the first frame was not timed (a device whose passes are timed only when asked),
    // the frames after the split are submitted at once again, as the caller asked.
    if share(0).is_none() {
        assert_eq!(share(4), None, "the last frame: {}", frames[4]);
    }
    let out = leakless(&[&base[..], &["--frame-ms", "40"]].concat(), &[]);
    assert_one_line_error(&out, "--frame-ms budgets the frames of a --sequence");
    let out = leakless(&[&base[..], &["--sequence", "1.9:2:20", "--frame-ms", "0"]].concat(), &[]);
    assert_one_line_error(&out, "--frame-ms 0 must be within");

    let out = leakless(&[&base[..], &["--sequence", "2:1:30"]].concat(), &[]);
    assert!(!out.status.success() && String::from_utf8_lossy(&out.stderr).contains("before the start"));
    let out = leakless(&[&base[..], &["--sequence", "0:1:10", "--frames", "2"]].concat(), &[]);
    assert_one_line_error(&out, "--frames 2");
}

/// A sequence whose frames miss their budget even at the fewest paths renders fewer pixels, as
/// the app does, and writes every frame at `--size`; `--dynamic-resolution off` keeps the size.
#[test]
fn a_sequence_over_its_budget_renders_fewer_pixels_at_its_size() {
    if common::gpu().is_none() {
        return;
    }
    let sizes = |dynamic: &str| {
        let dir = common::tmp_path(&format!("cli-sequence-dynamic-{dynamic}"));
        let _ = std::fs::remove_dir_all(&dir);
        let args = ["render", "scenes/door.gltf", "--size", "64x48", "--sequence", "1.5:2:20", "--frame-ms", "1"];
        let out =
            leakless(&[&args[..], &["--dynamic-resolution", dynamic, "--out", dir.to_str().unwrap()]].concat(), &[]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("sequence.json")).expect("sequence.json")).unwrap();
        let frames = json["frames"].as_array().expect("frames").clone();
        for k in 0..frames.len() {
            let exr = leakless::output::exr::read(&dir.join(format!("{k:04}.exr"))).expect("a frame");
            assert_eq!(exr.channel("R").unwrap().len(), 64 * 48, "frame {k} is not at --size");
        }
        assert!(json["parameters"].as_str().unwrap().contains("size=64x48"), "{}", json["parameters"]);
        frames
            .iter()
            .map(|f| (f["render_size"][0].as_u64().unwrap(), f["render_size"][1].as_u64().unwrap()))
            .collect::<Vec<_>>()
    };
    let on = sizes("on");
    assert_eq!(on[0], (64, 48));
    assert!(on.iter().any(|&(w, h)| w < 64 && h < 48), "never smaller: {on:?}");
    assert!(on.iter().all(|&(w, h)| w >= 16 && h >= 12), "below a sixteenth of the pixels: {on:?}");
    let off = sizes("off");
    assert!(off.iter().all(|&s| s == (64, 48)), "{off:?}");
}

/// `bench motion --budgeted` runs the budgeted sequence beside a fixed one, a frame of each in
/// turn, and prints and records them: a row of the CSV per frame for each run.
#[test]
fn bench_motion_compares_a_budgeted_run_at_the_fixed_runs_time() {
    if common::gpu().is_none() {
        return;
    }
    let csv_path = common::tmp_path("cli-bench-motion.csv");
    let args = ["bench", "motion", "scenes/cornell-box.gltf", "--size", "32x18", "--frames", "4", "--spp", "2"];
    let out = leakless(&[&args[..], &["--budgeted", "--csv", csv_path.to_str().unwrap()]].concat(), &[]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(stdout.contains("budgeted beside a fixed run") && stdout.contains("×), paths "), "{stdout}");
    let mut reader = csv::Reader::from_path(&csv_path).expect("the CSV written");
    let headers = reader.headers().expect("a header").clone();
    let column =
        |name: &str| headers.iter().position(|h| h == name).unwrap_or_else(|| panic!("no {name}: {headers:?}"));
    let (paths, ms) = (column("paths"), column("ms"));
    let rows: Vec<csv::StringRecord> = reader.records().map(|r| r.expect("a row")).collect();
    let runs: Vec<String> = rows.iter().map(|r| r[1].to_string()).collect();
    // Each frame's paths and time: a fixed run's are `--paths` (10 000 by default) on every frame.
    for row in &rows {
        assert!(row[ms].parse::<f64>().is_ok_and(|t| t > 0.0), "{row:?}");
        if row[1] != *"on-budgeted" {
            assert_eq!(&row[paths], "10000", "{row:?}");
        }
    }
    // The budgeted run and the fixed one beside it alternate frame by frame.
    let beside: Vec<&str> = runs.iter().map(String::as_str).filter(|r| r.contains("budgeted")).collect();
    assert_eq!(beside[..4], ["on-beside-budgeted", "on-budgeted", "on-beside-budgeted", "on-budgeted"], "{runs:?}");
    for run in ["on", "on-unfiltered", "off", "on-beside-budgeted", "on-budgeted"] {
        assert_eq!(runs.iter().filter(|r| *r == run).count(), 4, "{run}: {runs:?}");
    }
}
