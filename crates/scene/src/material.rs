//! Lambertian albedo: `baseColorFactor` × `baseColorTexture`, plus `MASK` cut-outs, and
//! emission: `emissiveFactor` × `emissiveTexture` × `KHR_materials_emissive_strength`.
//!
//! The renderer is diffuse-only (docs/architecture.md §1), so a glTF material reduces to its
//! base colour and, for surfaces that are lights, the radiance they emit. Textures are decoded to RGBA8 once, here, so the GPU side only
//! uploads bytes; they stay sRGB-encoded so an `*_SRGB` image format decodes them
//! in the sampler.

use std::collections::HashMap;
use std::path::Path;

use glam::Vec4;
use gltf::json;
use json::validation::Checked;

use crate::accessor::Data;
use crate::uri;

/// A diffuse material.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    pub name: String,
    /// Linear RGBA `baseColorFactor` (albedo = factor × texture; alpha only matters
    /// for `alpha_cutoff`).
    pub base_color: Vec4,
    /// Index into [`crate::Scene::textures`] of the base colour texture (texcoord
    /// set 0).
    pub texture: Option<u32>,
    /// `Some(cutoff)` only for `alphaMode: MASK` (glTF default 0.5): a surface point
    /// whose alpha is below it does not exist (no hit, no shadow, no photon).
    pub alpha_cutoff: Option<f32>,
    /// Emitted radiance (W/m²/sr, linear RGB): `emissiveFactor` × `emissive_strength`, times
    /// the emissive texture where there is one. Zero for surfaces that are not lights.
    pub emission: glam::Vec3,
    /// Index into [`crate::Scene::textures`] of the emissive texture (texcoord set 0).
    pub emission_texture: Option<u32>,
    /// glTF `doubleSided`: emission leaves both faces; otherwise only the front face, the
    /// one the counter-clockwise winding faces (reflection is two-sided either way).
    pub double_sided: bool,
}

impl Material {
    /// Whether the surface is a light.
    pub fn emits(&self) -> bool {
        self.emission.max_element() > 0.0
    }
}

impl Material {
    /// The stand-in for primitives without a material: white 0.8, a common
    /// renderer default that keeps energy well below 1 per bounce.
    pub fn default_white() -> Material {
        Material {
            name: "default".into(),
            base_color: Vec4::new(0.8, 0.8, 0.8, 1.0),
            texture: None,
            alpha_cutoff: None,
            emission: glam::Vec3::ZERO,
            emission_texture: None,
            double_sided: false,
        }
    }
}

/// A decoded base colour image.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    pub width: u32,
    pub height: u32,
    /// Row-major from the top-left texel (glTF UV (0,0)); RGBA8 as stored in the
    /// file: sRGB-encoded colour, linear alpha.
    pub texels: Vec<[u8; 4]>,
}

impl Texture {
    /// The texels as bytes, ready for an `R8G8B8A8_SRGB` upload.
    pub fn bytes(&self) -> &[u8] {
        bytemuck::cast_slice(&self.texels)
    }
}

/// Why a base colour image could not be used.
pub(crate) struct ImageError {
    pub index: usize,
    pub message: String,
}

/// What [`load`] returns.
pub(crate) struct Loaded {
    /// In file order, so primitive material indices stay valid.
    pub materials: Vec<Material>,
    pub textures: Vec<Texture>,
    pub warnings: Vec<String>,
}

/// The document's materials and the textures they reference.
pub(crate) fn load(root: &json::Root, data: &Data, base: &Path) -> Result<Loaded, ImageError> {
    let mut materials = Vec::with_capacity(root.materials.len());
    let mut textures = Vec::new();
    let mut by_image: HashMap<usize, u32> = HashMap::new();
    let mut blend = Vec::new();
    let mut clamped = Vec::new();
    let mut invalid_emission = Vec::new();
    for (i, m) in root.materials.iter().enumerate() {
        let name = m.name.clone().unwrap_or_else(|| format!("material {i}"));
        let pbr = &m.pbr_metallic_roughness;
        let mut slot_of = |index: usize| -> Result<u32, ImageError> {
            let image = root
                .textures
                .get(index)
                .map(|t| t.source.value())
                // Unreachable after validation; kept so that no index is trusted.
                .ok_or_else(|| ImageError {
                    index,
                    message: format!("material '{name}' references a missing texture"),
                })?;
            if let Some(&slot) = by_image.get(&image) {
                return Ok(slot);
            }
            textures.push(decode(root, data, base, image)?);
            let slot = (textures.len() - 1) as u32;
            by_image.insert(image, slot);
            Ok(slot)
        };
        // Other texcoord sets are not loaded; the ignored-features line says so.
        let texture = match pbr.base_color_texture.as_ref().filter(|t| t.tex_coord == 0) {
            Some(info) => Some(slot_of(info.index.value())?),
            None => None,
        };
        let emission_texture = match m.emissive_texture.as_ref().filter(|t| t.tex_coord == 0) {
            Some(info) => Some(slot_of(info.index.value())?),
            None => None,
        };
        let strength =
            m.extensions.as_ref().and_then(|e| e.emissive_strength.as_ref()).map_or(1.0, |s| s.emissive_strength.0);
        let emission = glam::Vec3::from(m.emissive_factor.0) * strength;
        // Negative or non-finite emission is no light at all (a NaN would poison every
        // estimate it reaches).
        let emission = if emission.is_finite() {
            emission.max(glam::Vec3::ZERO)
        } else {
            invalid_emission.push(format!("'{name}'"));
            glam::Vec3::ZERO
        };
        let alpha_cutoff = match m.alpha_mode {
            Checked::Valid(json::material::AlphaMode::Mask) => Some(m.alpha_cutoff.as_ref().map_or(0.5, |c| c.0)),
            Checked::Valid(json::material::AlphaMode::Blend) => {
                blend.push(format!("'{name}'"));
                None
            }
            _ => None,
        };
        // glTF's range is [0, 1]: beyond it an albedo creates or destroys energy, and a
        // number past f32's range (1e39) reads as infinity.
        let factor = Vec4::from(pbr.base_color_factor.0);
        let base_color = factor.clamp(Vec4::ZERO, Vec4::ONE);
        if base_color != factor {
            clamped.push(format!("'{name}'"));
        }
        let double_sided = m.double_sided;
        materials.push(Material { name, base_color, texture, alpha_cutoff, emission, emission_texture, double_sided });
    }
    let mut warnings = Vec::new();
    if !blend.is_empty() {
        warnings.push(format!(
            "alphaMode BLEND is rendered opaque: material{} {}",
            if blend.len() > 1 { "s" } else { "" },
            blend.join(", ")
        ));
    }
    if !clamped.is_empty() {
        let s = if clamped.len() > 1 { "s" } else { "" };
        warnings.push(format!("baseColorFactor clamped to [0, 1]: material{s} {}", clamped.join(", ")));
    }
    if !invalid_emission.is_empty() {
        let s = if invalid_emission.len() > 1 { "s" } else { "" };
        warnings.push(format!(
            "emission that is not a finite number is dropped: material{s} {}",
            invalid_emission.join(", ")
        ));
    }
    Ok(Loaded { materials, textures, warnings })
}

/// Decodes image `index` (PNG or JPEG from a buffer view, a data URI or a file).
fn decode(root: &json::Root, data: &Data, base: &Path, index: usize) -> Result<Texture, ImageError> {
    let err = |message: String| ImageError { index, message };
    let image = root.images.get(index).ok_or_else(|| err("does not exist".into()))?;
    let owned;
    let bytes: &[u8] = match (&image.buffer_view, &image.uri) {
        (Some(view), _) => data.view_bytes(view.value()).map_err(err)?,
        (None, Some(u)) => {
            owned = uri::read_uri(u, base).map_err(|e| err(e.to_string()))?;
            &owned
        }
        (None, None) => return Err(err("has neither a bufferView nor a uri".into())),
    };
    let decoded = image::load_from_memory(bytes)
        .map_err(|e| err(format!("cannot decode (glTF allows PNG and JPEG): {e}")))?
        .to_rgba8();
    let (width, height) = decoded.dimensions();
    let texels = decoded.into_raw().chunks_exact(4).map(|c| [c[0], c[1], c[2], c[3]]).collect();
    Ok(Texture { width, height, texels })
}
