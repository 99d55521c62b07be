//! Path-traced references recorded once instead of rendered by every test run.
//!
//! A reference of 1024–2048 samples a pixel takes lavapipe 10–35 s, and the statistical tests
//! need about twenty of them: most of the suite's time, in CI's 20 minutes on two cores. So
//! such a reference is read from `tests/fixtures/references/` when a **canary** says it is
//! still what this build would render: the same settings at 1/32 of the samples (at least
//! one) and at most two frames, rendered live, must hash to what was recorded beside the
//! image. Any change to the path tracer, the scene, the jitter or the device changes the
//! canary's float bits (as it changes `identity`'s hashes), and the test then renders the
//! whole reference live and says so; `tools/test` lists such tests. Record anew with
//! `LEAKLESS_RECORD_REFERENCES=1 tools/test FILTER` (or the whole suite) on the device CI
//! runs on. On another device (a GPU) the canary differs and every reference is rendered
//! live, which is as fast there as reading it.

use std::path::{Path, PathBuf};

use leakless::output::exr::{self, ExrLayer};
use leakless::{RenderSettings, RenderedFrame};

const DIR: &str = "tests/fixtures/references";

/// FNV-1a, 64 bits, over the float bits of the canary's layers.
fn hash(frame: &RenderedFrame) -> u64 {
    [&frame.radiance, &frame.direct, &frame.indirect]
        .into_iter()
        .flat_map(|layer| layer.iter().flatten().flat_map(|v| v.to_bits().to_le_bytes()))
        .fold(0xcbf2_9ce4_8422_2325, |h, b| (h ^ b as u64).wrapping_mul(0x0100_0000_01b3))
}

/// The cheap render whose bits stand for the whole reference's.
fn canary(settings: &RenderSettings) -> RenderSettings {
    RenderSettings { spp: (settings.spp / 32).max(1), frames: settings.frames.min(2), ..settings.clone() }
}

fn path(dir: &Path, label: &str, s: &RenderSettings) -> PathBuf {
    let name = format!(
        "{label}-{}x{}-{}spp-{}f-{}b-seed{}-{:?}.exr",
        s.width, s.height, s.spp, s.frames, s.max_bounces, s.seed, s.backend
    );
    dir.join(name.to_lowercase())
}

/// The reference `render(settings)` gives, from the fixture when its canary matches.
/// `label` names what `settings` do not say (the scene, a time on its clock).
pub fn reference(
    label: &str,
    settings: RenderSettings,
    render: impl Fn(RenderSettings) -> Option<RenderedFrame>,
) -> Option<RenderedFrame> {
    let record = std::env::var("LEAKLESS_RECORD_REFERENCES").as_deref() == Ok("1");
    reference_in(&super::root().join(DIR), record, label, settings, render)
}

/// [`reference`], with its fixtures in `dir`; `record`: render it and write the fixture.
pub fn reference_in(
    dir: &Path,
    record: bool,
    label: &str,
    settings: RenderSettings,
    render: impl Fn(RenderSettings) -> Option<RenderedFrame>,
) -> Option<RenderedFrame> {
    let file = path(dir, label, &settings);
    let canary_hash = hash(&render(canary(&settings))?);
    if !record {
        match read(&file) {
            Some((recorded, frame)) if recorded == canary_hash => return Some(frame),
            Some(_) => eprintln!("*** reference rendered live: {} is stale (its canary differs)", file.display()),
            None => eprintln!("*** reference rendered live: {} is not recorded", file.display()),
        }
    }
    let start = std::time::Instant::now();
    let frame = render(settings.clone())?;
    if record {
        write(&file, &format!("{settings:?}"), canary_hash, &frame);
        eprintln!("recorded {} ({:.1} s)", file.display(), start.elapsed().as_secs_f64());
    } else {
        eprintln!(
            "    ({:.1} s; record it with LEAKLESS_RECORD_REFERENCES=1 on the device CI runs on)",
            start.elapsed().as_secs_f64()
        );
    }
    Some(frame)
}

/// A fixture is a layered EXR (the renderer's own format, `output::exr`: any EXR viewer shows
/// it), its light layers losslessly, and in its header the canary's hash, the counts a frame
/// reports and, for a reader, the settings it was rendered with (the canary, not these,
/// decides whether it is still valid).
fn write(file: &Path, settings: &str, canary_hash: u64, frame: &RenderedFrame) {
    let layers = [
        ExrLayer { name: "", pixels: &frame.radiance },
        ExrLayer { name: "direct", pixels: &frame.direct },
        ExrLayer { name: "indirect", pixels: &frame.indirect },
    ];
    let attributes = [
        ("canary", format!("{canary_hash:016x}")),
        ("accumulated", frame.accumulated.to_string()),
        ("batches", frame.batches.to_string()),
        ("seed", frame.seed.to_string()),
        ("settings", settings.to_string()),
    ];
    std::fs::create_dir_all(file.parent().unwrap()).expect("fixture directory");
    exr::write(file, frame.width, frame.height, &layers, &attributes)
        .unwrap_or_else(|e| panic!("writing {}: {e}", file.display()));
}

/// The canary's hash and the frame (its three light layers and counts) of a fixture.
fn read(file: &Path) -> Option<(u64, RenderedFrame)> {
    let image = exr::read(file).ok()?;
    let pixels = (image.width * image.height) as usize;
    let layer = |name: &str| -> Option<Vec<[f32; 3]>> {
        let prefix = if name.is_empty() { String::new() } else { format!("{name}.") };
        let [r, g, b] = ["R", "G", "B"].map(|c| image.channel(&format!("{prefix}{c}")));
        let (r, g, b) = (r?, g?, b?);
        (r.len() == pixels).then(|| (0..pixels).map(|i| [r[i], g[i], b[i]]).collect())
    };
    let number = |key: &str| image.attribute(key)?.parse::<u32>().ok();
    let frame = RenderedFrame {
        width: image.width,
        height: image.height,
        radiance: layer("")?,
        direct: layer("direct")?,
        indirect: layer("indirect")?,
        leaked: vec![[0.0; 3]; pixels],
        surface: Vec::new(),
        display: Vec::new(),
        timings: Vec::new(),
        last_frame_timings: Vec::new(),
        gpu_span_ms: 0.0,
        wall_ms: 0.0,
        splat: None,
        accumulated: number("accumulated")?,
        batches: number("batches")?,
        seed: number("seed")?,
    };
    Some((u64::from_str_radix(image.attribute("canary")?, 16).ok()?, frame))
}

/// Makes `file`'s recorded canary hash wrong, as a change to the renderer would: for the test
/// of the mechanism.
pub fn spoil_canary(file: &Path) {
    let (canary, frame) = read(file).expect("a recorded reference");
    let settings = exr::read(file).expect("a recorded reference").attribute("settings").unwrap_or_default().to_string();
    write(file, &settings, canary ^ 1, &frame);
}

/// The fixture files in `dir`.
pub fn files(dir: &Path) -> Vec<PathBuf> {
    std::fs::read_dir(dir).map(|d| d.map(|e| e.unwrap().path()).collect()).unwrap_or_default()
}
