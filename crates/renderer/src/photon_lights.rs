//! The CPU side of photon emission: every light's emitted power, and the CDF over lights that
//! `photons.comp` samples so that lights are chosen in proportion to their power.
//!
//! Powers (RGB, W), from the shader's view of a light (`gpu_types::Light`: colour × intensity):
//! * point: 4π·I (radiant intensity I in W/sr, uniform over the sphere);
//! * spot: I·∫f dω with glTF's smooth falloff f = clamp((cos θ − c_outer)/Δ, 0, 1)², Δ =
//!   max(c_inner − c_outer, 1e-4) exactly as `light.glsl` evaluates it. With dω = dc dφ and
//!   T = min(1, (1 − c_outer)/Δ): ∫f dω = 2π·(Δ·T³/3 + max(0, 1 − c_outer − Δ));
//! * directional: E·π·R², the irradiance E (W/m²) through a disk of the radius R of the
//!   geometry's bounding sphere (the disk the shader emits from).
//!
//! * emissive triangle: π·A·s·Le (`emitters.rs`), after the punctual lights in one table.
//!
//! Lights are picked with probability p ∝ Rec.709 luminance of that power, and a path from
//! light ℓ carries flux power_rgb(ℓ) / (N·p(ℓ)), so the expected flux of N paths is the total
//! power, colour by colour. An emissive triangle's entry holds 1/p: the shader multiplies by
//! the power it emits where the path starts (π·A·s·Le(x), the texture and the posed area
//! there), so its estimate is exact even though the table's power is a mean.

use std::f64::consts::PI;

use ash::vk;
use glam::Vec3;
use leakless_graph::{BufferHandle, Graph};
use leakless_scene::{Aabb, Scene};

use crate::emitters::EmitterTable;
use crate::error::Result;
use crate::gpu_scene::gpu_light;
use crate::gpu_types::{Light, LIGHT_DIRECTIONAL, LIGHT_POINT, LIGHT_SPOT};
use crate::passes::photons::PhotonLight;

/// Rec. 709 luminance of linear RGB: how lights are weighed against each other, and what
/// the measures of images (`leakless_measure::metrics`) weigh pixels by.
pub fn luminance(rgb: [f64; 3]) -> f64 {
    0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]
}

/// The falloff's Δ = c_inner − c_outer as `light.glsl` and `photons.comp` compute it (in f32,
/// at least 1e-4).
pub fn spot_falloff_width(cos_outer: f32, cos_inner: f32) -> f32 {
    (cos_inner - cos_outer).max(1e-4)
}

/// glTF's smooth spot falloff at cos θ = `cos_angle` (`light.glsl`).
pub fn spot_falloff(cos_outer: f32, cos_inner: f32, cos_angle: f64) -> f64 {
    let t = ((cos_angle - cos_outer as f64) / spot_falloff_width(cos_outer, cos_inner) as f64).clamp(0.0, 1.0);
    t * t
}

/// ∫ falloff dω over the sphere (sr), in closed form: a spot of intensity I emits I times this.
pub fn spot_solid_angle(cos_outer: f32, cos_inner: f32) -> f64 {
    let c_outer = cos_outer as f64;
    let delta = spot_falloff_width(cos_outer, cos_inner) as f64;
    let t_max = ((1.0 - c_outer) / delta).min(1.0);
    2.0 * PI * (delta * t_max.powi(3) / 3.0 + (1.0 - c_outer - delta).max(0.0))
}

/// Emitted power (W, RGB) of a light as the shaders see it; `scene_radius` is the radius of
/// the bounding sphere that a directional light's emission disk covers.
pub fn light_power(light: &Light, scene_radius: f32) -> [f64; 3] {
    let factor = match light.kind {
        LIGHT_POINT => 4.0 * PI,
        LIGHT_SPOT => spot_solid_angle(light.cos_outer, light.cos_inner),
        LIGHT_DIRECTIONAL => PI * (scene_radius as f64).powi(2),
        _ => 0.0,
    };
    light.intensity.map(|c| c as f64 * factor)
}

/// The f32 CDF that picks entry i with probability ∝ `weights[i]` (≥ 0) by the first CDF value
/// above u ∈ [0, 1), and the probability each entry is then picked with (the width of its f32
/// interval, ∝ its weight up to rounding; 0 for weights of 0). From the last positive weight
/// on, the CDF is exactly 1, so any u < 1 finds an entry.
pub fn selection_cdf(weights: &[f64]) -> (Vec<f32>, Vec<f64>) {
    let total: f64 = weights.iter().sum();
    let last = weights.iter().rposition(|&w| w > 0.0);
    let mut cdf = Vec::with_capacity(weights.len());
    let mut sum = 0.0;
    for (i, w) in weights.iter().enumerate() {
        sum += w;
        cdf.push(if last.is_some_and(|l| i >= l) { 1.0 } else { (sum / total) as f32 });
    }
    let probabilities = (0..cdf.len()).map(|i| cdf[i] as f64 - if i == 0 { 0.0 } else { cdf[i - 1] as f64 }).collect();
    (cdf, probabilities)
}

/// The lights' powers and the selection CDF, in the scene's light order.
#[derive(Clone, Debug)]
pub struct LightTable {
    /// Centre and radius of the geometry's bounding sphere (directional emission disks).
    pub center: Vec3,
    pub radius: f32,
    /// Emitted power of each light (W, RGB): the punctual lights, then the emitters.
    pub powers: Vec<[f64; 3]>,
    /// Punctual lights at the start of the table (emissive triangles follow).
    pub punctual: usize,
    /// The probability with which the uploaded CDF selects each light (the width of its f32
    /// CDF interval; ∝ luminance of the power up to rounding).
    pub probabilities: Vec<f64>,
    /// What the GPU gets: per light, power / p (0 for lights never selected) and the CDF.
    pub entries: Vec<PhotonLight>,
}

impl LightTable {
    /// The table of the scene's lights (converted exactly as `GpuScene` uploads them).
    pub fn from_scene(scene: &Scene) -> LightTable {
        let lights: Vec<Light> = scene.lights.iter().map(gpu_light).collect();
        LightTable::new(&lights, &EmitterTable::from_scene(scene), &scene.bounds())
    }

    pub fn new(lights: &[Light], emitters: &EmitterTable, bounds: &Aabb) -> LightTable {
        let (center, radius) = (bounds.center(), bounds.bounding_radius());
        let mut powers: Vec<[f64; 3]> = lights.iter().map(|l| light_power(l, radius)).collect();
        powers.extend(&emitters.powers);
        let weights: Vec<f64> = powers.iter().map(|p| luminance(*p).max(0.0)).collect();
        let (cdf, probabilities) = selection_cdf(&weights);
        let entries = powers
            .iter()
            .zip(&probabilities)
            .zip(&cdf)
            .enumerate()
            .map(|(i, ((power, &p), &cdf))| PhotonLight {
                flux: match (p > 0.0, i < lights.len()) {
                    (false, _) => [0.0; 3],
                    (true, true) => power.map(|c| (c / p) as f32),
                    (true, false) => [(1.0 / p) as f32; 3],
                },
                cdf,
            })
            .collect();
        LightTable { center, radius, powers, punctual: lights.len(), probabilities, entries }
    }

    /// Total emitted power (W, RGB): the expected flux of all paths together.
    pub fn total_power(&self) -> [f64; 3] {
        self.powers.iter().fold([0.0; 3], |a, p| [a[0] + p[0], a[1] + p[1], a[2] + p[2]])
    }

    /// Whether any light emits anything (else no path is traced).
    pub fn emits(&self) -> bool {
        self.probabilities.iter().any(|&p| p > 0.0)
    }
}

/// One frame's lights on the GPU: `lights` (what every shading pass reads) and the photon
/// light table (`photon_lights` of photons.comp), uploaded with each frame so lights can move.
pub struct LightHandles {
    pub lights: BufferHandle,
    pub photon_lights: BufferHandle,
    pub table: LightTable,
    pub count: u32,
}

/// Uploads `lights` (in the scene's order) and their photon table, with the scene's
/// `emitters` after them, for this frame; `bounds` is the geometry a directional light's
/// emission disk covers.
pub fn upload_lights(
    graph: &mut Graph<'_>,
    lights: &[leakless_scene::Light],
    emitters: &EmitterTable,
    bounds: &Aabb,
) -> Result<LightHandles> {
    let gpu_lights: Vec<Light> = lights.iter().map(gpu_light).collect();
    let table = LightTable::new(&gpu_lights, emitters, bounds);
    let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
    Ok(LightHandles {
        lights: graph.upload("lights", storage, bytemuck::cast_slice(&gpu_lights))?,
        photon_lights: graph.upload("photon lights", storage, bytemuck::cast_slice(&table.entries))?,
        count: gpu_lights.len() as u32,
        table,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cdf_ends_at_one_and_its_widths_are_the_weights_shares() {
        let (cdf, p) = selection_cdf(&[1.0, 0.0, 3.0, 4.0, 0.0]);
        assert_eq!(cdf, [0.125, 0.125, 0.5, 1.0, 1.0], "exactly 1 from the last positive weight on");
        assert_eq!(p, [0.125, 0.0, 0.375, 0.5, 0.0]);
    }
}
