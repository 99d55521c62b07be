//! The radius that follows the photon count (docs/architecture.md §1.15): where `--radius` is not
//! given, a kernel holds about K photons on every shipped scene at 10k and 80k paths, the
//! radius shrinks as √(1/paths), a given radius is the radius, and a sealed room lit next door
//! stays exactly black at the count's radius with a frame budget, on both backends.

use crate::common;

use leakless::splatting::{auto_radius, DEFAULT_KERNEL_PHOTONS};
use leakless::{BackendChoice, Method, RenderSettings, Renderer, SplatSettings};
use leakless_scene::Camera;

fn settings(paths: u32, radius: Option<f32>) -> RenderSettings {
    RenderSettings {
        width: 64,
        height: 48,
        backend: BackendChoice::Auto,
        method: Method::LeakLess,
        max_bounces: 4,
        seed: 5,
        splat: SplatSettings { paths, radius, ..Default::default() },
        ..Default::default()
    }
}

/// Every shipped scene at 10k and 80k paths: the gather's photons a kernel within ±20% of K
/// (the frame's own photons, measured by the probe before it), and 8× the paths shrink the
/// radius by √8 (±20%).
#[test]
fn a_kernel_holds_about_k_photons_on_every_shipped_scene() {
    let Some(gpu) = common::gpu() else { return };
    drop(gpu);
    let mut scenes: Vec<_> = std::fs::read_dir(common::root().join("scenes"))
        .expect("scenes/")
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "gltf"))
        .collect();
    scenes.sort();
    let k = DEFAULT_KERNEL_PHOTONS as f64;
    let mut seen = 0;
    for path in &scenes {
        let scene = leakless::Scene::load(path).expect("a shipped scene");
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        let mut radii = Vec::new();
        for paths in [10_000, 80_000] {
            let frame = common::render_scene(&scene, settings(paths, None)).expect("a device");
            let s = frame.splat.expect("leakless splats");
            if frame.indirect.iter().all(|p| *p == [0.0; 3]) {
                // Room B of the sealed two rooms: the only photons its kernels hold are room
                // A's behind the partition, all culled, and so unevenly spread across it.
                continue;
            }
            assert!(
                (0.8 * k..=1.2 * k).contains(&s.photons_per_kernel),
                "{name} at {paths} paths: {:.1} photons a kernel, K = {k} (radius {})",
                s.photons_per_kernel,
                s.radius
            );
            eprintln!("{name} at {paths} paths: radius {:.4}, {:.1} photons a kernel", s.radius, s.photons_per_kernel);
            radii.push(s.radius);
        }
        if let [r10, r80] = radii[..] {
            let shrink = (r10 / r80) as f64 / 8f64.sqrt();
            assert!((0.8..=1.2).contains(&shrink), "{name}: 8× the paths shrank the radius {r10} → {r80}");
            seen += 1;
        }
    }
    assert!(seen >= scenes.len() - 2, "only {seen} of {} scenes show photons", scenes.len());
}

/// `--radius` is the radius whatever the photon count; without it, the same render twice is
/// the same image (the probe is the frame's own photons, deterministic).
#[test]
fn a_given_radius_is_the_radius_and_the_counted_one_is_repeatable() {
    let scene = common::scene("scenes/cornell-box.gltf");
    for paths in [2_000, 40_000] {
        let frame = common::render_scene(&scene, settings(paths, Some(0.07))).expect("a device");
        assert_eq!(frame.splat.as_ref().map(|s| s.radius), Some(0.07), "{paths} paths");
    }
    let a = common::render_scene(&scene, settings(10_000, None)).expect("a device");
    let b = common::render_scene(&scene, settings(10_000, None)).expect("a device");
    assert_eq!(a.splat.as_ref().map(|s| s.radius), b.splat.as_ref().map(|s| s.radius));
    assert!(a.radiance == b.radiance, "two renders of one setting differ");
}

/// The camera looks into the lit room A of the sealed two rooms (the first frame's probe
/// measures the density there), then walks into room B: with a frame budget of 1 ms, every
/// frame in room B is exactly black, on both backends. The first gathers at room A's count's
/// radius; its visibility rays cull every photon its kernels took (room A's, behind the
/// partition), so the frames after it gather at the fixed radius, not at one that K of those
/// culled photons would ask for (4× the fixed one).
#[test]
fn a_sealed_room_lit_next_door_stays_black_at_the_counted_radius() {
    let scene = common::scene("scenes/two-rooms.gltf");
    let fixed = auto_radius(&scene);
    for backend in common::choices() {
        let gpu = common::gpu_with(backend.wants_ray_queries()).expect("checked by common::choices()");
        let s = RenderSettings { backend, reuse: true, ..settings(20_000, None) };
        let mut r = Renderer::new(gpu, &scene, s).expect("renderer");
        r.set_progressive(true);
        r.set_advance_seed(true);
        r.set_frame_budget(Some(1.0)).expect("a budget");
        let room_b = r.camera().clone();
        let look = |eye: glam::Vec3, at: glam::Vec3| Camera::look_at(eye, at, room_b.up(), room_b.yfov, &room_b);
        let room_a = look(glam::Vec3::new(-0.3, 1.5, 1.2), glam::Vec3::new(-2.8, 0.8, -1.2)).expect("a view");
        r.set_camera(room_a);
        let lit = r.capture_frame().expect("a frame of room A");
        let counted = lit.splat.as_ref().expect("photons").radius;
        assert!(lit.radiance.iter().any(|p| p[0] > 0.0), "{backend:?}: room A is lit");
        assert!(counted != fixed, "{backend:?}: room A's radius is the count's, not the fixed {fixed}");
        for k in 0..5 {
            let eye = room_b.position() - 0.05 * k as f32 * room_b.forward();
            r.set_camera(look(eye, eye + room_b.forward()).expect("a view"));
            let frame = r.capture_frame().expect("a frame of room B");
            let lit_pixels = frame.radiance.iter().filter(|p| p.iter().any(|&c| c != 0.0)).count();
            assert_eq!(lit_pixels, 0, "{backend:?}: frame {k} in room B has light");
            let s = frame.splat.as_ref().expect("photons");
            assert!(s.accepted > 0 && s.leaks_culled == s.accepted, "{backend:?}: frame {k} keeps no photon");
            match k {
                0 => assert!(s.radius != fixed, "{backend:?}: the first frame in room B has room A's radius"),
                _ => assert_eq!(s.radius, fixed, "{backend:?}: frame {k} in room B"),
            }
        }
        r.gpu().check_validation().expect("validation clean");
    }
}
