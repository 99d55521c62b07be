//! The stress scenes (scenes/stress/, docs/scenes.md): every method on both backends gives
//! finite, non-negative layers, and the outcomes each scene's `expected` extras name hold —
//! exactly zero in the dark room for the leak-free methods, a leak for `splat` — and
//! `leakless` leaves no lone black pixel among lit neighbours.

use crate::common;

use leakless::{Backend, BackendChoice, Method, RenderSettings, RenderedFrame, Renderer, Scene, SplatSettings};
use leakless_measure::extras::in_dark_box;
use leakless_measure::metrics::mean_luminance as image_luminance;

const METHODS: [Method; 5] =
    [Method::Direct, Method::Splat, Method::LeakLessCapped, Method::LeakLess, Method::Reference];

fn scenes() -> Vec<(String, Scene)> {
    let mut paths: Vec<_> = std::fs::read_dir(common::root().join("scenes/stress"))
        .expect("scenes/stress")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "gltf"))
        .collect();
    paths.sort();
    paths
        .into_iter()
        .map(|p| (p.file_stem().unwrap().to_string_lossy().into_owned(), Scene::load(&p).expect("loads")))
        .collect()
}

fn settings(backend: BackendChoice, method: Method) -> RenderSettings {
    RenderSettings {
        width: 48,
        height: 36,
        backend,
        method,
        spp: 4,
        max_bounces: 4,
        seed: 1,
        splat: SplatSettings { paths: 4000, ..Default::default() },
        ..Default::default()
    }
}

/// Lone black specks: pixels exactly black — no direct light and every gathered photon culled
/// (the `leaked` layer is lit) — on a surface whose neighbours in the same plane are mostly
/// lit directly. That is the signature of a view sample that starts inside a solid, where
/// every ray is blocked. (A black pixel in a dim region where the photons around are culled
/// leaks is not one: its neighbours have no direct light either.)
fn specks(frame: &RenderedFrame, position: &[[f32; 4]], normal: &[[f32; 4]]) -> Vec<(u32, u32)> {
    let (w, h) = (frame.width as i32, frame.height as i32);
    let v = |a: [f32; 4]| glam::Vec3::new(a[0], a[1], a[2]);
    let mut out = Vec::new();
    for y in 1..h - 1 {
        for x in 1..w - 1 {
            let i = (y * w + x) as usize;
            if position[i][3] <= 0.0 || frame.radiance[i] != [0.0; 3] || frame.leaked[i] == [0.0; 3] {
                continue;
            }
            let (p, n) = (v(position[i]), v(normal[i]));
            let mut direct: Vec<f32> = (-1..=1)
                .flat_map(|dy| (-1..=1).map(move |dx| ((y + dy) * w + x + dx) as usize))
                .filter(|&j| j != i && position[j][3] > 0.0)
                .filter(|&j| {
                    let d = v(position[j]) - p;
                    v(normal[j]).dot(n) > 0.95 && d.dot(n).abs() <= 0.02 * d.length()
                })
                .map(|j| frame.direct[j].iter().sum::<f32>())
                .collect();
            direct.sort_by(f32::total_cmp);
            if direct.len() >= 3 && direct[direct.len() / 2] > 0.0 {
                out.push((x as u32, y as u32));
            }
        }
    }
    out
}

/// The scenes where specks were seen, at 256², where they showed: no lone black pixel with
/// `leakless`, on both backends.
#[test]
fn leakless_leaves_no_lone_black_pixel() {
    let scenes = [
        "scenes/doorway.gltf",
        "scenes/atrium.gltf",
        "scenes/two-rooms.gltf",
        "scenes/stress/coplanar.gltf",
        "scenes/stress/coplanar-dark.gltf",
        "scenes/stress/door-gap.gltf",
    ];
    let mut failures = Vec::new();
    for backend in common::choices() {
        for path in scenes {
            let scene = common::scene(path);
            let s = RenderSettings { width: 256, height: 256, ..settings(backend, Method::LeakLess) };
            let gpu = common::gpu_with(backend.wants_ray_queries()).expect("device");
            let mut r = Renderer::new(gpu, &scene, s).expect("renderer");
            let frame = r.render().expect("render");
            let capture = r.capture().expect("capture");
            let s = specks(&frame, &capture.position, &capture.normal);
            eprintln!("{path} {backend:?}: {} lone black pixels", s.len());
            if !s.is_empty() {
                failures.push(format!("{path} {backend:?}: {} lone black pixels, first at {:?}", s.len(), s[0]));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

fn check_backend(backend: BackendChoice) {
    let Some(_) = common::gpu_with(backend.wants_ray_queries()) else { return };
    if !common::choices().contains(&backend) {
        return;
    }
    let mut failures = Vec::new();
    for (name, scene) in scenes() {
        let expected = common::extras(&scene)["expected"].clone();
        let gpu = common::gpu_with(backend.wants_ray_queries()).expect("device");
        let mut r = Renderer::new(gpu, &scene, settings(backend, Method::Direct)).expect("renderer");
        for method in METHODS {
            r.set_settings(settings(backend, method)).expect("settings");
            let frame = r.render().expect("render");
            let capture = r.capture().expect("capture");
            let what = format!("{name} {} {backend:?}", method.name());
            let bad = [&frame.radiance, &frame.direct, &frame.indirect, &frame.leaked]
                .iter()
                .flat_map(|l| l.iter())
                .filter(|p| p.iter().any(|c| !c.is_finite() || *c < 0.0))
                .count();
            if bad > 0 {
                failures.push(format!("{what}: {bad} NaN, infinite or negative values"));
            }
            let dark = in_dark_box(&scene, &capture.position);
            match (expected[method.name()].as_str(), &dark) {
                (Some("zero_in_dark"), Some(dark)) => {
                    let lit = (0..dark.len()).filter(|&i| dark[i] && frame.radiance[i] != [0.0; 3]).count();
                    if lit > 0 {
                        failures.push(format!("{what}: {lit} lit pixels in the dark box"));
                    }
                }
                (Some("leaks"), Some(dark)) => {
                    let lit = (0..dark.len()).filter(|&i| dark[i] && frame.indirect[i] != [0.0; 3]).count();
                    if lit == 0 && dark.iter().any(|d| *d) {
                        failures.push(format!("{what}: expected to leak into the dark box, and did not"));
                    }
                }
                _ => {}
            }
            if method == Method::LeakLess {
                let s = specks(&frame, &capture.position, &capture.normal);
                if !s.is_empty() {
                    failures.push(format!("{what}: {} lone black pixels among lit ones, first at {:?}", s.len(), s[0]));
                }
            }
        }
        r.gpu().check_validation().expect("validation clean");
    }
    assert!(failures.is_empty(), "{} failures:\n{}", failures.len(), failures.join("\n"));
}

#[test]
fn stress_scenes_on_the_compute_backend() {
    check_backend(BackendChoice::Compute);
}

#[test]
fn stress_scenes_on_ray_queries() {
    check_backend(BackendChoice::RayQuery);
}

/// A generated mesh one triangle beyond what the device can hold (lavapipe: 2^24 triangles,
/// one more than its maxPrimitiveCount, 2^24 − 1) fails with one line naming the limit and
/// the count, before anything is allocated on the device (no BVH or BLAS is built: that
/// would take minutes), on each backend.
#[test]
fn a_mesh_beyond_the_device_limits_fails_before_allocating() {
    let Some(gpu) = common::gpu_with(false) else { return };
    let limits = gpu.report().limits;
    drop(gpu);
    // Past both maxPrimitiveCount and the G-buffer's triangle ids, whichever is lower.
    let count = (limits.max_primitive_count as usize).min(leakless::gpu_scene::MAX_TRIANGLES) + 1;
    let scene = grid_mesh(count);
    assert_eq!(scene.triangle_count(), count);
    for backend in common::choices() {
        let gpu = common::gpu_with(backend.wants_ray_queries()).expect("device");
        let settings = RenderSettings { width: 32, height: 24, backend, ..Default::default() };
        // The refusal is `limits::check`'s, which the renderer runs before it uploads the scene
        // or builds anything (not a limit found after a build, or a time bound: a busy machine
        // would fail that without anything being wrong).
        let resolved = if backend == BackendChoice::RayQuery { Backend::RayQuery } else { Backend::Compute };
        let before_allocating = leakless::limits::check(&settings, &scene, resolved, &limits)
            .expect_err("limits::check refuses the scene")
            .to_string();
        let e = Renderer::new(gpu, &scene, settings).err().expect("a scene beyond the limits is refused").to_string();
        assert_eq!(e, before_allocating, "refused by the check made before anything is allocated");
        eprintln!("{backend:?}: {e}");
        assert!(!e.contains('\n'), "one line: {e}");
        assert!(e.contains(&format!("the scene's {count} triangles")), "{e}");
        if backend == BackendChoice::RayQuery && count as u64 > limits.max_primitive_count {
            assert!(e.contains(&format!("maxPrimitiveCount ({})", limits.max_primitive_count)), "{e}");
        }
    }
}

/// `count` triangles tiling a plane: a grid of 4096 quads a row, two triangles each.
fn grid_mesh(count: usize) -> Scene {
    use leakless_scene::{Light, LightKind, Material, Vertex};
    let v = |x: f32, z: f32| Vertex { position: [x, 0.0, z], normal: [0.0, 1.0, 0.0], uv: [0.0; 2] };
    let mut vertices = Vec::with_capacity(3 * count);
    for t in 0..count {
        let (quad, upper) = (t / 2, t % 2 == 1);
        let (x, z) = ((quad % 4096) as f32, (quad / 4096) as f32);
        if upper {
            vertices.extend([v(x + 1.0, z), v(x + 1.0, z + 1.0), v(x, z + 1.0)]);
        } else {
            vertices.extend([v(x, z), v(x + 1.0, z), v(x, z + 1.0)]);
        }
    }
    let light = Light {
        name: "bulb".into(),
        kind: LightKind::Point,
        position: glam::Vec3::new(2048.0, 10.0, 2048.0),
        direction: glam::Vec3::NEG_Y,
        color: glam::Vec3::ONE,
        intensity: 1.0,
        range: None,
    };
    Scene::from_triangles("grid", vertices, vec![0; count], vec![Material::default_white()], vec![light], None)
}

/// The sealed variants (zero-thickness quads at 1× and 1000×, the partition sweep) stay
/// exactly black in the dark room with `leakless`, frame after frame with fresh photons, on
/// both backends. One seed is not enough: a photon at the foot of a sealed partition used to
/// be seen from the other room about one frame in eight.
#[test]
fn sealed_variants_stay_black_frame_after_frame() {
    let sealed =
        ["sealed-quads", "sealed-quads-x1000", "partition-0mm", "partition-1mm", "partition-10mm", "partition-50mm"];
    let mut failures = Vec::new();
    for backend in common::choices() {
        for name in sealed {
            let scene = common::scene(&format!("scenes/stress/{name}.gltf"));
            // The scene's fixed radius: the count's radius in a sealed room, set by the culled
            // photons behind the wall, is tested in kernel_radius.rs (both backends, a
            // budget), and here each of 204 renders would probe first.
            let settings = RenderSettings {
                width: 64,
                height: 48,
                splat: SplatSettings {
                    paths: 10_000,
                    radius: Some(leakless::splatting::auto_radius(&scene)),
                    ..Default::default()
                },
                ..settings(backend, Method::LeakLess)
            };
            let gpu = common::gpu_with(backend.wants_ray_queries()).expect("device");
            let mut r = Renderer::new(gpu, &scene, settings).expect("renderer");
            r.render().expect("render");
            let dark = in_dark_box(&scene, &r.capture().expect("capture").position).expect("a dark box");
            assert!(dark.iter().any(|d| *d), "{name}: the camera sees the dark room");
            r.set_advance_seed(true);
            for frame in 0..16 {
                let f = r.render().expect("render");
                let lit = (0..dark.len()).filter(|&i| dark[i] && f.radiance[i] != [0.0; 3]).count();
                if lit > 0 {
                    failures.push(format!("{name} {backend:?} frame {frame}: {lit} lit pixels in the dark room"));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The reference path tracer keeps the sealed dark room exactly black too. A path vertex used to
/// be moved into its triangle toward the centroid; a ray from the lit room meeting the seam
/// where the zero-thickness wall stands on the floor was reported on the dark room's floor
/// triangle, and the path went on from beyond the wall: one sample in 1.7 million (seed 1,
/// 96×72, 256 spp; seed 0 was clean). Vertices now move back along the ray they arrived on.
#[test]
fn the_reference_does_not_leak_through_a_sealed_seam() {
    let scene = common::scene("scenes/stress/partition-0mm.gltf");
    for backend in common::choices() {
        let settings = RenderSettings {
            width: 96,
            height: 72,
            method: Method::Reference,
            spp: 256,
            seed: 1,
            ..settings(backend, Method::Reference)
        };
        let gpu = common::gpu_with(backend.wants_ray_queries()).expect("device");
        let mut r = Renderer::new(gpu, &scene, settings).expect("renderer");
        let frame = r.render().expect("render");
        let dark = in_dark_box(&scene, &r.capture().expect("capture").position).expect("a dark box");
        let lit: Vec<usize> = (0..dark.len()).filter(|&i| dark[i] && frame.radiance[i] != [0.0; 3]).collect();
        assert!(lit.is_empty(), "{backend:?}: lit dark-room pixels {lit:?}");
    }
}

/// The same for sealed-quads, whose walls are single quads sealed only by shared edges: its dark
/// room was seen lit by one reference sample (seed 1, 96×72, 256 spp, pixel (93, 51), both
/// backends) before path vertices near a triangle's boundary moved back along their ray (the
/// partition-0mm fix above). That render, then two more seeds at 64 spp.
#[test]
fn the_reference_keeps_sealed_quads_black_over_seeds() {
    let scene = common::scene("scenes/stress/sealed-quads.gltf");
    for backend in common::choices() {
        let at = |seed, spp| RenderSettings {
            width: 96,
            height: 72,
            spp,
            seed,
            max_bounces: 8,
            ..settings(backend, Method::Reference)
        };
        let gpu = common::gpu_with(backend.wants_ray_queries()).expect("device");
        let mut r = Renderer::new(gpu, &scene, at(1, 256)).expect("renderer");
        let mut frame = r.render().expect("render");
        let dark = in_dark_box(&scene, &r.capture().expect("capture").position).expect("a dark box");
        for (seed, spp) in [(1, 256), (2, 64), (3, 64)] {
            if seed > 1 {
                r.set_settings(at(seed, spp)).expect("settings");
                frame = r.render().expect("render");
            }
            let lit: Vec<usize> = (0..dark.len()).filter(|&i| dark[i] && frame.radiance[i] != [0.0; 3]).collect();
            assert!(lit.is_empty(), "{backend:?}, seed {seed}: lit dark-room pixels {lit:?}");
        }
        r.gpu().check_validation().expect("validation clean");
    }
}

/// A million metres out, a lift (30 m) is larger than the room's triangles (4 m). Moving a
/// reference vertex back along its ray by that much put it halfway to the previous vertex, off
/// every surface, and one sample in 1.8 million (96×72, 256 spp, seed 0, 8 bounces, both
/// backends) came out at 2·10¹³: a pixel of 6·10¹⁰ in a room whose direct light peaks at 7.
/// The bound asserted is loose, not exact: indirect light is direct light reflected by
/// surfaces of albedo below 1, and with the light hanging in the middle of the room, far from
/// every wall, no pixel's indirect comes near the brightest pixel's direct (0.24 against 7.1
/// with the fix; 6·10¹⁰ without it). Compute backend only: the firefly was on both, and the
/// backends' agreement is tested elsewhere.
#[test]
fn the_reference_has_no_firefly_a_million_metres_out() {
    let scene = common::scene("scenes/stress/far-degenerate.gltf");
    let backend = BackendChoice::Compute;
    if common::gpu_with(false).is_none() {
        return;
    }
    let settings = RenderSettings {
        width: 96,
        height: 72,
        spp: 256,
        max_bounces: 8,
        seed: 0,
        ..settings(backend, Method::Reference)
    };
    let gpu = common::gpu_with(false).expect("device");
    let frame = Renderer::new(gpu, &scene, settings).expect("renderer").render().expect("render");
    let max = |layer: &[[f32; 3]]| layer.iter().flat_map(|p| p.iter().copied()).fold(0.0f32, f32::max);
    let (direct, indirect) = (max(&frame.direct), max(&frame.indirect));
    eprintln!("far-degenerate reference: brightest direct {direct:.3}, brightest indirect {indirect:.3e}");
    assert!(direct > 0.0 && indirect < direct, "indirect {indirect:e} against direct {direct}");
}

/// Mean luminance of an image and the standard error of that mean over independent frames.
fn mean_and_error(frames: &[f64]) -> (f64, f64) {
    let n = frames.len() as f64;
    let mean = frames.iter().sum::<f64>() / n;
    let var = frames.iter().map(|m| (m - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

/// `frames` independent frames of `settings`' method (fresh photons, or fresh reference
/// samples), by a renderer the scene's methods share: settings are all a frame depends on.
fn frame_means(r: &mut Renderer, settings: RenderSettings, frames: u32) -> (f64, f64, u32) {
    let mut means = Vec::new();
    let mut capped = 0;
    for k in 0..frames {
        r.set_settings(RenderSettings { seed: settings.seed + 101 * k, ..settings.clone() }).expect("settings");
        let f = r.render().expect("render");
        capped += f.splat.as_ref().map_or(0, |s| s.capped_samples);
        means.push(image_luminance(&f.radiance));
    }
    let (m, e) = mean_and_error(&means);
    (m, e, capped)
}

/// No method adds light: on every stress scene, each image's mean stays within the noise of
/// the reference path tracer's at the same bounce depth (five standard errors of the
/// difference, from four independent frames of each, plus 2% for the kernel's blur, which
/// moves light across what the camera frames). The expected failures are asserted too: the
/// capped method loses energy where its cap binds, beyond the noise; and behind the door
/// with a 1 cm gap, where the only light comes through the gap, one frame of `leakless`
/// gathers several times the reference's light: photons in and beyond the gap are visible
/// from the floor behind it, and the kernel spreads their light over the radius (a
/// density-estimation bias, not a leak; docs/stability.md). And the reference may not hold
/// over twice `leakless`'s light, since an inflated reference would let every other check
/// pass. Compute backend (the backends' agreement is tested elsewhere).
#[test]
fn no_method_adds_energy_and_the_cap_loses_it() {
    if common::gpu_with(false).is_none() {
        return;
    }
    let base = RenderSettings {
        width: 64,
        height: 48,
        splat: SplatSettings { paths: 10_000, ..Default::default() },
        ..settings(BackendChoice::Compute, Method::Direct)
    };
    let mut failures = Vec::new();
    let mut cap_binds = 0;
    for (name, scene) in scenes() {
        let reference_settings = RenderSettings { method: Method::Reference, spp: 16, ..base.clone() };
        let gpu = common::gpu_with(false).expect("device");
        let mut r = Renderer::new(gpu, &scene, reference_settings.clone()).expect("renderer");
        let (reference, reference_error, _) = frame_means(&mut r, reference_settings, 4);
        if reference == 0.0 {
            continue; // the camera sees only the dark room: the leak tests cover it
        }
        let mut energy = |method| frame_means(&mut r, RenderSettings { method, ..base.clone() }, 4);
        let (leakless, leakless_error, _) = energy(Method::LeakLess);
        let (capped, capped_error, capped_samples) = energy(Method::LeakLessCapped);
        let (direct, direct_error, _) = energy(Method::Direct);
        r.gpu().check_validation().expect("validation clean");
        eprintln!(
            "{name}: reference {reference:.4e} ± {reference_error:.1e}; leakless {:.3}, capped {:.3} ({capped_samples} capped samples), direct {:.3}",
            leakless / reference,
            capped / reference,
            direct / reference
        );
        if name == "door-gap" {
            if leakless < 2.0 * reference {
                failures.push(format!(
                    "door-gap: leakless {leakless:.4e} no longer above twice the reference {reference:.4e}: the gap's bias vanished (update docs/stability.md)"
                ));
            }
            continue;
        }
        // Nor is the reference far brighter than `leakless` (unbiased up to the kernel's blur):
        // an inflated reference would let every check below pass.
        let noise = 5.0 * (reference_error.powi(2) + leakless_error.powi(2)).sqrt();
        if leakless + noise < 0.5 * reference {
            failures
                .push(format!("{name}: the reference {reference:.4e} has over twice leakless's light {leakless:.4e}"));
        }
        for (method, mean, error) in [
            ("leakless", leakless, leakless_error),
            ("leakless-capped", capped, capped_error),
            ("direct", direct, direct_error),
        ] {
            let allowed = reference * 1.02 + 5.0 * (reference_error.powi(2) + error.powi(2)).sqrt();
            if mean > allowed {
                failures.push(format!("{name} {method}: mean {mean:.4e} above the reference's {reference:.4e} beyond the noise ({allowed:.4e})"));
            }
        }
        if capped_samples > 0 {
            let noise = 5.0 * (leakless_error.powi(2) + capped_error.powi(2)).sqrt();
            if capped + noise < leakless {
                cap_binds += 1;
            } else if capped > leakless + noise {
                failures.push(format!("{name}: the cap binds ({capped_samples} samples), yet it adds energy: {capped:.4e} against leakless {leakless:.4e}"));
            }
        }
    }
    eprintln!("the cap loses energy beyond the noise in {cap_binds} scenes");
    assert!(
        cap_binds >= 5,
        "the cap lost energy in only {cap_binds} scenes (7 at this writing): the expected failure vanished"
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
