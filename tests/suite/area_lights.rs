//! Emissive triangles as area lights: the closed form of a glowing box, the reference against
//! the photon methods under a ceiling panel, and sealed rooms that a panel never lights through
//! a wall, on both backends.

use crate::common;

use leakless::passes::photons::{PhotonParams, PhotonTracer};
use leakless::{BackendChoice, Method, RenderSettings, RenderedFrame, Scene};

fn render(scene: &Scene, settings: RenderSettings) -> RenderedFrame {
    common::render_scene(scene, settings).expect("checked by common::choices()")
}

fn luminance_mean(layer: &[[f32; 3]]) -> f64 {
    let m = common::mean(layer);
    0.2126 * m[0] + 0.7152 * m[1] + 0.0722 * m[2]
}

/// A closed cube whose every inner face emits Le and reflects ρ: every pixel sees
/// L = Le·Σ_{k=0}^{B+1} ρ^k with B indirect bounces (docs/architecture.md §1): Le emitted,
/// ρ·Le direct (the walls see Le over the whole hemisphere, E = π·Le), then ρ^(b+1)·Le for
/// bounce b. The direct layer, the reference and `leakless` each match their part.
#[test]
fn a_glowing_box_has_its_closed_form_radiance() {
    let scene = common::scene("tests/scenes/glowing-box.gltf");
    let (rho, le) = (common::extra(&scene, "albedo") as f64, common::extra(&scene, "emitted_radiance") as f64);
    let bounces = 4u32;
    let direct = le * (1.0 + rho);
    let indirect: f64 = (2..=bounces + 1).map(|k| le * rho.powi(k as i32)).sum();
    for backend in common::choices() {
        let base =
            RenderSettings { width: 32, height: 32, backend, max_bounces: bounces, seed: 3, ..Default::default() };
        let reference = render(&scene, RenderSettings { method: Method::Reference, spp: 64, frames: 4, ..base });
        let d = luminance_mean(&reference.direct);
        let i = luminance_mean(&reference.indirect);
        eprintln!("{backend:?}: direct {d:.5} (exact {direct:.5}), reference indirect {i:.5} (exact {indirect:.5})");
        assert!((d - direct).abs() / direct < 0.01, "{backend:?}: direct {d} vs {direct}");
        assert!((i - indirect).abs() / indirect < 0.01, "{backend:?}: reference indirect {i} vs {indirect}");
        let photons = RenderSettings {
            method: Method::LeakLess,
            frames: 8,
            splat: leakless::SplatSettings { paths: 20_000, ..Default::default() },
            ..base
        };
        let ours = render(&scene, photons);
        let i = luminance_mean(&ours.indirect);
        eprintln!("{backend:?}: leakless indirect {i:.5} (exact {indirect:.5})");
        assert!((i - indirect).abs() / indirect < 0.03, "{backend:?}: leakless indirect {i} vs {indirect}");
    }
}

/// The sealed rooms lit only by a two-sided panel 1 mm in front of the partition in room A:
/// from room B, every method's image is exactly black (no shadow ray, photon or path gets
/// through the partition), while the same panel lights room A.
#[test]
fn a_panel_against_a_sealed_wall_never_lights_the_other_room() {
    let scene = common::scene("scenes/stress/sealed-panel.gltf");
    assert!(scene.lights.is_empty(), "lit by its panel alone");
    for backend in common::choices() {
        for method in [Method::Direct, Method::Reference, Method::LeakLess, Method::LeakLessCapped] {
            let mut settings = common::photon_settings(method, backend, 20_000, 0.3);
            settings.spp = 16;
            let frame = render(&scene, settings);
            let lit = frame.radiance.iter().filter(|p| **p != [0.0; 3]).count();
            assert_eq!(lit, 0, "{backend:?} {method:?}: {lit} pixels of room B are lit");
        }
        // The panel does light its own room (seen from room A).
        let mut from_a = scene.clone();
        let clip = scene.camera_or_framing();
        let (eye, target) = (glam::Vec3::new(-2.8, 1.4, 1.2), glam::Vec3::new(0.0, 1.2, 0.0));
        from_a.camera = leakless_scene::Camera::look_at(eye, target, glam::Vec3::Y, clip.yfov, &clip);
        let lit = render(&from_a, common::photon_settings(Method::LeakLess, backend, 20_000, 0.3));
        assert!(luminance_mean(&lit.direct) > 0.0 && luminance_mean(&lit.indirect) > 0.0, "{backend:?}: room A dark");
    }
}

/// Under the Cornell box's ceiling panel, `leakless` after 32 frames is within 3% of the
/// reference's mean (the same bounces), and a single frame has no NaN.
#[test]
fn leakless_under_a_ceiling_panel_converges_to_the_reference() {
    let scene = common::scene("scenes/cornell-panel.gltf");
    let backend = *common::choices().first().unwrap_or(&BackendChoice::Auto);
    if common::choices().is_empty() {
        return;
    }
    let base = RenderSettings { width: 48, height: 48, backend, max_bounces: 4, seed: 5, ..Default::default() };
    let reference = render(&scene, RenderSettings { method: Method::Reference, spp: 64, frames: 8, ..base });
    let ours = render(
        &scene,
        RenderSettings {
            method: Method::LeakLess,
            frames: 32,
            splat: leakless::SplatSettings { paths: 20_000, ..Default::default() },
            ..base
        },
    );
    assert!(common::all_finite(&ours.radiance) && common::all_finite(&reference.radiance));
    let (r, o) = (luminance_mean(&reference.radiance), luminance_mean(&ours.radiance));
    let (ri, oi) = (luminance_mean(&reference.indirect), luminance_mean(&ours.indirect));
    eprintln!("{backend:?}: mean radiance reference {r:.5}, leakless {o:.5}; indirect {ri:.5} vs {oi:.5}");
    assert!((o - r).abs() / r < 0.03, "leakless {o} vs reference {r}");
}

/// Photons leave emissive triangles with their power: in the closed glowing box every path's
/// first hit is stored (`store_direct`), and their flux sums to π·A·Le over its 6 m² of walls,
/// spread over the walls as a cosine emitter's is (each wall gets its share, none more).
#[test]
fn emissive_triangles_emit_their_power_as_photons() {
    let Some(gpu) = common::gpu() else { return };
    let scene = common::scene("tests/scenes/glowing-box.gltf");
    let le = common::extra(&scene, "emitted_radiance") as f64;
    let power = std::f64::consts::PI * 6.0 * le;
    let n = 1u32 << 15;
    for backend in common::backends(&gpu) {
        let mut tracer = PhotonTracer::new(&gpu, &scene, backend, n).unwrap();
        let table = tracer.light_table();
        assert_eq!((table.punctual, table.powers.len()), (0, 12), "twelve emitting triangles");
        let total: f64 = table.total_power().iter().sum::<f64>() / 3.0;
        assert!((total - power).abs() / power < 1e-6, "table power {total} vs {power}");
        let params = PhotonParams { paths: n, max_bounces: 0, seed: 4, store_direct: true, ..Default::default() };
        let t = tracer.trace(&params).unwrap();
        assert_eq!(t.photons.len(), n as usize, "a closed box: every path hits a wall");
        let flux: f64 = t.photons.iter().map(|p| p.flux[1] as f64).sum();
        eprintln!("{backend:?}: photon flux {flux:.6} vs power {power:.6}");
        assert!((flux - power).abs() / power < 1e-4, "{flux} vs {power}");
        // The floor (y = 0) receives a sixth of the emitted light by symmetry.
        let floor: f64 = t.photons.iter().filter(|p| p.position[1] < 1e-3).map(|p| p.flux[1] as f64).sum();
        assert!((floor / flux - 1.0 / 6.0).abs() < 0.01, "floor share {}", floor / flux);
    }
}
