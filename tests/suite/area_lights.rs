//! Emissive triangles as area lights: the closed form of a glowing box, the reference against
//! the photon methods under a ceiling panel, and sealed rooms that a panel never lights through
//! a wall, on both backends.

use crate::common;

use leakless::passes::photons::PhotonParams;
use leakless::{BackendChoice, Method, RenderSettings, RenderedFrame, Scene};
use leakless_measure::photon_tracer::PhotonTracer;

use common::render_chosen as render;

fn luminance_mean(layer: &[[f32; 3]]) -> f64 {
    leakless_measure::metrics::rgb_luminance(common::mean(layer))
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
        // Pixel by pixel: every pixel's exact radiance is the same, Le·Σρ^k.
        let exact = direct + indirect;
        let rel_mse = reference.radiance.iter().map(|p| (p[1] as f64 - exact).powi(2)).sum::<f64>()
            / (reference.radiance.len() as f64 * exact * exact);
        eprintln!("{backend:?}: reference relMSE against the closed form {rel_mse:.2e}");
        assert!(rel_mse < 0.05, "{backend:?}: relMSE {rel_mse}");
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
/// reference's mean (the same bounces), its indirect light within 2%, and no pixel is NaN.
#[test]
fn leakless_under_a_ceiling_panel_converges_to_the_reference() {
    let scene = common::scene("scenes/cornell-panel.gltf");
    let backend = *common::choices().first().unwrap_or(&BackendChoice::Auto);
    if common::choices().is_empty() {
        return;
    }
    let base = RenderSettings { width: 48, height: 48, backend, max_bounces: 4, seed: 5, ..Default::default() };
    // The reference at the same 32 pixel jitters: the panel, which a pixel of outshines a
    // hundred of the room, is covered alike (at other jitters its one-pixel-high edge moves the
    // image's mean by several percent).
    let reference = RenderSettings { method: Method::Reference, spp: 8, frames: 32, max_batches: 1, ..base };
    let reference = render(&scene, reference);
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
    // The indirect light alone.
    assert!((oi - ri).abs() / ri < 0.02, "leakless indirect {oi} vs reference {ri}");
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

/// Single-frame noise of the panel's direct light: the per-pixel standard deviation over seeds,
/// over the mean, for the direct pass's default (2 shadow rays resampled from 8 candidates),
/// the same rays without resampling, and one plain sample (what a path tracer's next-event
/// estimation gives at 1 sample per pixel), over the pixels whose direct light varies.
/// Resampling must lower the noise at equal rays, and keep it with the panel split into 512.
#[test]
fn resampled_emitter_samples_are_less_noisy_than_plain_ones() {
    let scene = common::scene("scenes/cornell-panel.gltf");
    let Some(&backend) = common::choices().first() else { return };
    let split = subdivide_emitters(&scene, 4);
    let noise_in = |scene: &Scene, light_samples: u32, light_candidates: u32| -> f64 {
        let frames: Vec<RenderedFrame> = (0..8)
            .map(|seed| {
                let settings = RenderSettings {
                    width: 48,
                    height: 48,
                    backend,
                    method: Method::Direct,
                    seed,
                    light_samples,
                    light_candidates,
                    ..Default::default()
                };
                render(scene, settings)
            })
            .collect();
        let lum = |p: [f32; 3]| leakless_measure::metrics::luminance(&p);
        let (mut std_sum, mut mean_sum) = (0.0, 0.0);
        for i in 0..frames[0].direct.len() {
            let v: Vec<f64> = frames.iter().map(|f| lum(f.direct[i])).collect();
            let m = v.iter().sum::<f64>() / v.len() as f64;
            let std = (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (v.len() - 1) as f64).sqrt();
            // The panel itself shows its emission, the same in every frame: not light it receives.
            if std > 0.0 {
                std_sum += std;
                mean_sum += m;
            }
        }
        std_sum / mean_sum
    };
    let noise = |samples, candidates| noise_in(&scene, samples, candidates);
    let (ours, unresampled, plain) = (noise(2, 8), noise(2, 1), noise(1, 1));
    // The same panel as 512 triangles: picking by power then spreads candidates over all of
    // them, and resampling keeps the noise where it was.
    let ours_split = noise_in(&split, 2, 8);
    eprintln!("{backend:?}: the panel as 512 triangles: 2 rays x 8 candidates {ours_split:.4}");
    assert!(ours_split < 1.2 * ours, "{ours_split} with 512 emitters, {ours} with 2");
    eprintln!(
        "{backend:?}: direct-light noise (std over seeds / mean): 2 rays x 8 candidates {ours:.4}, \
         2 rays x 1 candidate {unresampled:.4}, 1 ray x 1 candidate {plain:.4}"
    );
    assert!(ours < unresampled && unresampled < plain, "{ours} {unresampled} {plain}");
}

/// Emission is `emissiveFactor` × the sRGB emissive texture, seen from the front face: the
/// textured quad (lit head-on so that radiance = albedo) made to emit 2 × its own texture shows
/// 3 × each texel, and nothing where its alpha mask cuts it away.
#[test]
fn emission_is_factor_times_texture() {
    let mut scene = common::scene("tests/scenes/textured-quad.gltf");
    let m = scene.triangle_material[0] as usize;
    scene.materials[m].emission = glam::Vec3::splat(2.0);
    scene.materials[m].emission_texture = scene.materials[m].texture;
    for backend in common::choices() {
        let settings = RenderSettings { width: 66, height: 66, backend, method: Method::Direct, ..Default::default() };
        let frame = render(&scene, settings);
        let at = |x, y| RenderedFrame::pixel(&frame.direct, 66, x, y);
        let close = |got: [f32; 3], want: [f32; 3]| got.iter().zip(want).all(|(g, w)| (g - w).abs() < 6e-3);
        assert!(close(at(16, 16), [3.0, 0.0, 0.0]), "{backend:?}: top-left red: {:?}", at(16, 16));
        assert!(close(at(49, 16), [0.0, 3.0, 0.0]), "{backend:?}: top-right green: {:?}", at(49, 16));
        assert!(close(at(16, 49), [0.0, 0.0, 3.0]), "{backend:?}: bottom-left blue: {:?}", at(16, 49));
        assert_eq!(at(49, 49), [0.0; 3], "{backend:?}: cut away by the alpha mask");
    }
}

/// Every emissive triangle of `scene` split into 4^levels by midpoints: the same light, as an
/// exporter that subdivides a lamp writes it.
fn subdivide_emitters(scene: &Scene, levels: u32) -> Scene {
    assert!(scene.instances.is_empty(), "triangles are appended after the static ones");
    let mut out = scene.clone();
    let (mut vertices, mut materials) = (Vec::new(), Vec::new());
    for (t, &m) in scene.triangle_material.iter().enumerate() {
        let tri = [scene.vertices[3 * t], scene.vertices[3 * t + 1], scene.vertices[3 * t + 2]];
        if !scene.materials[m as usize].emits() {
            vertices.extend(tri);
            materials.push(m);
            continue;
        }
        let mut tris = vec![tri];
        for _ in 0..levels {
            let mid = |a: leakless_scene::Vertex, b: leakless_scene::Vertex| leakless_scene::Vertex {
                position: std::array::from_fn(|i| 0.5 * (a.position[i] + b.position[i])),
                normal: a.normal,
                uv: std::array::from_fn(|i| 0.5 * (a.uv[i] + b.uv[i])),
            };
            tris = tris
                .into_iter()
                .flat_map(|[a, b, c]| {
                    let (ab, bc, ca) = (mid(a, b), mid(b, c), mid(c, a));
                    [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]
                })
                .collect();
        }
        materials.extend(std::iter::repeat_n(m, tris.len()));
        vertices.extend(tris.into_iter().flatten());
    }
    out.vertices = vertices;
    out.triangle_material = materials;
    out
}

/// The Cornell box's panel as 512 emitting triangles instead of 2: the same light, so the same
/// image (direct light and photons alike), and resampling keeps the direct light's noise
/// where it was with 2.
#[test]
fn a_subdivided_panel_lights_the_box_as_the_whole_one_does() {
    let whole = common::scene("scenes/cornell-panel.gltf");
    let split = subdivide_emitters(&whole, 4);
    assert_eq!(split.triangle_count(), whole.triangle_count() + 510);
    let Some(&backend) = common::choices().first() else { return };
    let settings = RenderSettings {
        width: 48,
        height: 48,
        backend,
        max_bounces: 4,
        frames: 8,
        seed: 2,
        splat: leakless::SplatSettings { paths: 20_000, ..Default::default() },
        ..Default::default()
    };
    let (a, b) = (render(&whole, settings.clone()), render(&split, settings));
    for (name, x, y) in [("direct", &a.direct, &b.direct), ("indirect", &a.indirect, &b.indirect)] {
        let (x, y) = (luminance_mean(x), luminance_mean(y));
        eprintln!("{backend:?}: {name}: 2 emitters {x:.5}, 512 emitters {y:.5}");
        assert!((x - y).abs() / x < 0.01, "{name}: {x} vs {y}");
    }
}

/// A reference of one image (`--frames 1`: its samples added over several submissions) has a
/// direct layer estimated once, for all its samples, in the frame that is read: in the glowing
/// box, 64 samples get 16 shadow rays a pixel against a single frame's 2, and the layer's
/// per-pixel error against Le·(1 + ρ) falls (by 2.6×, not 8×: area sampling of the walls next
/// to a concave edge has a heavy tail, 1/r² of a point that nears the edge).
#[test]
fn a_single_image_reference_estimates_direct_light_for_all_its_samples() {
    let scene = common::scene("tests/scenes/glowing-box.gltf");
    let Some(&backend) = common::choices().first() else { return };
    let exact = 1.5f64;
    let error = |layer: &[[f32; 3]]| {
        layer.iter().map(|p| (p[1] as f64 - exact).powi(2)).sum::<f64>() / (layer.len() as f64 * exact * exact)
    };
    let base = RenderSettings { width: 32, height: 32, backend, max_bounces: 1, seed: 6, ..Default::default() };
    let single = render(&scene, RenderSettings { method: Method::Direct, ..base.clone() });
    let reference = render(&scene, RenderSettings { method: Method::Reference, spp: 64, ..base });
    let (e1, e64) = (error(&single.direct), error(&reference.direct));
    eprintln!("{backend:?}: direct layer relMSE: one frame {e1:.2e}, a 64-sample reference {e64:.2e}");
    assert!(e64 < 0.5 * e1, "{e64} vs {e1}");
}
