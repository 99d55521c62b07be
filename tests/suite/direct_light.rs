//! The first frame: G-buffer + direct light, checked against closed-form answers.

use crate::common;

use std::f32::consts::PI;

use leakless::RenderedFrame;

/// A point light of intensity I at height d above a Lambertian floor of albedo ρ: straight
/// below the light, E = I / d² and L = ρ I / (π d²).
#[test]
fn floor_radiance_under_a_point_light_is_rho_i_over_pi_d2() {
    // Odd size: the centre pixel's ray goes exactly through the point below the light.
    let Some(frame) = common::render("tests/scenes/floor-light.gltf", 65, 65) else {
        return;
    };
    let (rho, intensity, d) = (0.8f32, 2.0f32, 1.0f32);
    let expected = rho * intensity / (PI * d * d);
    let centre = RenderedFrame::pixel(&frame.direct, 65, 32, 32);
    for c in centre {
        assert!((c - expected).abs() / expected < 0.01, "centre radiance {c}, expected {expected}");
    }
    // Further out, the cosine and distance fall off: radiance decreases away from the centre.
    let edge = RenderedFrame::pixel(&frame.direct, 65, 0, 32);
    assert!(edge[0] < centre[0] && edge[0] > 0.0, "edge {edge:?} vs centre {centre:?}");
}

#[test]
fn floor_radiance_follows_the_inverse_square_law_off_axis() {
    let Some(frame) = common::render("tests/scenes/floor-light.gltf", 65, 65) else {
        return;
    };
    // The camera looks straight down from height 2 with the file's yfov; pixel (x, 32) sees
    // the floor point at horizontal distance r, where L = ρ I cos θ / (π (d² + r²)), cos θ = d/√(d²+r²).
    let scene = common::scene("tests/scenes/floor-light.gltf");
    let camera = scene.camera_or_framing();
    let height = camera.position().y;
    let tan_half = (camera.yfov / 2.0).tan();
    for x in [40u32, 48, 56] {
        let ndc = ((x as f32 + 0.5) / 65.0) * 2.0 - 1.0;
        let r = ndc * tan_half * height; // square image: aspect 1
        let (rho, i, d) = (0.8f32, 2.0f32, 1.0f32);
        let dist2 = d * d + r * r;
        let expected = rho * i * (d / dist2.sqrt()) / (PI * dist2);
        let got = RenderedFrame::pixel(&frame.direct, 65, x, 32)[0];
        assert!((got - expected).abs() / expected < 0.01, "x={x}: r={r}, got {got}, expected {expected}");
    }
}

#[test]
fn authored_scenes_render_finite_and_lit() {
    for scene in ["scenes/cornell-box.gltf", "scenes/sphere.gltf", "tests/scenes/textured-quad.gltf"] {
        let Some(frame) = common::render(scene, 64, 48) else {
            return;
        };
        assert!(common::all_finite(&frame.radiance), "{scene}: NaN or Inf in the image");
        let lit = frame.radiance.iter().filter(|p| p[0] + p[1] + p[2] > 0.0).count();
        assert!(lit > frame.radiance.len() / 10, "{scene}: only {lit} lit pixels");
        assert!(frame.timings.iter().any(|t| t.name == "gbuffer") && frame.timings.iter().any(|t| t.name == "direct"));
    }
}

/// Inside a closed sphere with the light at its centre, every wall point is at distance R
/// and faces the light: L = ρ I / (π R²) everywhere (direct light only).
#[test]
fn sphere_interior_direct_radiance_is_uniform_and_analytic() {
    let Some(frame) = common::render("scenes/sphere.gltf", 48, 48) else {
        return;
    };
    let expected = 0.5 * 1.0 / (PI * 1.0);
    for p in &frame.direct {
        // Tessellation puts flat facets slightly inside the sphere (closer, more oblique);
        // a ≥2000-triangle sphere stays within 2%.
        assert!((p[0] - expected).abs() / expected < 0.02, "radiance {} vs {expected}", p[0]);
    }
}

/// Albedo comes from baseColorFactor × an sRGB texture, and alphaMode MASK cuts surfaces away:
/// a quad filling the view, lit head-on by irradiance π, shows radiance = albedo per texel.
#[test]
fn texture_albedo_and_alpha_mask_reach_the_image() {
    // 66 pixels: the centre of each image quadrant (pixel 16 or 49) samples a texel centre.
    let Some(frame) = common::render("tests/scenes/textured-quad.gltf", 66, 66) else {
        return;
    };
    let at = |x, y| RenderedFrame::pixel(&frame.direct, 66, x, y);
    let close = |got: [f32; 3], want: [f32; 3]| got.iter().zip(want).all(|(g, w)| (g - w).abs() < 2e-3);
    assert!(close(at(16, 16), [1.0, 0.0, 0.0]), "top-left red: {:?}", at(16, 16));
    assert!(close(at(49, 16), [0.0, 1.0, 0.0]), "top-right green: {:?}", at(49, 16));
    assert!(close(at(16, 49), [0.0, 0.0, 1.0]), "bottom-left blue: {:?}", at(16, 49));
    assert_eq!(at(49, 49), [0.0; 3], "bottom-right texel has alpha 0 < cutoff: no surface");
}
