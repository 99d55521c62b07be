//! The game-scale basilica (scenes/basilica.glb, about 210k triangles of curved and narrow
//! geometry): it renders on both backends, and its sealed variant, where a 12 cm sunlit
//! gallery floor is all that stands between the sun and the camera's aisle, is exactly black.

use crate::common;

use leakless::{BackendChoice, Method, RenderSettings, RenderedFrame, Scene, SplatSettings};

fn settings(method: Method, backend: BackendChoice) -> RenderSettings {
    RenderSettings {
        width: 64,
        height: 36,
        backend,
        method,
        max_bounces: 4,
        seed: 1,
        splat: SplatSettings { paths: 10_000, ..Default::default() },
        ..Default::default()
    }
}

fn render(scene: &Scene, settings: RenderSettings) -> RenderedFrame {
    common::render_scene(scene, settings).expect("checked by common::choices()")
}

fn lit(layer: &[[f32; 3]]) -> usize {
    layer.iter().filter(|p| **p != [0.0; 3]).count()
}

#[test]
fn the_basilica_renders_on_both_backends() {
    let scene = common::scene("scenes/basilica.glb");
    assert!(scene.triangle_count() >= 200_000, "{} triangles", scene.triangle_count());
    let mut means = Vec::new();
    for backend in common::choices() {
        let frame = render(&scene, settings(Method::LeakLess, backend));
        for (name, layer) in [("radiance", &frame.radiance), ("direct", &frame.direct), ("indirect", &frame.indirect)] {
            assert!(common::all_finite(layer), "{backend:?}: {name} has a NaN or an infinity");
        }
        let pixels = frame.indirect.len();
        assert!(lit(&frame.direct) > pixels / 4, "{backend:?}: {} of {pixels} pixels lit directly", lit(&frame.direct));
        assert!(
            lit(&frame.indirect) > pixels / 2,
            "{backend:?}: {} of {pixels} pixels lit indirectly",
            lit(&frame.indirect)
        );
        let mean = common::mean(&frame.indirect)[1];
        eprintln!("{backend:?}: {} triangles, mean indirect {mean:.4e}", scene.triangle_count());
        means.push(mean);
    }
    if let [a, b] = means[..] {
        assert!((a - b).abs() <= 0.01 * a, "the backends' mean indirect light differs: {a:.5e} and {b:.5e}");
    }
}

/// The east aisle walled off along its arcade, unlit, the camera in it: the sun reaches the
/// 12 cm gallery floor above it, so splat lights the aisle's ceiling; leakless leaves every
/// pixel at exactly zero.
#[test]
fn the_sealed_aisle_is_exactly_black() {
    let scene = common::scene("scenes/basilica-sealed.glb");
    for backend in common::choices() {
        let splat = render(&scene, settings(Method::Splat, backend));
        let leaky = lit(&splat.indirect);
        assert!(leaky > 0, "{backend:?}: splat should leak into the sealed aisle");
        let ours = render(&scene, settings(Method::LeakLess, backend));
        assert_eq!(lit(&ours.radiance), 0, "{backend:?}: pixels of the sealed aisle are lit");
        eprintln!("{backend:?}: splat lit {leaky} of {} pixels; leakless none", splat.indirect.len());
    }
}
