//! The scenes where splatting leaks (scenes/two-rooms, doorway): leakless removes the leak,
//! at every scale, on both backends.

use crate::common;

use leakless::{BackendChoice, Method, RenderSettings, RenderedFrame, Scene};
use leakless_measure::metrics;
use leakless_scene::LightKind;

use common::render_chosen as render;

fn photons(method: Method, backend: BackendChoice, paths: u32, radius: f32) -> RenderSettings {
    common::photon_settings(method, backend, paths, radius)
}

/// The scene scaled by `s` about the origin, with point intensities scaled by s² so that
/// irradiance, and so the image, stays the same.
fn scaled(scene: &Scene, s: f32) -> Scene {
    let mut out = scene.clone();
    for v in &mut out.vertices {
        v.position = v.position.map(|c| c * s);
    }
    for l in &mut out.lights {
        l.position *= s;
        if l.kind != LightKind::Directional {
            l.intensity *= s * s;
        }
    }
    let mut camera = scene.camera_or_framing();
    camera.world_from_camera.w_axis = (camera.world_from_camera.w_axis.truncate() * s).extend(1.0);
    camera.znear *= s;
    camera.zfar = camera.zfar.map(|z| z * s);
    out.camera = Some(camera);
    out
}

/// Light in room A, camera in room B, a 2 cm partition between: splat leaks light into B
/// near the partition; leakless leaves every pixel of B at exactly zero indirect light.
#[test]
fn sealed_rooms_leak_with_splat_and_not_with_leakless() {
    let scene = common::scene("scenes/two-rooms.gltf");
    for backend in common::choices() {
        let splat = render(&scene, photons(Method::Splat, backend, 20_000, 0.3));
        let leaky = splat.indirect.iter().filter(|p| p.iter().any(|&c| c > 0.0)).count();
        assert!(leaky > 100, "{backend:?}: splat should leak into room B, {leaky} lit pixels");
        let ours = render(&scene, photons(Method::LeakLess, backend, 20_000, 0.3));
        let lit: Vec<usize> = (0..ours.indirect.len()).filter(|&i| ours.indirect[i] != [0.0; 3]).collect();
        assert!(
            lit.is_empty(),
            "{backend:?}: {} pixels of room B got indirect light, first {:?}",
            lit.len(),
            &lit[..lit.len().min(8)]
        );
        assert!(ours.radiance.iter().all(|p| *p == [0.0; 3]), "{backend:?}: room B is not black");
        let s = ours.splat.unwrap();
        assert!(s.leaks_culled > 0 && s.leaked_energy_fraction == 1.0, "{backend:?}: {s:?}");
        eprintln!(
            "{backend:?}: splat lit {leaky} pixels of room B; leakless culled {} leaks, none left",
            s.leaks_culled
        );
    }
}

/// Leakless decides the same at any scale: the offsets and the segment's end are relative.
#[test]
fn sealed_rooms_stay_sealed_and_the_doorway_renders_the_same_at_any_scale() {
    let Some(&backend) = common::choices().first() else { return };
    let sealed = common::scene("scenes/two-rooms.gltf");
    let door = common::scene("scenes/doorway.gltf");
    let base = render(&door, photons(Method::LeakLess, backend, 10_000, 0.3));
    for s in [0.001f32, 1000.0] {
        let frame = render(&scaled(&sealed, s), photons(Method::LeakLess, backend, 20_000, 0.3 * s));
        assert!(frame.indirect.iter().all(|p| *p == [0.0; 3]), "scale {s}: room B got indirect light");
        let frame = render(&scaled(&door, s), photons(Method::LeakLess, backend, 10_000, 0.3 * s));
        let diff = common::relative_rms(&frame.radiance, &base.radiance);
        eprintln!("doorway ×{s}: relative RMS {diff:.2e} against ×1");
        assert!(diff < 1e-3, "scale {s}: relative RMS {diff}");
    }
}

/// Light reaches room B only through the doorway: against the reference, leakless's error
/// over room B (the whole image) is at most half of splat's (relMSE).
#[test]
fn doorway_leakless_is_closer_to_the_reference_than_splat() {
    let scene = common::scene("scenes/doorway.gltf");
    let Some(&backend) = common::choices().first() else { return };
    let reference = common::recorded::reference(
        "doorway",
        RenderSettings {
            width: 64,
            height: 48,
            backend,
            method: Method::Reference,
            spp: 2048,
            max_bounces: 4,
            seed: 1,
            ..Default::default()
        },
        |s| Some(render(&scene, s)),
    )
    .expect("a device, checked by common::choices()");
    // relMSE over room B, which is the whole view, as `leakless chart` measures it.
    let eps = metrics::epsilon(&reference.radiance);
    let relmse =
        |frame: &RenderedFrame| metrics::rel_mse(&frame.radiance, &reference.radiance, None, eps).expect("pixels");
    let splat = relmse(&render(&scene, photons(Method::Splat, backend, 40_000, 0.2)));
    let ours = relmse(&render(&scene, photons(Method::LeakLess, backend, 40_000, 0.2)));
    eprintln!("doorway relMSE over room B: splat {splat:.4}, leakless {ours:.4} (paths 40k, radius 0.2, 4 bounces)");
    assert!(ours <= 0.5 * splat, "leakless {ours} vs splat {splat}");
}
