//! Refactoring changes no pixel: every shipped scene, rendered with each method the frame
//! composes differently (splat, leakless over an accumulation of three frames, the reference),
//! on each backend, hashes to what `tests/fixtures/image-hashes.txt` recorded.
//!
//! The hashes are of the float bits of every layer and of the tonemapped bytes, so they hold
//! only on the device that recorded them (lavapipe's generated code follows its LLVM and the
//! CPU's vector width): on another device the test says so and compares nothing. Record them
//! anew, on purpose, when an image is meant to change or the device is new:
//! `LEAKLESS_RECORD_HASHES=1 cargo test --test suite identity`. CI sets
//! `LEAKLESS_REQUIRE_HASHES=1`, which makes a device without recorded hashes a failure.

use std::fmt::Write as _;

use leakless::{BackendChoice, Method, RenderSettings, Renderer, SplatSettings};

use crate::common;

const FIXTURE: &str = "tests/fixtures/image-hashes.txt";

/// FNV-1a, 64 bits: enough to tell images apart, and no dependency.
fn fnv1a(bytes: impl IntoIterator<Item = u8>) -> u64 {
    bytes.into_iter().fold(0xcbf2_9ce4_8422_2325, |h, b| (h ^ b as u64).wrapping_mul(0x0100_0000_01b3))
}

fn layer_bytes(layer: &[[f32; 3]]) -> impl Iterator<Item = u8> + '_ {
    layer.iter().flatten().flat_map(|v| v.to_bits().to_le_bytes())
}

/// The shipped scenes (`scenes/*.gltf`), in name order.
fn shipped_scenes() -> Vec<String> {
    let mut scenes: Vec<String> = std::fs::read_dir(common::root().join("scenes"))
        .expect("scenes/")
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "gltf"))
        .map(|p| format!("scenes/{}", p.file_name().unwrap().to_string_lossy()))
        .collect();
    scenes.sort();
    scenes
}

/// One line per (scene, backend, method): `scene backend method hash`.
fn hash_lines(choice: BackendChoice) -> Option<(String, Vec<String>)> {
    let gpu = common::gpu_with(choice.wants_ray_queries())?;
    let device = format!("{} / {}", gpu.report().name, gpu.report().driver);
    drop(gpu);
    let mut lines = Vec::new();
    for path in shipped_scenes() {
        let scene = common::scene(&path);
        let settings = RenderSettings {
            width: 40,
            height: 30,
            backend: choice,
            max_bounces: 4,
            seed: 3,
            // The fixed radius the hashes were recorded at: the count-following radius is
            // checked by its own test (splat.rs), and a given radius keeps every image.
            splat: SplatSettings {
                paths: 4000,
                radius: Some(leakless::splatting::auto_radius(&scene)),
                ..Default::default()
            },
            spp: 2,
            ..Default::default()
        };
        let gpu = common::gpu_with(choice.wants_ray_queries())?;
        let mut renderer = Renderer::new(gpu, &scene, settings).expect("renderer");
        for (method, frames) in [(Method::Splat, 1), (Method::LeakLess, 3), (Method::Reference, 1)] {
            renderer.update(|s| (s.method, s.frames) = (method, frames)).expect("settings");
            let frame = renderer.render().expect("render");
            let hash = fnv1a(
                [&frame.radiance, &frame.direct, &frame.indirect, &frame.leaked]
                    .into_iter()
                    .flat_map(|l| layer_bytes(l))
                    .chain(frame.display.iter().flatten().copied()),
            );
            lines.push(format!("{path} {} {} {hash:016x}", choice.name(), method.name()));
        }
        renderer.gpu().check_validation().expect("validation clean");
    }
    Some((device, lines))
}

#[test]
fn every_shipped_scene_renders_as_recorded() {
    let Some(gpu) = common::gpu() else { return };
    let choices: Vec<BackendChoice> = common::backends(&gpu)
        .into_iter()
        .map(|b| if b == leakless::Backend::RayQuery { BackendChoice::RayQuery } else { BackendChoice::Compute })
        .collect();
    drop(gpu);
    let (mut device, mut lines) = (String::new(), Vec::new());
    for choice in choices {
        let Some((d, l)) = hash_lines(choice) else { return };
        (device, lines) = (d, [lines, l].concat());
    }
    let path = common::root().join(FIXTURE);
    if std::env::var("LEAKLESS_RECORD_HASHES").as_deref() == Ok("1") {
        let mut text = format!("# device: {device}\n");
        for l in &lines {
            writeln!(text, "{l}").unwrap();
        }
        std::fs::write(&path, text).expect("write the fixture");
        eprintln!("recorded {} image hashes on {device} in {FIXTURE}", lines.len());
        return;
    }
    let recorded = std::fs::read_to_string(&path).expect("tests/fixtures/image-hashes.txt");
    let recorded_device = recorded.lines().next().and_then(|l| l.strip_prefix("# device: ")).unwrap_or_default();
    if recorded_device != device {
        let why = format!(
            "image hashes were recorded on {recorded_device}, this is {device}: not compared \
             (LEAKLESS_RECORD_HASHES=1 records them here)"
        );
        // CI sets this: a new driver must be recorded on purpose, not skipped unnoticed.
        assert!(std::env::var("LEAKLESS_REQUIRE_HASHES").as_deref() != Ok("1"), "{why}");
        eprintln!("\n*** {why} ***\n");
        return;
    }
    let want: Vec<&str> = recorded.lines().skip(1).collect();
    let changed: Vec<String> = lines
        .iter()
        .filter(|l| !want.contains(&l.as_str()))
        .map(|l| format!("  now {l}"))
        .chain(want.iter().filter(|w| !lines.iter().any(|l| l == *w)).map(|w| format!("  was {w}")))
        .collect();
    assert!(changed.is_empty(), "images changed on {device}:\n{}", changed.join("\n"));
    eprintln!("{} image hashes as recorded on {device}", lines.len());
}
