//! Photon tracing: energy against the closed sphere's geometric series, determinism, the
//! first hit never stored, overflow without out-of-bounds writes, backend agreement, and the
//! emitted power of spot and directional lights (closed form against numerical integration on
//! the CPU, and measured on the GPU by storing first hits on a floor that catches them).

use crate::common;

use std::f64::consts::PI;

use glam::{DVec3, Vec3};
use leakless::gpu_types::{Light, LIGHT_DIRECTIONAL, LIGHT_POINT, LIGHT_SPOT};
use leakless::passes::photons::{Photon, PhotonParams};
use leakless::photon_lights::{luminance, spot_falloff, spot_solid_angle, LightTable};
use leakless::{Backend, Gpu, Scene};
use leakless_measure::photon_tracer::{canonical_order, PhotonTrace, PhotonTracer};
use leakless_scene::Aabb;

fn v(a: [f32; 3]) -> DVec3 {
    DVec3::new(a[0] as f64, a[1] as f64, a[2] as f64)
}

fn trace(gpu: &Gpu, scene: &Scene, backend: Backend, capacity: u32, params: &PhotonParams) -> PhotonTrace {
    let mut tracer = PhotonTracer::new(gpu, scene, backend, capacity).expect("photon tracer");
    let t = tracer.trace(params).expect("trace photons");
    assert!(t.guard_intact, "{backend:?}: photons written past the capacity");
    t
}

/// A tracer of the Cornell box on the device's first backend, room for 40k photons.
fn cornell_tracer(gpu: &Gpu) -> (Backend, PhotonTracer<'_>) {
    let scene = common::scene("scenes/cornell-box.gltf");
    let backend = common::backends(gpu)[0];
    (backend, PhotonTracer::new(gpu, &scene, backend, 40_000).expect("photon tracer"))
}

fn sorted(mut photons: Vec<Photon>) -> Vec<Photon> {
    canonical_order(&mut photons);
    photons
}

// ------------------------------------------------------------------------------ CPU: powers

/// ∫ falloff dω by the midpoint rule over θ (dω = 2π sin θ dθ), independent of the closed
/// form's case analysis.
fn numeric_spot_solid_angle(cos_outer: f32, cos_inner: f32, max_theta: f64) -> f64 {
    let n = 400_000;
    let h = max_theta / n as f64;
    (0..n)
        .map(|i| {
            let theta = (i as f64 + 0.5) * h;
            spot_falloff(cos_outer, cos_inner, theta.cos()) * theta.sin() * h * 2.0 * PI
        })
        .sum()
}

#[test]
fn spot_power_matches_numerical_integration() {
    // (inner, outer) in radians: glTF's defaults, a soft cone, a hard one, inner > outer
    // (invalid glTF: light.glsl's Δ = 1e-4 floor), a wide one, a cone narrower than Δ.
    for (inner, outer) in [(0.0f32, 0.785f32), (0.2, 0.6), (0.5, 0.5), (0.7, 0.3), (1.0, 1.5), (0.0, 0.005)] {
        let (co, ci) = (outer.cos(), inner.cos());
        let closed = spot_solid_angle(co, ci);
        let numeric = numeric_spot_solid_angle(co, ci, PI);
        assert!((closed - numeric).abs() <= 1e-5 * numeric, "inner {inner} outer {outer}: {closed} vs {numeric}");
    }
    // A hard-edged cone is the cone's solid angle 2π(1 − cos θ), up to the 1e-4 ramp.
    let c = 0.5f32.cos();
    assert!((spot_solid_angle(c, c) - 2.0 * PI * (1.0 - c as f64)).abs() < 2.0 * PI * 1e-4);
}

fn light(kind: u32, intensity: [f32; 3], cos_outer: f32, cos_inner: f32) -> Light {
    Light { position: [0.0; 3], kind, direction: [0.0, -1.0, 0.0], cos_outer, intensity, cos_inner }
}

#[test]
fn light_cdf_is_proportional_to_luminance_of_power() {
    let bounds = Aabb { min: Vec3::splat(-1.0), max: Vec3::splat(1.0) };
    let lights = [
        light(LIGHT_POINT, [1.0, 1.0, 1.0], -1.0, -1.0),
        light(LIGHT_POINT, [0.0, 0.0, 0.0], -1.0, -1.0),
        light(LIGHT_DIRECTIONAL, [0.0, 2.0, 0.0], 1.0, 1.0),
        light(LIGHT_SPOT, [3.0, 0.0, 1.0], 0.8, 0.9),
        light(LIGHT_POINT, [0.0; 3], -1.0, -1.0),
    ];
    let t = LightTable::new(&lights, &Default::default(), &bounds);
    assert!((t.powers[0][1] - 4.0 * PI).abs() < 1e-9, "point: 4πI");
    // Directional: E·πR² with R = √3, the bounding radius of the cube.
    assert!((t.powers[2][1] - 2.0 * PI * 3.0).abs() < 1e-4, "directional: {}", t.powers[2][1]);
    assert!((t.powers[3][0] - 3.0 * spot_solid_angle(0.8, 0.9)).abs() < 1e-9, "spot");
    let lum: Vec<f64> = t.powers.iter().map(|p| luminance(*p)).collect();
    let total: f64 = lum.iter().sum();
    for (i, (p, l)) in t.probabilities.iter().zip(&lum).enumerate() {
        assert!((p - l / total).abs() < 1e-6, "light {i}: {p} vs {}", l / total);
    }
    assert_eq!((t.probabilities[1], t.probabilities[4]), (0.0, 0.0), "black lights are never chosen");
    assert_eq!((t.entries[3].cdf, t.entries[4].cdf), (1.0, 1.0));
    // The expected flux of one path, Σ p · power/p, is the total power, channel by channel.
    let total_power = t.total_power();
    for (c, power) in total_power.iter().enumerate() {
        let expected: f64 = t.entries.iter().zip(&t.probabilities).map(|(e, p)| p * e.flux[c] as f64).sum();
        assert!((expected - power).abs() <= 1e-6 * power, "channel {c}: {expected} vs {power}");
    }
    assert!(t.emits());
    assert!(!LightTable::new(&lights[1..2], &Default::default(), &bounds).emits());
}

// ---------------------------------------------------------------------------- GPU: photons

/// The closed sphere (R = 1, ρ = 0.5, I = 1 W/sr at the centre): every path hits the wall, so
/// the photons stored at bounce k carry ρ^k Φ/N each, Φ = 4πI, and all together Φ Σ ρ^k.
#[test]
fn sphere_photons_carry_the_geometric_series() {
    let Some(gpu) = common::gpu() else { return };
    let scene = common::scene("scenes/sphere.gltf");
    // Tessellation tolerance: the wall's triangles lie between their plane's distance to the
    // centre and the vertices' radius.
    let min_plane = scene
        .vertices
        .chunks(3)
        .map(|t| {
            let (a, b, c) = (v(t[0].position), v(t[1].position), v(t[2].position));
            (b - a).cross(c - a).normalize().dot(a).abs()
        })
        .fold(f64::INFINITY, f64::min);
    let (n, k_max, rho, phi) = (10_000u32, 3u32, 0.5f64, 4.0 * PI);
    for backend in common::backends(&gpu) {
        let params = PhotonParams { paths: n, max_bounces: k_max, seed: 1, store_direct: false, ..Default::default() };
        let t = trace(&gpu, &scene, backend, n * k_max, &params);
        assert_eq!(t.counters.overflowed, 0);
        assert_eq!(t.counters.stored as usize, t.photons.len());
        let mut count = vec![0u32; k_max as usize + 1];
        let mut total = DVec3::ZERO;
        for p in &t.photons {
            let (x, nrm, dir) = (v(p.position), v(p.normal), v(p.direction));
            assert!((1..=k_max).contains(&p.bounce), "bounce {}", p.bounce);
            assert!(p.path < n);
            assert!(x.length() >= min_plane - 1e-5 && x.length() <= 1.0 + 1e-5, "photon at radius {}", x.length());
            assert!((nrm.length() - 1.0).abs() < 1e-5 && (dir.length() - 1.0).abs() < 1e-5, "{p:?}");
            assert!(nrm.dot(-x) > 0.99 * x.length(), "normal not inward: {p:?}");
            assert!(nrm.dot(dir) < 0.0, "normal does not face the incoming photon: {p:?}");
            let expected = rho.powi(p.bounce as i32) * phi / n as f64;
            for c in 0..3 {
                assert!((p.flux[c] as f64 - expected).abs() <= 1e-6 * expected, "{p:?}: expected flux {expected}");
            }
            count[p.bounce as usize] += 1;
            total += v(p.flux);
        }
        // A path ends early only when a cosine-sampled bounce dips below the facet (smooth
        // normals ≠ facet normals) or a ray slips between triangles: a few in 10⁴.
        let ideal: f64 = (1..=k_max).map(|k| phi * rho.powi(k as i32)).sum();
        let deficit = 1.0 - total.x / ideal;
        eprintln!("{backend:?}: {} photons, per bounce {:?} of {n}; total flux {:.6} W vs Φ Σρ^k = {ideal:.6} W (deficit {deficit:.2e})",
            t.photons.len(), &count[1..], total.x);
        for k in 1..=k_max as usize {
            assert!(count[k] <= n && count[k] as f64 >= 0.998 * n as f64, "bounce {k}: {} photons", count[k]);
            assert!(k == 1 || count[k] <= count[k - 1], "a path stores its hits in order");
        }
        assert!((0.0..2e-3).contains(&deficit), "deficit {deficit}");
        assert_eq!(total.x, total.y);
        assert_eq!(total.y, total.z);
    }
    gpu.check_validation().expect("validation clean");
}

#[test]
fn same_seed_same_photons_another_seed_others() {
    let Some(gpu) = common::gpu() else { return };
    let (backend, mut tracer) = cornell_tracer(&gpu);
    let params = PhotonParams { paths: 4096, max_bounces: 8, seed: 11, store_direct: false, ..Default::default() };
    let a = tracer.trace(&params).unwrap();
    let b = tracer.trace(&params).unwrap();
    let c = tracer.trace(&PhotonParams { seed: 12, ..params }).unwrap();
    assert!(a.photons.len() > 4096, "{} photons", a.photons.len());
    eprintln!(
        "{backend:?}: {} photons; buffer order {} between runs",
        a.photons.len(),
        if a.photons == b.photons { "identical" } else { "differs (atomic append)" }
    );
    assert_eq!(a.counters, b.counters);
    let (a, b, c) = (sorted(a.photons), sorted(b.photons), sorted(c.photons));
    assert!(a == b, "same seed, different photons");
    // Another seed: another point set. Compare the first photon of every path.
    let first = |s: &[Photon]| -> Vec<[f32; 3]> { s.iter().filter(|p| p.bounce == 1).map(|p| p.position).collect() };
    let (fa, fc) = (first(&a), first(&c));
    let same = fa.iter().zip(&fc).filter(|(x, y)| x == y).count();
    assert!(same < fa.len() / 100, "seeds 11 and 12 share {same} of {} first photons", fa.len());
    gpu.check_validation().expect("validation clean");
}

/// Threads that take the next path when theirs ends (CPU devices) trace exactly the paths one
/// thread a path (GPUs) traces: every path once, none twice, the same photons and rays, also
/// when the threads do not divide the paths evenly, and whether they take the paths in
/// emission order (emission_order.rs) or in index order.
#[test]
fn every_path_is_traced_once_however_many_a_thread_takes() {
    let Some(gpu) = common::gpu() else { return };
    let (_, mut tracer) = cornell_tracer(&gpu);
    let params = PhotonParams { paths: 3001, max_bounces: 8, seed: 5, store_direct: true, ..Default::default() };
    let mut traces = Vec::new();
    let mut gaps = Vec::new();
    for (per_thread, emission_order) in [(1, true), (8, true), (7, true), (3001, true), (1, false), (8, false)] {
        tracer.set_paths_per_thread(per_thread);
        let t = tracer.trace(&PhotonParams { emission_order, ..params }).unwrap();
        // How far apart the first hits of neighbouring threads lie, in the order they were stored.
        let first: Vec<DVec3> = t.photons.iter().filter(|p| p.bounce == 0).map(|p| v(p.position)).collect();
        let gap = first.windows(2).map(|w| (w[1] - w[0]).length()).sum::<f64>() / (first.len() - 1) as f64;
        gaps.push((per_thread, emission_order, gap));
        traces.push((per_thread, t.counters, sorted(t.photons)));
    }
    // The order groups what it should: one path a thread, neighbouring threads' first hits lie
    // far closer together taken in emission order than in index order (Sobol points spread).
    let gap = |per_thread, ordered| gaps.iter().find(|g| (g.0, g.1) == (per_thread, ordered)).expect("traced").2;
    eprintln!(
        "mean gap between consecutive first hits: {:.4} in emission order, {:.4} in index order",
        gap(1, true),
        gap(1, false)
    );
    assert!(gap(1, true) < 0.5 * gap(1, false), "emission order does not group the paths");
    let (_, counters, photons) = &traces[0];
    // No path twice: one photon per (path, bounce); paths that escape through the open front
    // before a hit store nothing.
    let keys: std::collections::BTreeSet<(u32, u32)> = photons.iter().map(|p| (p.path, p.bounce)).collect();
    assert_eq!(keys.len(), photons.len(), "a path traced twice");
    let paths: std::collections::BTreeSet<u32> = photons.iter().map(|p| p.path).collect();
    assert!(paths.len() > 2500 && paths.iter().all(|&p| p < 3001), "{} paths stored photons", paths.len());
    for (per_thread, c, p) in &traces {
        assert_eq!((c.stored, c.rays), (counters.stored, counters.rays), "{per_thread} paths a thread");
        assert!(p == photons, "{per_thread} paths a thread: other photons");
        // Every thread's last fetch finds the paths used up: one fetch per path in all. With a
        // thread per path (a GPU's tuning) there is nothing to fetch, and no thread fetches.
        let fetches = if *per_thread == 1 { 0 } else { 3001 };
        assert_eq!(c.next_path, fetches, "{per_thread} paths a thread");
    }
    eprintln!(
        "{} photons from {} paths, the same at 1, 8, 7 and 3001 paths a thread, in emission and index order",
        photons.len(),
        paths.len()
    );
    gpu.check_validation().expect("validation clean");
}

/// A single floor under a point light: whatever leaves the floor escapes, so there is never a
/// second hit and nothing may be stored. With `store_direct` the first hits are there.
#[test]
fn the_first_hit_is_never_stored() {
    let Some(gpu) = common::gpu() else { return };
    let scene = common::scene("tests/scenes/floor-light.gltf");
    for backend in common::backends(&gpu) {
        let mut tracer = PhotonTracer::new(&gpu, &scene, backend, 50_000).unwrap();
        let params = PhotonParams { paths: 10_000, max_bounces: 8, seed: 3, store_direct: false, ..Default::default() };
        let t = tracer.trace(&params).unwrap();
        assert_eq!((t.counters.stored, t.counters.overflowed, t.photons.len()), (0, 0, 0), "{backend:?}");
        // Control: the same paths do hit the floor: those inside the solid angle of the
        // 20 m square seen from 1 m above its centre, Ω = 4 asin(a²/(a² + h²)).
        let direct = tracer.trace(&PhotonParams { store_direct: true, ..params }).unwrap();
        assert!(direct.photons.iter().all(|p| p.bounce == 0 && p.position[1].abs() < 1e-6));
        let expected = 10_000.0 * 4.0 * (100.0f64 / 101.0).asin() / (4.0 * PI);
        let hits = direct.photons.len() as f64;
        assert!((hits - expected).abs() < 10.0, "{backend:?}: {hits} first hits, expected {expected:.1}");
        // max_bounces 0: no stored hit at all.
        let none = tracer.trace(&PhotonParams { max_bounces: 0, ..params }).unwrap();
        assert_eq!(none.counters.stored, 0);
    }
    gpu.check_validation().expect("validation clean");
}

#[test]
fn overflow_is_counted_and_nothing_is_written_past_the_capacity() {
    let Some(gpu) = common::gpu() else { return };
    let scene = common::scene("scenes/cornell-box.gltf");
    let params = PhotonParams { paths: 4096, max_bounces: 4, seed: 5, store_direct: false, ..Default::default() };
    for backend in common::backends(&gpu) {
        let all = trace(&gpu, &scene, backend, 4096 * 4, &params);
        assert_eq!(all.counters.overflowed, 0);
        let every = sorted(all.photons);
        for capacity in [1u32, 100, 1000] {
            let t = trace(&gpu, &scene, backend, capacity, &params);
            assert_eq!(t.counters.stored, capacity, "{backend:?}");
            assert_eq!(t.counters.stored + t.counters.overflowed, every.len() as u32, "{backend:?}: all accounted for");
            // What was kept is real photons (the guard check in `trace` saw no write beyond).
            for p in &t.photons {
                assert!(every
                    .binary_search_by_key(&(p.path, p.bounce), |q| (q.path, q.bounce))
                    .is_ok_and(|i| every[i] == *p));
            }
        }
    }
    gpu.check_validation().expect("validation clean");
}

#[test]
fn backends_trace_the_same_photons() {
    let Some(gpu) = common::gpu() else { return };
    let backends = common::backends(&gpu);
    if backends.len() < 2 {
        return;
    }
    for (path, k) in [("scenes/cornell-box.gltf", 8u32), ("scenes/sphere.gltf", 4)] {
        let scene = common::scene(path);
        let params = PhotonParams { paths: 10_000, max_bounces: k, seed: 7, store_direct: false, ..Default::default() };
        let [rq, cs] =
            [Backend::RayQuery, Backend::Compute].map(|b| sorted(trace(&gpu, &scene, b, 10_000 * k, &params).photons));
        let key = |p: &Photon| (p.path, p.bounce);
        let worst = rq
            .iter()
            .zip(&cs)
            .map(|(a, b)| {
                assert_eq!(key(a), key(b), "{path}: the backends stored different photons");
                (v(a.position) - v(b.position)).length()
            })
            .fold(0.0, f64::max);
        eprintln!("{path}: {} photons on both backends, positions within {worst:.1e}", rq.len());
        assert_eq!(rq.len(), cs.len(), "{path}");
        // The two backends' intersection tests round differently; along up to 8 bounces the
        // paths drift apart by a few ten-thousandths of the scene's size.
        let tolerance = 5e-4 * leakless::trace::scene_scale(&scene) as f64;
        assert!(worst < tolerance, "{path}: positions differ by {worst} (tolerance {tolerance})");
    }
    gpu.check_validation().expect("validation clean");
}

/// tests/scenes/spot-sun.gltf: a 2 m floor catching a downward spot's whole cone and a 45° sun.
/// Storing the first hits measures what each light emits.
#[test]
fn spot_and_directional_emit_their_power() {
    let Some(gpu) = common::gpu() else { return };
    let scene = common::scene("tests/scenes/spot-sun.gltf");
    let spot_index = scene.lights.iter().position(|l| l.name == "spot").unwrap();
    let sun_index = scene.lights.iter().position(|l| l.name == "sun").unwrap();
    let spot = &scene.lights[spot_index];
    let (co, ci) = match spot.kind {
        leakless_scene::LightKind::Spot { inner_cone, outer_cone } => (outer_cone.cos(), inner_cone.cos()),
        _ => unreachable!(),
    };
    let height = spot.position.y as f64;
    let n = 1u32 << 16;
    for backend in common::backends(&gpu) {
        let mut tracer = PhotonTracer::new(&gpu, &scene, backend, n).unwrap();
        let table = tracer.light_table().clone();
        let params = PhotonParams { paths: n, max_bounces: 0, seed: 9, store_direct: true, ..Default::default() };
        let t = tracer.trace(&params).unwrap();
        let of = |light: usize| t.photons.iter().filter(move |p| p.light as usize == light);
        for p in &t.photons {
            assert_eq!(p.bounce, 0);
            assert!(p.position[1].abs() < 1e-6 && p.normal == [0.0, 1.0, 0.0], "{p:?}");
        }

        // Spot: every path hits the floor; its photons sum to its power.
        let spot_flux = of(spot_index).fold(DVec3::ZERO, |s, p| s + v(p.flux));
        let spot_paths = of(spot_index).count();
        let power = DVec3::from(table.powers[spot_index]);
        let p_spot = table.probabilities[spot_index];
        eprintln!(
            "{backend:?}: spot {spot_paths} paths (expected {:.1}), flux {spot_flux:.5} vs power {power:.5}",
            p_spot * n as f64
        );
        assert!((spot_paths as f64 - p_spot * n as f64).abs() <= 2.0, "light selection is stratified");
        assert!(((spot_flux - power) / power).abs().max_element() < 1e-4, "{spot_flux} vs {power}");
        // Its angular distribution is the falloff's: the share of its flux within radius r of
        // the axis is ∫_{θ<atan(r/h)} f dω / ∫ f dω.
        let total = spot_solid_angle(co, ci);
        for r in [0.1, 0.2, 0.3, 0.4, 0.5, 0.6] {
            let expected = numeric_spot_solid_angle(co, ci, (r / height).atan()) / total;
            let inside = of(spot_index)
                .filter(|p| (p.position[0] as f64).hypot(p.position[2] as f64) < r)
                .fold(0.0, |s, p| s + p.flux[1] as f64)
                / spot_flux.y;
            assert!((inside - expected).abs() < 3e-3, "r = {r}: {inside} of the flux inside, expected {expected}");
        }
        for p in of(spot_index) {
            let to = (v(p.position) - v(spot.position.to_array())).normalize();
            assert!((to - v(p.direction)).length() < 1e-4, "{p:?}");
        }

        // Sun: E·A·sin(elevation) lands on the floor (area A = 4 m², elevation 45°).
        let sun = &scene.lights[sun_index];
        let sun_flux = of(sun_index).fold(DVec3::ZERO, |s, p| s + v(p.flux));
        let e = DVec3::from((sun.color * sun.intensity).to_array().map(f64::from));
        let expected = e * 4.0 * (-sun.direction.y as f64);
        eprintln!("{backend:?}: sun flux on the floor {sun_flux:.5} vs E·A·cos {expected:.5}");
        assert!(((sun_flux - expected) / expected).abs().max_element() < 5e-3, "{sun_flux} vs {expected}");
        for p in of(sun_index) {
            assert!((v(p.direction) - v(sun.direction.to_array())).length() < 1e-6);
        }
    }
    gpu.check_validation().expect("validation clean");
}

/// Photon-tracing time in the Cornell box (printed; `--nocapture` shows it).
#[test]
fn cornell_photon_timings() {
    let Some(gpu) = common::gpu() else { return };
    let scene = common::scene("scenes/cornell-box.gltf");
    for backend in common::backends(&gpu) {
        let mut tracer = PhotonTracer::new(&gpu, &scene, backend, 800_000).unwrap();
        for paths in [10_000u32, 100_000] {
            let params = PhotonParams { paths, max_bounces: 8, seed: 0, store_direct: false, ..Default::default() };
            let runs: Vec<PhotonTrace> = (0..3).map(|_| tracer.trace(&params).unwrap()).collect();
            let best = runs.iter().map(|r| r.trace_ms).fold(f64::INFINITY, f64::min);
            let stored = runs[0].counters.stored;
            assert_eq!(runs[0].counters.overflowed, 0);
            eprintln!(
                "{backend:?}: {paths} paths, {stored} photons, {best:.1} ms (best of 3), {:.2} Mphotons/s",
                stored as f64 / best / 1e3
            );
        }
    }
    gpu.check_validation().expect("validation clean");
}
