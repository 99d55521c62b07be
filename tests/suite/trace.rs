//! Both trace backends: they agree ray by ray, they are watertight, shadows are exact, and
//! the reference path tracer converges to the closed sphere's analytic radiance.

use crate::common;

use std::f32::consts::PI;

use glam::Vec3;
use leakless::gpu_types::{GpuRay, RayHit};
use leakless::{Backend, BackendChoice, Method, RenderSettings, RenderedFrame};
use leakless_measure::raycast::RayCaster;
use leakless_measure::raygen;

const MISS: u32 = u32::MAX;

/// Distance of barycentrics from the triangle's boundary.
fn edge_distance(h: &RayHit) -> f32 {
    let [u, v] = h.barycentrics;
    u.min(v).min(1.0 - u - v)
}

/// `bench rays` times the traversal, not the hits' way to the host: the timed pass writes
/// device-local memory, and a copy after it brings the hits back (on a discrete GPU the hits
/// were written across the bus into host memory, timing the bus at one rate for every kind of
/// ray). The copy brings every hit: each backend's hits of the same rays are the ones it
/// reports, ray for ray, against a second cast.
#[test]
fn bench_rays_times_no_host_visible_write() {
    let Some(gpu) = common::gpu() else { return };
    let scene = common::scene("scenes/cornell-box.gltf");
    let rays = raygen::random_rays(&scene, 4096, 5);
    for backend in common::backends(&gpu) {
        let mut caster = RayCaster::new(&gpu, &scene, backend).unwrap();
        let cast = caster.cast(&rays, false).unwrap();
        assert_eq!(cast.hits_written_to, leakless_device::MemoryLocation::GpuOnly, "{backend:?}");
        assert!(cast.trace_ms > 0.0, "{backend:?}: the raycast pass is timed");
        assert_eq!(cast.hits.len(), rays.len());
        let hit = cast.hits.iter().filter(|h| h.triangle != MISS && h.t > 0.0).count();
        assert!(hit > rays.len() / 2, "{backend:?}: {hit} of {} rays hit inside the closed box", rays.len());
        let again = caster.cast(&rays, false).unwrap().hits;
        assert!(cast.hits.iter().zip(&again).all(|(a, b)| a.triangle == b.triangle && a.t == b.t), "{backend:?}");
    }
    gpu.check_validation().unwrap();
}

/// `bench rays` counts the compute traversal's work per ray with a pass of its own
/// (`TRACE_COUNT_WORK`): the counts are what the CPU twin of the traversal (`Bvh::traverse`)
/// counts on the same tree, ray for ray, for closest hits and occlusion. The static Cornell
/// box is one part whose tree is `Bvh::build` of its triangles.
#[test]
fn the_counted_traversal_work_is_the_cpu_traversals() {
    let Some(gpu) = common::gpu() else { return };
    let scene = common::scene("scenes/cornell-box.gltf");
    let rays = raygen::random_rays(&scene, 256, 3);
    let bvh = leakless_accel::Bvh::build(&scene.vertices).unwrap();
    let mut caster = RayCaster::new(&gpu, &scene, Backend::Compute).unwrap();
    for occlusion in [false, true] {
        let work = caster.count_work(&rays, occlusion).unwrap().expect("the compute backend counts");
        let mut differ = Vec::new();
        for (i, (ray, w)) in rays.iter().zip(&work).enumerate() {
            let mut counts = leakless_accel::bvh::TraversalCounts::default();
            bvh.traverse(
                leakless_accel::RayQuery {
                    origin: ray.origin,
                    dir: ray.dir,
                    tmin: ray.tmin,
                    tmax: ray.tmax,
                    any_hit: occlusion,
                },
                |_, _| true,
                &mut counts,
            );
            if (counts.nodes, counts.triangles) != (w.nodes as u64, w.triangles as u64) {
                differ.push(format!("ray {i}: GPU {w:?}, CPU {counts:?}"));
            }
        }
        assert!(
            differ.is_empty(),
            "occlusion {occlusion}: {} of {} rays differ: {:?}",
            differ.len(),
            rays.len(),
            &differ[..differ.len().min(5)]
        );
        // A ray that misses the root's box (or starts beyond it) does no work, here as there.
        let worked = work.iter().filter(|w| w.nodes > 0).count();
        assert!(worked > rays.len() / 2, "occlusion {occlusion}: {worked} of {} rays entered the tree", rays.len());
    }
    if common::backends(&gpu).contains(&Backend::RayQuery) {
        let mut rq = RayCaster::new(&gpu, &scene, Backend::RayQuery).unwrap();
        assert!(rq.count_work(&rays, false).unwrap().is_none(), "ray queries count nothing");
    }
    gpu.check_validation().unwrap();
}

#[test]
fn backends_agree_on_random_rays() {
    let Some(gpu) = common::gpu() else { return };
    let backends = common::backends(&gpu);
    if backends.len() < 2 {
        return;
    }
    // The door half shut: its leaf, handle and bolt are instances in their own BLASes (ray
    // queries) and bottom-level BVHs (compute), placed by a rotation.
    let door = common::scene("scenes/door.gltf").frozen_at(1.0);
    for (path, scene) in [
        ("scenes/cornell-box.gltf", common::scene("scenes/cornell-box.gltf")),
        ("scenes/sphere.gltf", common::scene("scenes/sphere.gltf")),
        ("scenes/door.gltf at t = 1", door),
    ] {
        let rays = raygen::random_rays(&scene, 100_000, 11);
        let b = scene.bounds();
        let magnitude = b.min.abs().max(b.max.abs()).max_element();
        let mut rq = RayCaster::new(&gpu, &scene, Backend::RayQuery).unwrap();
        let mut cs = RayCaster::new(&gpu, &scene, Backend::Compute).unwrap();
        for occlusion in [false, true] {
            let a = rq.cast(&rays, occlusion).unwrap().hits;
            let b = cs.cast(&rays, occlusion).unwrap().hits;
            let closest = if occlusion { None } else { Some((&a, &b)) };
            let mut disagreements = 0;
            for (i, (x, y)) in a.iter().zip(&b).enumerate() {
                if (x.triangle == MISS) != (y.triangle == MISS) {
                    // A tie: the hit lies within 1e-5 of an edge, or at the ray's extent.
                    let h = if x.triangle != MISS { x } else { y };
                    let at_extent = !occlusion && (h.t - rays[i].tmax).abs() <= 1e-4 * rays[i].tmax;
                    assert!(
                        occlusion || edge_distance(h) < 1e-5 || at_extent,
                        "{path} ray {i}: rayquery {x:?} vs compute {y:?} (not at an edge)"
                    );
                    disagreements += 1;
                }
            }
            assert!(disagreements <= 10, "{path}: {disagreements} hit/miss disagreements in 100000 rays");
            if let Some((a, b)) = closest {
                for (i, (x, y)) in a.iter().zip(b.iter()).enumerate() {
                    if x.triangle != MISS && y.triangle != MISS {
                        // Relative, plus a few ulps of the scene's coordinates: a ray moved into an
                        // instance's space has its origin rounded by that much, on each backend
                        // its own way, which moves t by as much however short the ray.
                        let tolerance = 1e-4 * x.t.max(1e-3) + 8.0 * f32::EPSILON * magnitude;
                        assert!((x.t - y.t).abs() <= tolerance, "{path} ray {i}: t {} vs {}", x.t, y.t);
                        if x.triangle != y.triangle {
                            // Only a shared edge or surfaces that meet at the hit (the same t as
                            // the check above measures it: the door scene's boxes
                            // interpenetrate, so a ray can end on the line where a wall's face
                            // crosses the ceiling's, inside both triangles) may pick another
                            // triangle.
                            let tie = (x.t - y.t).abs() <= tolerance;
                            assert!(
                                edge_distance(x) < 1e-4 || edge_distance(y) < 1e-4 || tie,
                                "{path} ray {i}: {x:?} vs {y:?}"
                            );
                        }
                    }
                }
            }
        }
    }
    gpu.check_validation().unwrap();
}

/// Rays from inside a closed mesh aimed exactly at its shared edges and vertices must hit.
#[test]
fn closed_mesh_is_watertight_on_both_backends() {
    let Some(gpu) = common::gpu() else { return };
    let lavapipe = gpu.report().name.contains("llvmpipe");
    let scene = common::scene("scenes/sphere.gltf");
    let p = |i: usize| Vec3::from(scene.vertices[i].position);
    let mut targets = Vec::new();
    for t in 0..scene.triangle_count() {
        for e in 0..3 {
            let (a, b) = (p(3 * t + e), p(3 * t + (e + 1) % 3));
            targets.push(a); // a vertex shared by ~6 triangles
            for s in [0.5f32, 0.25, 0.125, 1.0 / 3.0] {
                targets.push(a + s * (b - a)); // points on a shared edge
            }
        }
    }
    for origin in [Vec3::ZERO, Vec3::new(0.1, -0.2, 0.05), Vec3::new(-0.31, 0.4, 0.22)] {
        let rays: Vec<GpuRay> = targets
            .iter()
            .map(|&t| GpuRay {
                origin: origin.to_array(),
                tmin: 0.0,
                dir: (t - origin).normalize().to_array(),
                tmax: 1e30,
            })
            .collect();
        for backend in common::backends(&gpu) {
            let mut caster = RayCaster::new(&gpu, &scene, backend).unwrap();
            for occlusion in [false, true] {
                let hits = caster.cast(&rays, occlusion).unwrap().hits;
                let escaped = hits.iter().filter(|h| h.triangle == MISS).count();
                eprintln!(
                    "{backend:?} from {origin} (occlusion {occlusion}): {escaped} of {} rays escaped",
                    rays.len()
                );
                if backend == Backend::RayQuery && lavapipe {
                    // Mesa 25.0's lavapipe misses some rays through shared vertices of a
                    // consistently wound, indexed mesh (≈0.1–0.3% here), which the Vulkan spec's
                    // watertightness rule forbids: a driver defect, bounded here so a worse one
                    // is caught, and reported in the project notes.
                    assert!(escaped * 200 < rays.len(), "{backend:?}: {escaped} of {} rays escaped", rays.len());
                } else {
                    assert_eq!(
                        escaped,
                        0,
                        "{backend:?} occlusion={occlusion}: {escaped} of {} rays escaped",
                        rays.len()
                    );
                }
            }
        }
    }
    gpu.check_validation().unwrap();
}

/// A floor point whose view of the light is blocked gets exactly zero direct light; an
/// unblocked one gets the analytic value.
#[test]
fn shadowed_pixel_gets_exactly_zero_direct_light() {
    let Some(gpu) = common::gpu() else { return };
    let backends = common::backends(&gpu);
    drop(gpu);
    let scene = common::scene("tests/scenes/occluder.gltf");
    let camera = scene.camera_or_framing();
    let size = 64u32;
    // The pixel whose ray hits the floor point `x` (camera straight above the origin).
    let pixel_of = |x: Vec3| {
        let h = camera.position().y;
        let tan_half = (camera.yfov / 2.0).tan();
        let ndc_x = x.x / (h * tan_half);
        let ndc_y = -x.z / (h * tan_half);
        (((ndc_x + 1.0) / 2.0 * size as f32) as u32, ((1.0 - ndc_y) / 2.0 * size as f32) as u32)
    };
    for backend in backends {
        let choice = if backend == Backend::RayQuery { BackendChoice::RayQuery } else { BackendChoice::Compute };
        let settings = RenderSettings { width: size, height: size, backend: choice, ..Default::default() };
        let frame = common::render_with("tests/scenes/occluder.gltf", settings).unwrap();
        let (sx, sy) = pixel_of(Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(
            RenderedFrame::pixel(&frame.direct, size, sx, sy),
            [0.0; 3],
            "{backend:?}: shadow centre ({sx},{sy})"
        );
        // The mirror point (-1, 0, 0) sees the light: L = ρ I cos θ / (π d²), d² = 2, cos θ = 1/√2.
        let (lx, ly) = pixel_of(Vec3::new(-1.0, 0.0, 0.0));
        let lit = RenderedFrame::pixel(&frame.direct, size, lx, ly)[0];
        let expected = 0.8 * 2.0 * (1.0 / 2f32.sqrt()) / (PI * 2.0);
        assert!((lit - expected).abs() / expected < 0.05, "{backend:?}: lit {lit} vs {expected}");
    }
}

/// Inside a closed sphere (radius R, albedo ρ) with a point light of intensity I at the
/// centre, every wall point receives E₀ = I/R² directly, and each bounce multiplies the
/// radiance by ρ (the wall sees only wall of uniform radiance L, so E = πL and ρE/π = ρL).
/// With K indirect bounces: L = ρ I / (π R²) · Σ_{k=0..K} ρ^k = ρ I (1 − ρ^{K+1}) / (π R² (1 − ρ)).
#[test]
fn reference_converges_to_the_sphere_closed_form() {
    let Some(gpu) = common::gpu() else { return };
    let backends = common::backends(&gpu);
    drop(gpu);
    let (r, rho, i, k) = (1.0f64, 0.5f64, 1.0f64, 6u32);
    let expected = rho * i * (1.0 - rho.powi(k as i32 + 1)) / (std::f64::consts::PI * r * r * (1.0 - rho));
    for backend in backends {
        let choice = if backend == Backend::RayQuery { BackendChoice::RayQuery } else { BackendChoice::Compute };
        let settings = RenderSettings {
            width: 32,
            height: 32,
            backend: choice,
            method: Method::Reference,
            spp: 32,
            max_bounces: k,
            seed: 1,
            ..Default::default()
        };
        let frame = common::render_with("scenes/sphere.gltf", settings).unwrap();
        assert!(common::all_finite(&frame.radiance));
        let mean = common::mean(&frame.radiance);
        for c in mean {
            assert!((c - expected).abs() / expected < 0.01, "{backend:?}: mean radiance {c} vs {expected}");
        }
    }
}

#[test]
fn forcing_ray_queries_without_them_is_a_clear_error() {
    use leakless_device::{Capabilities, DeviceType};
    let none = Capabilities { ray_query: false, acceleration_structure: false, validation: false };
    let err = BackendChoice::RayQuery.resolve(none, DeviceType::Discrete, "some device").unwrap_err().to_string();
    assert!(err.contains("rayquery") && err.contains("some device") && err.contains("compute"), "{err}");
    let auto = |caps, ty| BackendChoice::Auto.resolve(caps, ty, "d").unwrap().backend;
    let rq = Capabilities { ray_query: true, acceleration_structure: true, validation: false };
    assert_eq!(auto(none, DeviceType::Discrete), Backend::Compute);
    // What each device is best at: ray queries on GPUs, the compute BVH on CPU devices.
    assert_eq!(auto(rq, DeviceType::Discrete), Backend::RayQuery);
    assert_eq!(auto(rq, DeviceType::Integrated), Backend::RayQuery);
    assert_eq!(auto(rq, DeviceType::Cpu), Backend::Compute);
    assert_eq!(BackendChoice::RayQuery.resolve(rq, DeviceType::Cpu, "d").unwrap().backend, Backend::RayQuery);
}

/// The compute backend's GLSL traversal is the CPU traversal of the same BVH, ray for ray.
#[test]
fn gpu_bvh_traversal_equals_the_cpu_traversal() {
    let Some(gpu) = common::gpu_with(false) else { return };
    for path in ["scenes/cornell-box.gltf", "scenes/sphere.gltf", "tests/scenes/occluder.gltf"] {
        let scene = common::scene(path);
        let bvh = leakless_accel::Bvh::build(&scene.vertices).unwrap();
        let rays = raygen::random_rays(&scene, 20_000, 3);
        let mut caster = RayCaster::new(&gpu, &scene, Backend::Compute).unwrap();
        let hits = caster.cast(&rays, false).unwrap().hits;
        for (i, (r, h)) in rays.iter().zip(&hits).enumerate() {
            let cpu = bvh.intersect(r.origin, r.dir, r.tmin, r.tmax, false);
            match cpu {
                None => assert_eq!(h.triangle, MISS, "{path} ray {i}: GPU hit, CPU missed"),
                Some(c) => {
                    assert_eq!(h.triangle, c.triangle, "{path} ray {i}");
                    assert!((h.t - c.t).abs() <= 1e-6 * c.t.max(1.0), "{path} ray {i}: t {} vs {}", h.t, c.t);
                }
            }
        }
    }
}
