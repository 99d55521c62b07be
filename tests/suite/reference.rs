//! The reference path tracer as ground truth: deterministic, backend-independent, and with
//! noise low enough at a fixed budget to judge the splatting methods against.
//!
//! The Cornell-box ground truth is regenerated in the test run (64×48, 4096 spp): these tests
//! judge the path tracer itself. The sphere's closed form (tests/suite/trace.rs) pins it to an
//! analytic answer. The statistical tests' slower references are recorded, and read only while
//! a live canary render matches (`common::recorded`; tested last here).

use crate::common;

use leakless::{BackendChoice, Method, RenderSettings, RenderedFrame};

/// Samples per pixel of the Cornell ground truth.
pub const GROUND_TRUTH_SPP: u32 = 4096;

pub fn cornell_reference(backend: BackendChoice, seed: u32, spp: u32) -> Option<RenderedFrame> {
    common::render_with("scenes/cornell-box.gltf", cornell_settings(backend, seed, spp))
}

fn cornell_settings(backend: BackendChoice, seed: u32, spp: u32) -> RenderSettings {
    RenderSettings {
        width: 64,
        height: 48,
        backend,
        method: Method::Reference,
        spp,
        max_bounces: 8,
        seed,
        ..Default::default()
    }
}

/// The ground truth at two seeds, recorded (`common::recorded`: read while a live canary still
/// renders as recorded, so this judges what the path tracer renders today).
#[test]
fn cornell_ground_truth_noise_is_low() {
    let truth = |seed| {
        common::recorded::reference("cornell-box", cornell_settings(BackendChoice::Auto, seed, GROUND_TRUTH_SPP), |s| {
            common::render_with("scenes/cornell-box.gltf", s)
        })
    };
    let Some(a) = truth(1) else { return };
    let b = truth(2).unwrap();
    assert!(common::all_finite(&a.radiance));
    // Two independent estimates differ by √2 × the noise of one.
    let indirect_noise = common::relative_rms(&a.indirect, &b.indirect) / 2f64.sqrt();
    let image_noise = common::relative_rms(&a.radiance, &b.radiance) / 2f64.sqrt();
    eprintln!("Cornell reference at {GROUND_TRUTH_SPP} spp: relative RMS noise {indirect_noise:.4} (indirect), {image_noise:.4} (image)");
    assert!(image_noise < 0.015, "image noise {image_noise}");
    assert!(indirect_noise < 0.035, "indirect noise {indirect_noise}");
    // The indirect light is real: a sizeable share of the image (colour bleeding, the shadowed
    // block faces), and the direct layer is identical between seeds (it is exact).
    let (ind, tot) = (common::mean(&a.indirect), common::mean(&a.radiance));
    assert!(ind[0] > 0.1 * tot[0], "indirect {ind:?} vs total {tot:?}");
    assert_eq!(a.direct, b.direct);
}

#[test]
fn same_seed_is_bit_identical_and_another_seed_differs() {
    let Some(a) = cornell_reference(BackendChoice::Auto, 5, 16) else { return };
    let b = cornell_reference(BackendChoice::Auto, 5, 16).unwrap();
    let c = cornell_reference(BackendChoice::Auto, 6, 16).unwrap();
    assert!(a.radiance == b.radiance, "same seed, different image");
    assert!(a.radiance != c.radiance, "different seeds, same image");
}

#[test]
fn backends_give_the_same_reference() {
    let Some(gpu) = common::gpu() else { return };
    if common::backends(&gpu).len() < 2 {
        return;
    }
    drop(gpu);
    let rq = cornell_reference(BackendChoice::RayQuery, 3, 64).unwrap();
    let cs = cornell_reference(BackendChoice::Compute, 3, 64).unwrap();
    // Same seeds, same paths: only ties at edges (a different triangle of equal t) may differ.
    let diff = common::relative_rms(&rq.radiance, &cs.radiance);
    eprintln!("reference rayquery vs compute, same seed: relative RMS {diff:.2e}");
    assert!(diff < 1e-3, "backends differ by {diff}");
}

/// A recorded reference is read only while its canary still renders bit for bit as recorded:
/// recorded, it reads back exactly, without the whole render; with the canary's hash spoiled
/// (as a change to the renderer would), the whole reference is rendered again.
#[test]
fn recorded_references_are_read_only_while_their_canary_matches() {
    let dir = common::tmp_path("recorded-references");
    let _ = std::fs::remove_dir_all(&dir);
    let settings = RenderSettings {
        width: 16,
        height: 12,
        method: Method::Reference,
        spp: 64,
        max_bounces: 4,
        seed: 3,
        ..Default::default()
    };
    let whole_renders = std::cell::Cell::new(0);
    let render = |s: RenderSettings| {
        if s.spp == settings.spp {
            whole_renders.set(whole_renders.get() + 1);
        }
        common::render_with("scenes/cornell-box.gltf", s)
    };
    let get = |record| common::recorded::reference_in(&dir, record, "cornell-box", settings.clone(), render);
    let Some(recorded) = get(true) else { return };
    let [file] = &common::recorded::files(&dir)[..] else { panic!("one fixture written") };
    let read = get(false).unwrap();
    assert_eq!(whole_renders.get(), 1, "a matching canary renders only the canary");
    assert!(read.indirect == recorded.indirect && read.direct == recorded.direct && read.radiance == recorded.radiance);
    assert!(recorded.indirect.iter().any(|p| *p != [0.0; 3]), "the fixture holds light");

    common::recorded::spoil_canary(file);
    let live = get(false).unwrap();
    assert_eq!(whole_renders.get(), 2, "a stale fixture is rendered again");
    assert!(live.indirect == recorded.indirect, "the same settings render the same image");
}
