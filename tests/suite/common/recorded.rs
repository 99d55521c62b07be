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

use std::fmt::Write as _;
use std::path::PathBuf;

use leakless::{RenderSettings, RenderedFrame};

const DIR: &str = "tests/fixtures/references";
const MAGIC: &str = "leakless recorded reference v1";

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

fn path(dir: &std::path::Path, label: &str, s: &RenderSettings) -> PathBuf {
    let name = format!(
        "{label}-{}x{}-{}spp-{}f-{}b-seed{}-{:?}.bin",
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
    dir: &std::path::Path,
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
        write(&file, &settings, canary_hash, &frame);
        eprintln!("recorded {} ({:.1} s)", file.display(), start.elapsed().as_secs_f64());
    } else {
        eprintln!(
            "    ({:.1} s; record it with LEAKLESS_RECORD_REFERENCES=1 on the device CI runs on)",
            start.elapsed().as_secs_f64()
        );
    }
    Some(frame)
}

fn write(file: &PathBuf, settings: &RenderSettings, canary_hash: u64, frame: &RenderedFrame) {
    let mut header = String::new();
    writeln!(header, "{MAGIC}").unwrap();
    writeln!(
        header,
        "{:016x} {} {} {} {} {}",
        canary_hash, frame.width, frame.height, frame.accumulated, frame.batches, frame.seed
    )
    .unwrap();
    // For a reader: what it was rendered with (the canary, not this line, decides validity).
    writeln!(header, "{settings:?}").unwrap();
    let mut bytes = header.into_bytes();
    bytes.push(0);
    for layer in [&frame.radiance, &frame.direct, &frame.indirect] {
        bytes.extend(layer.iter().flatten().flat_map(|v| v.to_le_bytes()));
    }
    std::fs::create_dir_all(file.parent().unwrap()).expect("fixture directory");
    std::fs::write(file, bytes).unwrap_or_else(|e| panic!("writing {}: {e}", file.display()));
}

/// The canary's hash and the frame (its three light layers and counts) of a fixture.
fn read(file: &PathBuf) -> Option<(u64, RenderedFrame)> {
    let bytes = std::fs::read(file).ok()?;
    let end = bytes.iter().position(|&b| b == 0)?;
    let header = std::str::from_utf8(&bytes[..end]).ok()?;
    let mut lines = header.lines();
    if lines.next()? != MAGIC {
        return None;
    }
    let fields: Vec<&str> = lines.next()?.split(' ').collect();
    let [canary, width, height, accumulated, batches, seed] = fields[..] else { return None };
    let number = |s: &str| s.parse::<u32>().ok();
    let (width, height) = (number(width)?, number(height)?);
    let floats: Vec<f32> =
        bytes[end + 1..].chunks_exact(4).map(|c| f32::from_le_bytes(c.try_into().unwrap())).collect();
    let pixels = (width * height) as usize;
    if floats.len() != 9 * pixels {
        return None;
    }
    let layer =
        |k: usize| floats[3 * k * pixels..3 * (k + 1) * pixels].chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect();
    let frame = RenderedFrame {
        width,
        height,
        radiance: layer(0),
        direct: layer(1),
        indirect: layer(2),
        leaked: vec![[0.0; 3]; pixels],
        surface: Vec::new(),
        display: Vec::new(),
        timings: Vec::new(),
        gpu_span_ms: 0.0,
        wall_ms: 0.0,
        splat: None,
        accumulated: number(accumulated)?,
        batches: number(batches)?,
        seed: number(seed)?,
    };
    Some((u64::from_str_radix(canary, 16).ok()?, frame))
}

/// Makes `file`'s recorded canary hash wrong, as a change to the renderer would: for the test
/// of the mechanism.
pub fn spoil_canary(file: &std::path::Path) {
    let mut bytes = std::fs::read(file).expect("a recorded reference");
    let at = MAGIC.len() + 1; // the canary's first hex digit
    bytes[at] = if bytes[at] == b'0' { b'1' } else { b'0' };
    std::fs::write(file, bytes).expect("rewriting the reference");
}

/// The fixture files in `dir`.
pub fn files(dir: &std::path::Path) -> Vec<PathBuf> {
    std::fs::read_dir(dir).map(|d| d.map(|e| e.unwrap().path()).collect()).unwrap_or_default()
}
