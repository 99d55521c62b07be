//! Emissive triangles as area lights (docs/architecture.md §1): which triangles emit, how much
//! power each emits, and the CDF by which next-event estimation picks them (`emitters.glsl`).
//!
//! A triangle of area A whose material emits radiance Le (W/m²/sr) uniformly and
//! Lambertian-ly from s faces (1, or 2 when `doubleSided`) emits power Φ = π·A·s·Le. Textured
//! emission varies over the triangle; the power here uses the texture's mean over 36 points
//! of the triangle. These powers only weigh the choice of emitter: every estimate divides by
//! the probability it was chosen with and evaluates the emission (and the area, for moving
//! instances) where it samples, so rough weights cost noise, never bias.

use glam::{Vec2, Vec3};
use leakless_scene::{Scene, Texture};

use crate::gpu_types::Emitter;
use crate::photon_lights::{luminance, selection_cdf};

/// The scene's emissive triangles, in triangle order.
#[derive(Clone, Debug, Default)]
pub struct EmitterTable {
    /// What the GPU gets: triangle index and the NEE CDF (∝ luminance of the power).
    pub emitters: Vec<Emitter>,
    /// Each emitter's power (W, RGB), at the scene's pose at t = 0.
    pub powers: Vec<[f64; 3]>,
}

impl EmitterTable {
    pub fn from_scene(scene: &Scene) -> EmitterTable {
        let mut triangles = Vec::new();
        let mut powers = Vec::new();
        for (t, &m) in scene.triangle_material.iter().enumerate() {
            let material = &scene.materials[m as usize];
            if !material.emits() {
                continue;
            }
            let v = &scene.vertices[3 * t..3 * t + 3];
            let p = |i: usize| Vec3::from(v[i].position);
            let area = 0.5 * (p(1) - p(0)).cross(p(2) - p(0)).length() as f64;
            let uv = |i: usize| Vec2::from(v[i].uv);
            let mean = match material.emission_texture {
                Some(i) => material.emission * texture_mean(&scene.textures[i as usize], [uv(0), uv(1), uv(2)]),
                None => material.emission,
            };
            let sides = if material.double_sided { 2.0 } else { 1.0 };
            let power = mean.to_array().map(|c| std::f64::consts::PI * area * sides * c as f64);
            if luminance(power) > 0.0 {
                triangles.push(t as u32);
                powers.push(power);
            }
        }
        let weights: Vec<f64> = powers.iter().map(|p| luminance(*p)).collect();
        let (cdf, probabilities) = selection_cdf(&weights);
        let emitters = triangles
            .iter()
            .zip(cdf.iter().zip(&probabilities))
            .map(|(&triangle, (&cdf, &p))| Emitter { triangle, cdf, probability: p as f32, pad0: 0 })
            .collect();
        EmitterTable { emitters, powers }
    }

    pub fn len(&self) -> usize {
        self.emitters.len()
    }

    pub fn is_empty(&self) -> bool {
        self.emitters.is_empty()
    }
}

/// The texture's linear-RGB mean over 36 stratified points of the triangle with texcoords
/// `uv` (nearest texel, repeat wrapping, sRGB decoded as the shaders do).
fn texture_mean(t: &Texture, uv: [Vec2; 3]) -> Vec3 {
    const N: usize = 8;
    let mut sum = Vec3::ZERO;
    let mut count = 0.0;
    for i in 0..N {
        for j in 0..N - i {
            // Points of a regular grid of the triangle's barycentric simplex.
            let (a, b) = ((i as f32 + 1.0 / 3.0) / N as f32, (j as f32 + 1.0 / 3.0) / N as f32);
            let p = uv[0] * (1.0 - a - b) + uv[1] * a + uv[2] * b;
            let size = Vec2::new(t.width as f32, t.height as f32);
            let texel = (p * size).floor();
            let x = (texel.x as i64).rem_euclid(t.width as i64) as usize;
            let y = (texel.y as i64).rem_euclid(t.height as i64) as usize;
            let c = t.texels[y * t.width as usize + x];
            sum += Vec3::new(srgb(c[0]), srgb(c[1]), srgb(c[2]));
            count += 1.0;
        }
    }
    sum / count
}

fn srgb(c: u8) -> f32 {
    let c = c as f32 / 255.0;
    if c > 0.04045 {
        ((c + 0.055) / 1.055).powf(2.4)
    } else {
        c / 12.92
    }
}
