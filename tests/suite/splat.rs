//! Photon splatting on the view-sample hierarchy: the hierarchy changes which photons are
//! tested, never the result; the energy is right; error falls with more photons and smaller
//! radii; a seed fixes the frame.

use crate::common;

use std::f64::consts::PI;

use glam::Vec3;
use leakless::{BackendChoice, Method, RenderSettings, Renderer, SplatSettings};
use leakless_scene::Camera;

fn settings(width: u32, height: u32, splat: SplatSettings, max_bounces: u32, seed: u32) -> RenderSettings {
    RenderSettings {
        width,
        height,
        backend: BackendChoice::Auto,
        method: Method::Splat,
        max_bounces,
        seed,
        splat,
        ..Default::default()
    }
}

/// Every photon against every view sample, in f64: what the hierarchy must reproduce.
fn brute_force(capture: &leakless::Capture, radius: f32) -> Vec<[f64; 3]> {
    let r = radius as f64;
    capture
        .position
        .iter()
        .zip(&capture.normal)
        .zip(&capture.albedo)
        .map(|((p, n), a)| {
            if p[3] <= 0.0 {
                return [0.0; 3];
            }
            let mut e = [0.0f64; 3];
            for ph in &capture.photons {
                let d = (0..3).map(|i| (p[i] as f64 - ph.position[i] as f64).powi(2)).sum::<f64>().sqrt();
                let facing = -(0..3).map(|i| n[i] as f64 * ph.direction[i] as f64).sum::<f64>();
                if d < r && facing > 0.0 {
                    let t = 1.0 - d * d / (r * r);
                    let k = 3.0 / (PI * r * r) * t * t;
                    for (ec, flux) in e.iter_mut().zip(ph.flux) {
                        *ec += flux as f64 * k;
                    }
                }
            }
            [0, 1, 2].map(|c| a[c] as f64 / PI * e[c])
        })
        .collect()
}

/// The node lists the gather read (`list_scatter.comp`): ranges that tile the list buffer in
/// node order, each holding a photon at most once (a node takes a photon once), every listed
/// photon on some list and no other. With the brute force below, which shows the lists hold
/// all that reaches each sample, this is what the linked lists held, each exactly once.
fn assert_contiguous_lists(capture: &leakless::Capture, stats: &leakless::splatting::SplatStats, what: &str) {
    let (ends, photons) = (&capture.list_ends, &capture.list_photons);
    assert!(!ends.is_empty(), "{what}: no list ends captured");
    assert_eq!(*ends.last().unwrap(), stats.list_entries, "{what}: the root's range ends the buffer");
    assert_eq!(photons.len() as u32, stats.list_entries, "{what}");
    let mut begin = 0u32;
    let mut listed = vec![false; stats.photons_stored as usize];
    for (node, &end) in ends.iter().enumerate() {
        assert!(begin <= end, "{what}: node {node}'s range [{begin}, {end}) runs backwards");
        let mut list: Vec<u32> = photons[begin as usize..end as usize].to_vec();
        list.sort_unstable();
        let len = list.len();
        list.dedup();
        assert_eq!(list.len(), len, "{what}: node {node} holds a photon twice");
        for &p in &list {
            assert!(p < stats.photons_stored, "{what}: node {node} lists photon {p} of {}", stats.photons_stored);
            listed[p as usize] = true;
        }
        begin = end;
    }
    let on_lists = listed.iter().filter(|&&l| l).count() as u32;
    assert_eq!(on_lists, stats.photons_listed, "{what}: photons on the lists against the splat's count");
}

#[test]
fn hierarchy_gather_equals_brute_force_with_and_without_trivial_accept() {
    // A radius large against the leaves, so that trivial accept really lists photons on
    // interior nodes (checked below through the entry counts).
    let radius = 0.25;
    for branching in [4, 8, 32] {
        let mut entries = Vec::new();
        for trivial_accept in [true, false] {
            let Some(gpu) = common::gpu() else { return };
            let scene = common::scene("scenes/cornell-box.gltf");
            let splat = SplatSettings {
                paths: 3000,
                radius: Some(radius),
                branching: Some(branching),
                trivial_accept,
                list_capacity: Some(1 << 22),
                ..Default::default()
            };
            let mut renderer = Renderer::new(gpu, &scene, settings(96, 72, splat, 4, 1)).unwrap();
            let frame = renderer.render().unwrap();
            let capture = renderer.capture().unwrap();
            let stats = frame.splat.clone().unwrap();
            assert_eq!((stats.photons_dropped, stats.list_entries_dropped), (0, 0));
            assert!(capture.photons.len() > 1000, "{} photons", capture.photons.len());
            assert_contiguous_lists(&capture, &stats, &format!("trivial_accept={trivial_accept} B={branching}"));
            let expected = brute_force(&capture, radius);
            let peak = expected.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
            for (i, (got, want)) in frame.indirect.iter().zip(&expected).enumerate() {
                for c in 0..3 {
                    let err = (got[c] as f64 - want[c]).abs();
                    assert!(
                        err <= 1e-5 * want[c].abs().max(1e-3 * peak),
                        "trivial_accept={trivial_accept} B={branching} pixel {i}: {} vs brute force {}",
                        got[c],
                        want[c]
                    );
                }
            }
            eprintln!(
                "trivial_accept={trivial_accept} B={branching}: {} candidate tests vs {} brute force ({:.2}%), {} list entries, {} node tests",
                stats.candidate_tests,
                stats.brute_force_tests,
                100.0 * stats.candidate_tests as f64 / stats.brute_force_tests as f64,
                stats.list_entries,
                stats.nodes_visited
            );
            assert!(stats.candidate_tests < stats.brute_force_tests, "{stats:?}");
            entries.push((stats.list_entries, stats.nodes_visited));
            renderer.gpu().check_validation().unwrap();
        }
        // A leaf of 32 samples spans more than the radius here: no node lies inside a sphere,
        // so with B = 32 the lists alone are checked (the GPU preset's width of a subgroup).
        if branching < 32 {
            assert!(entries[0].0 < entries[1].0, "trivial accept listed no photon on an inner node: {entries:?}");
            assert!(entries[0].1 < entries[1].1, "trivial accept saved no node tests: {entries:?}");
        }
    }
}

/// With the wide leaves' samples tested (the GPU preset's `leaf_samples`), a leaf's list holds
/// only photons some sample of it can gather. Where the Morton order jumps, a leaf's
/// consecutive samples lie far apart and its box meets a large share of all photons: each of its
/// samples then tested about 40% of them (the atrium at 10k paths: 4565 candidates against a
/// mean of 44), on a GPU a chain that the whole gather waited for. With the test the longest
/// sample tests a few times the mean, and no more at four times the photons; the image is the
/// one without it, bit for bit, and without it the longest sample tests a share of them all.
#[test]
fn no_sample_tests_a_share_of_all_photons() {
    for path in ["scenes/atrium.gltf", "scenes/doorway.gltf"] {
        let mut most = Vec::new();
        for paths in [10_000, 40_000] {
            let Some(gpu) = common::gpu() else { return };
            let report = gpu.report().clone();
            let cpu = leakless::DeviceTuning::choose(&report, leakless::TuningChoice::Cpu);
            let scene = common::scene(path);
            let splat = SplatSettings { paths, ..Default::default() };
            let render = |gpu, leaf_samples| {
                let tuning = leakless::DeviceTuning { leaf_samples, ..cpu.clone() };
                let mut renderer =
                    Renderer::with_tuning(gpu, &scene, settings(96, 72, splat.clone(), 8, 0), tuning).unwrap();
                let frame = renderer.render().unwrap();
                renderer.gpu().check_validation().unwrap();
                frame
            };
            let without = render(gpu, false);
            let frame = render(common::gpu().expect("a device"), true);
            assert!(
                frame.radiance == without.radiance && frame.indirect == without.indirect,
                "{path} {paths}: images differ"
            );
            let (stats, before) = (frame.splat.unwrap(), without.splat.unwrap());
            assert!(
                before.candidates_most as u64 * 10 > before.photons_stored as u64,
                "{path} {paths}: without the test the longest sample tested {} of {} photons",
                before.candidates_most,
                before.photons_stored
            );
            let mean = stats.candidate_tests as f64 / stats.valid_samples.max(1) as f64;
            eprintln!(
                "{path} {paths} paths: most {} candidates, mean {mean:.1}, {} photons",
                stats.candidates_most, stats.photons_stored
            );
            assert!(
                stats.candidates_most as f64 <= 8.0 * mean,
                "{path} {paths}: {} against a mean of {mean:.1}",
                stats.candidates_most
            );
            most.push(stats.candidates_most as f64);
        }
        assert!(most[1] <= 1.5 * most[0], "{path}: the longest sample grew with the photons: {most:?}");
    }
}

/// `capture` reads the photons of the last frame, every batch of them: an accumulation's third
/// frame traces 4 batches into a buffer 4 times one batch's size. It used to ask the pool for
/// one batch's size, which named another buffer, and copied past its end (a validation error).
#[test]
fn capture_reads_every_batch_of_an_accumulating_frame() {
    let Some(gpu) = common::gpu() else { return };
    let scene = common::scene("scenes/cornell-box.gltf");
    let batch = 2000;
    let splat = SplatSettings { paths: batch, ..Default::default() };
    // One stored photon per path at most, so 4 batches store more than one batch's buffer holds.
    let settings = RenderSettings { frames: 3, max_batches: 4, ..settings(32, 24, splat, 1, 1) };
    let mut renderer = Renderer::new(gpu, &scene, settings).unwrap();
    let frame = renderer.render().unwrap();
    let capture = renderer.capture().unwrap();
    renderer.gpu().check_validation().unwrap();
    let stats = frame.splat.clone().unwrap();
    assert_eq!(stats.paths, 4 * batch, "the last frame traces 4 batches");
    assert!(stats.photons_stored > batch, "{} photons stored", stats.photons_stored);
    assert_eq!(capture.photons.len(), stats.photons_stored as usize);
    let last_path = capture.photons.iter().map(|p| p.path).max().unwrap();
    assert!((3 * batch..4 * batch).contains(&last_path), "the fourth batch's photons: last path {last_path}");
    assert!(capture.photons.iter().all(|p| p.position.iter().all(|c| c.is_finite())), "photons read back");
}

/// The box the Morton codes are quantised to is exactly the box around the valid view samples.
/// `sample_bounds.comp` reduces each 8×8 workgroup in shared memory before its atomics. The
/// view holds the sphere seen from outside, off its centre: its extremes lie at single pixels, the
/// image is cut through workgroups at its edges (61×43), and the pixels beside the sphere have
/// no surface (and a zero position outside the box), which must not count.
#[test]
fn sample_bounds_are_the_box_around_the_valid_samples() {
    let Some(gpu) = common::gpu() else { return };
    let scene = common::scene("scenes/sphere.gltf");
    let splat = SplatSettings { paths: 500, ..Default::default() };
    let mut renderer = Renderer::new(gpu, &scene, settings(61, 43, splat, 2, 1)).unwrap();
    renderer.set_camera(Camera {
        world_from_camera: glam::camera::rh::view::look_at_mat4(Vec3::new(4.0, 0.6, 0.8), Vec3::ZERO, Vec3::Y)
            .inverse(),
        yfov: 0.6,
        znear: 0.01,
        zfar: None,
    });
    renderer.render().unwrap();
    let capture = renderer.capture().unwrap();
    let valid: Vec<&[f32; 4]> = capture.position.iter().filter(|p| p[3] > 0.0).collect();
    let without_surface = capture.position.len() - valid.len();
    eprintln!("{} samples with a surface, {without_surface} without", valid.len());
    assert!(!valid.is_empty() && without_surface > 0, "the view must hold both kinds of pixel");
    let mut expected = [[f32::INFINITY; 3], [f32::NEG_INFINITY; 3]];
    for p in &valid {
        for axis in 0..3 {
            expected[0][axis] = expected[0][axis].min(p[axis]);
            expected[1][axis] = expected[1][axis].max(p[axis]);
        }
    }
    // Each extreme is held by one sample: any sample the reduction missed would show.
    for (bound, side) in expected.iter().zip(["min", "max"]) {
        for axis in 0..3 {
            let holders = valid.iter().filter(|p| p[axis] == bound[axis]).count();
            eprintln!("{side} of axis {axis}: {} held by {holders} sample(s)", bound[axis]);
        }
    }
    assert!((0..3).any(|axis| expected[0][axis] > 0.0 || expected[1][axis] < 0.0), "the box holds the origin");
    assert_eq!(capture.sample_bounds, Some(expected));
    renderer.gpu().check_validation().unwrap();
}

/// Closed sphere (R = 1, ρ = 0.5, I = 1 W/sr at the centre): the photons stored on the wall
/// carry Φ·Σ_{k=1..K} ρ^k spread evenly over 4πR², so the indirect radiance is
/// L = ρ/π · I Σ_{k=1..K} ρ^k / R². Setting: 20k paths, K = 4, radius 0.2 R.
#[test]
fn sphere_indirect_energy_matches_the_closed_form() {
    let (rho, k) = (0.5f64, 4);
    let expected = rho / PI * (1..=k).map(|j| rho.powi(j)).sum::<f64>();
    for backend in common::choices() {
        let splat = SplatSettings { paths: 20_000, radius: Some(0.2), ..Default::default() };
        let frame = common::render_with(
            "scenes/sphere.gltf",
            RenderSettings { backend, ..settings(48, 48, splat, k as u32, 3) },
        )
        .unwrap();
        let mean = common::mean(&frame.indirect);
        eprintln!("{backend:?}: sphere mean indirect {mean:?}, closed form {expected}");
        for c in mean {
            assert!((c - expected).abs() / expected < 0.03, "{backend:?}: mean indirect {c} vs {expected}");
        }
    }
}

/// Error against the reference ground truth falls as paths grow and the radius shrinks.
#[test]
fn error_against_the_reference_falls_with_paths_and_radius() {
    let Some(reference) = common::reference("scenes/cornell-box.gltf", 4096, 8) else { return };
    let mut errors = Vec::new();
    for (paths, radius) in [(2_000, 0.12), (8_000, 0.07), (32_000, 0.04), (128_000, 0.025)] {
        let splat = SplatSettings { paths, radius: Some(radius), ..Default::default() };
        let frame = common::render_with("scenes/cornell-box.gltf", settings(64, 48, splat, 8, 1)).unwrap();
        let err = common::relative_rms(&frame.indirect, &reference.indirect);
        eprintln!("paths {paths}, radius {radius}: relative RMS error of the indirect layer {err:.4}");
        errors.push(err);
    }
    assert!(errors.windows(2).all(|w| w[1] < w[0]), "errors do not fall: {errors:?}");
}

#[test]
fn a_seed_fixes_the_frame() {
    for backend in common::choices() {
        let run = |seed| {
            let splat = SplatSettings { paths: 4000, ..Default::default() };
            common::render_with(
                "scenes/cornell-box.gltf",
                RenderSettings { backend, ..settings(40, 30, splat, 4, seed) },
            )
            .unwrap()
        };
        let (a, b, c) = (run(7), run(7), run(8));
        assert!(a.indirect == b.indirect && a.radiance == b.radiance, "{backend:?}: same seed, different frames");
        assert!(a.indirect != c.indirect, "{backend:?}: different seeds, same frame");
        assert!(a.indirect.iter().any(|p| p[0] > 0.0), "{backend:?}: no indirect light at all");
    }
}

/// A fixed list capacity that is too small drops entries, counts them, and writes nothing
/// past the buffer (validation stays clean); the default capacity grows to what a frame
/// needs and renders the frame again.
#[test]
fn list_overflow_is_counted_and_the_default_capacity_grows() {
    let splat = SplatSettings { paths: 2000, radius: Some(0.1), list_capacity: Some(100), ..Default::default() };
    let Some(frame) = common::render_with("scenes/cornell-box.gltf", settings(48, 36, splat, 4, 1)) else { return };
    let s = frame.splat.unwrap();
    assert_eq!((s.list_entries, s.list_capacity), (100, 100));
    assert!(s.list_entries_dropped > 1000, "{s:?}");

    let splat = SplatSettings { paths: 2000, radius: Some(0.3), ..Default::default() };
    let frame = common::render_with("scenes/cornell-box.gltf", settings(48, 36, splat, 4, 1)).unwrap();
    let s = frame.splat.unwrap();
    assert_eq!(s.list_entries_dropped, 0, "{s:?}");
    assert!(s.list_capacity > 2000 * 4 * 16, "the lists did not grow: {s:?}");

    // An accumulation whose lists grow restarts within the render, silently (its progress
    // never goes back to 0), once per growth rather than once more at the end, and is the
    // accumulation that never ran short, bit for bit (frames of 1, 2 and 4 batches).
    let accumulate = |list_capacity, progress: &mut Vec<(u32, u32)>| {
        let splat = SplatSettings { paths: 2000, radius: Some(0.3), list_capacity, ..Default::default() };
        let settings = RenderSettings { frames: 3, ..settings(48, 36, splat, 4, 1) };
        let gpu = common::gpu_with(settings.backend.wants_ray_queries()).expect("device");
        let mut r = Renderer::new(gpu, &common::scene("scenes/cornell-box.gltf"), settings).expect("renderer");
        let frame = r.render_with_progress(&mut |done, total| progress.push((done, total))).expect("render");
        r.gpu().check_validation().expect("validation clean");
        frame
    };
    let mut progress = Vec::new();
    let grown = accumulate(None, &mut progress);
    let ample = accumulate(Some(1 << 22), &mut Vec::new());
    let s = grown.splat.as_ref().unwrap();
    assert_eq!((grown.accumulated, grown.batches, s.list_entries_dropped), (3, 7, 0), "{s:?}");
    assert!(s.list_capacity > 4 * 2000 * 4 * 16, "the lists did not grow: {s:?}");
    assert!(grown.indirect == ample.indirect, "a restart after the lists grew changed the image");
    assert!(progress.iter().all(|&(done, _)| done > 0) && progress.last() == Some(&(3, 3)), "progress {progress:?}");
    eprintln!("an accumulation whose lists grew: progress {progress:?}");
}

/// Ordering the photons by grid cell before the splat (passes/photon_order.rs) changes which
/// thread walks which photon, never a pixel: a single frame and an accumulation's third frame
/// are bit-identical with and without it, in every layer, after the same node tests. And it
/// orders: the copy holds the same photons, each cell's in one run, where the trace's order
/// changes cell at almost every photon.
#[test]
fn ordering_photons_changes_no_pixel() {
    use leakless::passes::photon_order::cell;
    use leakless::passes::photons::Photon;
    for path in ["scenes/cornell-box.gltf", "scenes/doorway.gltf", "scenes/atrium.gltf"] {
        let scene = common::scene(path);
        let gpu = common::gpu_with(false).expect("device");
        let splat = SplatSettings { paths: 4000, ..Default::default() };
        let base = RenderSettings { method: Method::LeakLess, ..settings(64, 48, splat, 8, 1) };
        let mut r = Renderer::new(gpu, &scene, base).expect("renderer");
        let mut frames = Vec::new();
        let mut capture = None;
        for order in [true, false] {
            for count in [1, 3] {
                r.update(|s| (s.frames, s.splat.order_photons) = (count, order)).expect("settings");
                frames.push(r.render().expect("render"));
                if order && count == 1 {
                    capture = Some(r.capture().expect("capture"));
                }
            }
        }
        r.gpu().check_validation().expect("validation clean");
        for (name, (ordered, unordered)) in
            ["single frame", "third frame"].iter().zip(frames[..2].iter().zip(&frames[2..]))
        {
            assert!(ordered.radiance == unordered.radiance, "{path}: the {name}'s image differs");
            assert!(ordered.indirect == unordered.indirect, "{path}: the {name}'s indirect layer differs");
            assert!(ordered.leaked == unordered.leaked, "{path}: the {name}'s leaked layer differs");
            let (a, b) = (ordered.splat.as_ref().expect("stats"), unordered.splat.as_ref().expect("stats"));
            assert_eq!((a.nodes_visited, a.list_entries), (b.nodes_visited, b.list_entries), "{path}: the {name}");
        }

        let capture = capture.expect("captured");
        let bytes = |photons: &[Photon]| {
            let mut all: Vec<Vec<u8>> = photons.iter().map(|p| bytemuck::bytes_of(p).to_vec()).collect();
            all.sort();
            all
        };
        assert!(capture.photons.len() > 1000, "{path}: {} photons", capture.photons.len());
        assert!(bytes(&capture.ordered_photons) == bytes(&capture.photons), "{path}: not the same photons");
        let bounds = scene.bounds();
        let cells = |photons: &[Photon]| photons.iter().map(|p| cell(p.position, &bounds)).collect::<Vec<_>>();
        let runs = |cells: &[u32]| 1 + cells.windows(2).filter(|w| w[0] != w[1]).count();
        let mut distinct = cells(&capture.photons);
        distinct.sort_unstable();
        distinct.dedup();
        let (ordered, traced) = (runs(&cells(&capture.ordered_photons)), runs(&cells(&capture.photons)));
        eprintln!(
            "{path}: {} photons in {} cells: {ordered} runs of one cell ordered, {traced} as traced",
            capture.photons.len(),
            distinct.len()
        );
        // A photon on a cell's boundary may fall on the other side on the device.
        let bound = distinct.len() + capture.photons.len() / 100;
        assert!(ordered <= bound, "{path}: {ordered} runs");
        assert!(traced > bound, "{path}: the trace's order passes the bound as well ({traced} runs)");
    }
    // leakless-capped keeps a list's first photons: it reads them in the traced order.
    let gpu = common::gpu_with(false).expect("device");
    let capped = RenderSettings {
        method: Method::LeakLessCapped,
        ..settings(64, 48, SplatSettings { paths: 4000, ..Default::default() }, 8, 1)
    };
    let mut r = Renderer::new(gpu, &common::scene("scenes/cornell-box.gltf"), capped).expect("renderer");
    let frame = r.render().expect("render");
    let passes: Vec<&str> = frame.timings.iter().map(|t| t.name.as_str()).collect();
    assert!(passes.contains(&"splat") && !passes.contains(&"photon order"), "capped: {passes:?}");
    let capture = r.capture().expect("capture");
    assert!(
        !capture.photons.is_empty() && capture.ordered_photons.is_empty(),
        "the capped gather read ordered photons"
    );
}
