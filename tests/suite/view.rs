//! The app (`leakless view`) in a real window: an Xvfb server started by the test, lavapipe
//! presenting to it. A script cycles every method and view layer, moves the light, resizes the
//! window 20 times, minimises and restores it, and captures; the run must exit 0 without a
//! validation error, and the capture must equal, bit for bit, what `leakless render` makes of
//! the command line the capture recorded. A soak of 1000 frames must keep its memory flat.
//!
//! Without an X server (no Xvfb installed, or it fails to start) the tests say so loudly and
//! pass, unless LEAKLESS_REQUIRE_DEVICE=1 (CI), where that is a failure.

use crate::common;

use std::path::Path;
use std::process::{Child, Command, Output, Stdio};
use std::time::Duration;

use leakless::output::exr;

/// An Xvfb server on a display of its own, stopped when dropped.
struct XServer {
    child: Child,
    display: String,
}

impl Drop for XServer {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn no_display(why: &str) -> Option<XServer> {
    if std::env::var("LEAKLESS_REQUIRE_DEVICE").as_deref() == Ok("1") {
        panic!("LEAKLESS_REQUIRE_DEVICE=1 but no X server for the window tests: {why}");
    }
    eprintln!("\n*** SKIPPED: no X server for the window tests ({why}); install xvfb (tools/install-deps) ***\n");
    None
}

/// Starts Xvfb on a display it picks itself (`-displayfd`: no race between tests that start
/// servers at the same time).
fn xvfb() -> Option<XServer> {
    use std::io::{BufRead, BufReader};
    let mut child = match Command::new("Xvfb")
        .args(["-displayfd", "1", "-screen", "0", "1280x1024x24", "-nolisten", "tcp"])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
    {
        Ok(c) => c,
        Err(e) => return no_display(&format!("cannot run Xvfb: {e}")),
    };
    let stdout = child.stdout.take().expect("piped");
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let mut line = String::new();
        let _ = BufReader::new(stdout).read_line(&mut line);
        let _ = tx.send(line);
    });
    // Xvfb reports its display within a second; the limit only ends a server that hangs, long
    // enough that a busy machine never reaches it.
    match rx.recv_timeout(Duration::from_secs(180)) {
        Ok(line) if line.trim().parse::<u32>().is_ok() => Some(XServer { child, display: format!(":{}", line.trim()) }),
        other => {
            let _ = child.kill();
            let _ = child.wait();
            no_display(&format!("Xvfb did not report a display ({other:?})"))
        }
    }
}

fn view(x: &XServer, args: &[&str], validation: bool) -> Output {
    Command::new(env!("CARGO_BIN_EXE_leakless"))
        .arg("view")
        .args(args)
        .current_dir(common::root())
        .env("DISPLAY", &x.display)
        .env_remove("WAYLAND_DISPLAY")
        .env("LEAKLESS_VALIDATION", if validation { "1" } else { "0" })
        .output()
        .expect("run leakless view")
}

fn assert_clean(out: &Output) -> String {
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "leakless view failed: {stderr}\n{stdout}");
    assert!(!stderr.contains("validation error"), "validation errors: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    stdout
}

/// An empty directory of the test's own for scripts and captures.
fn fresh_dir(name: &str) -> std::path::PathBuf {
    let dir = common::tmp_path(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Every channel of two EXRs, bit for bit.
fn assert_same_exr(a: &Path, b: &Path) {
    let (a_exr, b_exr) = (exr::read(a).expect("read capture"), exr::read(b).expect("read render"));
    assert_eq!((a_exr.width, a_exr.height), (b_exr.width, b_exr.height));
    assert_eq!(a_exr.channels.len(), 12, "R,G,B and the direct, indirect, leaked layers");
    for (name, values) in &a_exr.channels {
        let other = b_exr.channel(name).unwrap_or_else(|| panic!("{} has no channel {name}", b.display()));
        let differ = values.iter().zip(other).filter(|(x, y)| x.to_bits() != y.to_bits()).count();
        assert_eq!(differ, 0, "channel {name}: {differ} of {} pixels differ", values.len());
    }
}

/// The app ends a lost device as the CLI does: one line naming the pass, status 1, the
/// window closed (debug builds' fault injection stalls the gather pass of the first frame).
#[test]
fn a_lost_device_ends_the_app_with_one_line() {
    let Some(x) = xvfb() else { return };
    if !cfg!(debug_assertions) {
        eprintln!("\n*** SKIPPED: fault injection exists in debug builds only ***\n");
        return;
    }
    let dir = fresh_dir("view-lost");
    // Should the stall not happen, the script ends the app instead of the test hanging.
    let script = dir.join("quit.txt");
    std::fs::write(&script, "200 quit\n").unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_leakless"))
        .args(["view", "scenes/cornell-box.gltf", "--size", "64x48", "--paths", "2000", "--script"])
        .arg(&script)
        .current_dir(common::root())
        .env("DISPLAY", &x.display)
        .env_remove("WAYLAND_DISPLAY")
        .env("LEAKLESS_FAULT_HANG", "gather")
        .env("LEAKLESS_GPU_TIMEOUT", "1")
        .output()
        .expect("run leakless view");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(errors.len(), 1, "{stderr}");
    assert!(errors[0].starts_with("error: device lost during pass gather ("), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn scripted_session_is_clean_and_captures_what_render_renders() {
    let Some(x) = xvfb() else { return };
    let dir = fresh_dir("view-session");
    let capture = dir.join("capture.exr");
    let mut script = String::new();
    let frame = std::cell::Cell::new(2);
    let at = |s: &mut String, event: &str| {
        s.push_str(&format!("{} {event}\n", frame.get()));
        frame.set(frame.get() + 2);
    };
    // Every method, every view layer (in leakless), settings and the light.
    for key in ["Digit1", "Digit2", "Digit3", "Digit5", "Digit4"] {
        at(&mut script, &format!("key {key}"));
    }
    for _ in 0..leakless::ViewLayer::ALL.len() {
        at(&mut script, "key KeyV");
    }
    let keys =
        ["BracketRight", "Equal", "Period", "KeyT", "KeyT", "KeyU", "KeyU", "KeyB", "KeyB", "ArrowLeft", "PageUp"];
    for key in keys.into_iter().chain(["KeyW"]) {
        at(&mut script, &format!("key {key}"));
    }
    at(&mut script, "drag 15 -10");
    // Paused, then a change: the window still shows the state before it, which no command
    // renders, so a capture is refused (panel and stderr) and nothing is written.
    let paused_capture = dir.join("paused.exr");
    at(&mut script, "key Space");
    at(&mut script, "key Equal");
    at(&mut script, "key Minus");
    at(&mut script, &format!("capture {}", paused_capture.display()));
    at(&mut script, "key Space");
    // 20 resizes, then minimised and restored.
    for i in 0..20 {
        at(&mut script, &format!("resize {} {}", 64 + 8 * (i % 5), 48 + 6 * (i % 4)));
    }
    at(&mut script, "resize 0 0");
    at(&mut script, "resize 96 72");
    at(&mut script, "key Tab");
    at(&mut script, "key Tab");
    // The reference, accumulating jittered frames while the view is still, captured.
    let reference = dir.join("reference.exr");
    at(&mut script, "key Digit5");
    frame.set(frame.get() + 10); // still frames
    at(&mut script, &format!("capture {}", reference.display()));
    at(&mut script, "key Digit4");
    // A fixed seed, then a capture.
    at(&mut script, "key KeyP");
    at(&mut script, &format!("capture {}", capture.display()));
    at(&mut script, "quit");
    let script_path = dir.join("session.txt");
    std::fs::write(&script_path, &script).unwrap();

    let frame_log = dir.join("frames.csv");
    let out = view(
        &x,
        &["scenes/cornell-box.gltf", "--size", "96x72", "--render-scale", "1", "--paths", "2000", "--script"]
            .into_iter()
            .chain([script_path.to_str().unwrap(), "--frame-log", frame_log.to_str().unwrap()])
            .collect::<Vec<_>>(),
        true,
    );
    let stdout = assert_clean(&out);
    assert!(stdout.contains("frames "), "the summary line: {stdout}");
    // The budget's log: a row per budgeted frame, the first a warm-up, the resized windows'
    // render sizes among them. A frame that runs a pass for the first time is a warm-up too
    // (the first moving frame's reuse, each method's first frame): a few, and no more.
    let mut log = csv::Reader::from_path(&frame_log).expect("the frame log written");
    let rows: Vec<csv::StringRecord> = log.records().map(|r| r.expect("a row")).collect();
    let warm_up: Vec<&str> = rows.iter().map(|r| &r[8]).collect();
    let warm_ups = warm_up.iter().filter(|w| **w == "true").count();
    assert!(warm_up.len() > 5 && warm_up[0] == "true" && (2..=8).contains(&warm_ups), "{warm_ups} {warm_up:?}");
    let sizes: std::collections::BTreeSet<(&str, &str)> = rows.iter().map(|r| (&r[5], &r[6])).collect();
    assert!(sizes.contains(&("96", "72")) && sizes.len() > 1, "{sizes:?}");
    for ext in ["exr", "png", "json"] {
        assert!(capture.with_extension(ext).exists(), "capture .{ext} written");
    }
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("not applied: capture: paused since the last change"), "{stderr}");
    assert!(!paused_capture.exists(), "a refused capture writes nothing");

    // The command each capture recorded renders the same EXR.
    let reference_command = assert_command_renders(&reference, &dir.join("reference-again.exr"));
    assert!(
        reference_command.contains("--method reference") && reference_command.contains("--frames"),
        "{reference_command}"
    );
    assert_command_renders(&capture, &dir.join("again.exr"));
}

/// Runs the `leakless render` command recorded beside `capture`, writing `again`, and checks
/// that it renders the same EXR. Returns the command.
fn assert_command_renders(capture: &Path, again: &Path) -> String {
    let stats: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(capture.with_extension("json")).unwrap()).unwrap();
    let command = stats["command"].as_str().expect("the capture records its command");
    let words: Vec<&str> = command.split_whitespace().collect();
    assert_eq!(&words[..2], ["leakless", "render"]);
    let out_at = words.iter().position(|w| *w == "--out").expect("--out");
    let mut args: Vec<String> = words[1..out_at].iter().map(|s| s.to_string()).collect();
    args.extend(["--out".into(), again.display().to_string()]);
    let render = Command::new(env!("CARGO_BIN_EXE_leakless"))
        .args(&args)
        .current_dir(common::root())
        .env("LEAKLESS_VALIDATION", "1")
        .output()
        .expect("run leakless render");
    assert!(render.status.success(), "{command}: {}", String::from_utf8_lossy(&render.stderr));
    assert_same_exr(capture, again);
    command.to_string()
}

/// A key that would take a setting past a device limit is refused, not fatal: `=` doubles the
/// paths past what the photon buffer holds (from half the device's limit plus one); the app
/// says so once and runs on at the paths it had. `render` exits on the same setting.
#[test]
fn a_key_past_a_device_limit_is_refused_and_the_app_runs_on() {
    let Some(x) = xvfb() else { return };
    let Some(gpu) = common::gpu() else { return };
    // 64 bounces: the photon buffer's limit is low (32,768 paths on lavapipe's 128 MiB range).
    let most = leakless::limits::max_frame_paths(&gpu.report().limits, 64);
    drop(gpu);
    let paths = (most / 2 + 1).to_string();
    let dir = fresh_dir("view-refused");
    let script = dir.join("script.txt");
    std::fs::write(&script, "3 key Equal\n5 key Equal\n12 quit\n").unwrap();
    let args = ["scenes/cornell-box.gltf", "--size", "32x24", "--max-bounces", "64", "--paths", &paths, "--script"];
    let mut args: Vec<&str> = args.to_vec();
    args.push(script.to_str().unwrap());
    let out = view(&x, &args, true);
    let stdout = assert_clean(&out);
    assert!(stdout.contains("frames 12,"), "the app ran to the end of its script: {stdout}");
    let stderr = String::from_utf8_lossy(&out.stderr);
    let refusals: Vec<&str> = stderr.lines().filter(|l| l.starts_with("not applied:")).collect();
    assert_eq!(refusals.len(), 1, "said once: {stderr}");
    assert!(refusals[0].contains(&format!("--paths {}", 2 * (most / 2 + 1))), "{stderr}");
}

#[test]
fn soak_keeps_memory_flat() {
    let Some(x) = xvfb() else { return };
    // Validation off: the layers track objects of their own; this measures the app's memory.
    // 1000 light paths keep a frame short on a CPU device; every pass still runs.
    let args = [
        "scenes/cornell-box.gltf",
        "--size",
        "64x64",
        "--render-scale",
        "1",
        "--paths",
        "1000",
        "--exit-after",
        "1000",
        // Frames still grow (1, then 2 batches), so the soak holds the grown buffers too, at
        // a third of the default's 8 batches' time.
        "--max-batches",
        "2",
        // The budget on, at the 100 ms a still frame was fitted to before it (the CPU
        // default's 150 ms makes the soak's frames longer, and CI's run with them).
        "--frame-ms",
        "100",
    ];
    let out = view(&x, &args, false);
    let stdout = assert_clean(&out);
    let line = stdout.lines().find(|l| l.starts_with("frames ")).expect("summary line");
    eprintln!("soak: {line}");
    let mib = |label: &str| -> f64 {
        let rest = &line[line.find(label).unwrap_or_else(|| panic!("{label} in {line}")) + label.len()..];
        rest.trim().split(' ').next().unwrap().parse().unwrap()
    };
    assert!(line.starts_with("frames 1000,"), "{line}");
    // Without a leak the resident set still moves by whole MiB as the allocator and the driver
    // take and return pages: 1–3 MiB over these 900 frames on an idle machine (the builds of
    // ec74ff5 and be6eb36 alike), 5 MiB once in CI beside another test, and 2 MiB over 2900
    // frames. 8 MiB still fails a leak of 9 KiB a frame.
    let (at_100, at_end) = (mib("RSS at frame 100"), mib("RSS at end"));
    assert!((at_end - at_100).abs() <= 8.0, "RSS grew from {at_100} MiB at frame 100 to {at_end} MiB: {line}");
}

/// The app plays the scene's animation (1/30 s per scripted frame): the door, open at first,
/// has swung shut by frame 80 (t ≥ 2 s), leaving room B exactly black with leakless, and the
/// capture's command carries the time. M stops the clock: without it, frame 130 would be
/// 4.3 s into a 3 s loop, door half open, room B lit.
#[test]
fn the_app_plays_the_door_shut_and_m_stops_it() {
    let Some(x) = xvfb() else { return };
    let dir = fresh_dir("view-door");
    let [open, closed, stopped] = ["open", "closed", "stopped"].map(|n| dir.join(format!("{n}.exr")));
    let script = format!(
        "3 capture {}\n80 capture {}\n85 key KeyM\n130 capture {}\n132 quit\n",
        open.display(),
        closed.display(),
        stopped.display()
    );
    let script_path = dir.join("door.txt");
    std::fs::write(&script_path, script).unwrap();
    let args = ["scenes/door.gltf", "--size", "64x48", "--render-scale", "1", "--paths", "2000", "--script"];
    let out = view(&x, &args.into_iter().chain([script_path.to_str().unwrap()]).collect::<Vec<_>>(), true);
    assert_clean(&out);
    let lit = |path: &Path| {
        let image = exr::read(path).expect("read capture");
        image.channel("G").expect("G").iter().filter(|&&v| v > 0.0).count()
    };
    assert!(lit(&open) > 100, "the open door lets light into room B");
    assert_eq!(lit(&closed), 0, "room B behind the closed door");
    assert_eq!(lit(&stopped), 0, "M stopped the animation with the door closed");
    let stats: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(closed.with_extension("json")).unwrap()).unwrap();
    let command = stats["command"].as_str().expect("the capture records its command");
    assert!(command.contains(" --time 2 "), "{command}");
    assert_eq!(stats["instances"], 3, "leaf, handle, bolt");
}
