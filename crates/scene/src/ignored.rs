//! The one "ignored: ..." warning line (docs/architecture.md §4).
//!
//! A file from any exporter should load, so unused features are never errors, but
//! the user should know in one glance why a scene may look different from another
//! viewer. One line in total keeps logs readable however rich the file is.

use gltf::json;
use json::mesh::Semantic;
use json::texture::WrappingMode;
use json::validation::Checked;

/// Extensions the loader implements; every other one in `extensionsUsed` is
/// reported as ignored.
pub(crate) const IMPLEMENTED_EXTENSIONS: &[&str] =
    &["KHR_lights_punctual", "KHR_mesh_quantization", "KHR_materials_emissive_strength"];

/// Collects what a file has that the renderer does not use.
#[derive(Default)]
pub(crate) struct Ignored {
    items: Vec<String>,
}

impl Ignored {
    pub fn add(&mut self, item: impl Into<String>) {
        let item = item.into();
        if !self.items.contains(&item) {
            self.items.push(item);
        }
    }

    /// The warning line, or `None` when nothing was ignored.
    pub fn line(&self) -> Option<String> {
        (!self.items.is_empty()).then(|| format!("ignored: {}", self.items.join(", ")))
    }

    /// Scans the whole document (not only the rendered scene: the user asked for
    /// this file, and anything in it that will not show is worth a mention).
    pub fn scan(root: &json::Root, extra_extensions: &[String]) -> Ignored {
        let mut ig = Ignored::default();
        // Animations are played (node TRS channels); `weights` channels and
        // unknown paths are reported by `animation::load`.
        counted(&mut ig, root.skins.len(), "skin");
        counted(&mut ig, root.scenes.len().saturating_sub(1), "other scene");
        let prims = || root.meshes.iter().flat_map(|m| m.primitives.iter());
        if prims().any(|p| p.targets.as_ref().is_some_and(|t| !t.is_empty())) {
            ig.add("morph targets");
        }
        let mut attributes: Vec<String> = Vec::new();
        for p in prims() {
            for key in p.attributes.keys() {
                let name = match key {
                    Checked::Valid(Semantic::Positions | Semantic::Normals | Semantic::TexCoords(0)) => continue,
                    Checked::Valid(s) => semantic_name(s),
                    Checked::Invalid => "unknown".to_string(),
                };
                if !attributes.contains(&name) {
                    attributes.push(name);
                }
            }
        }
        if !attributes.is_empty() {
            ig.add(format!("vertex attributes {}", attributes.join(" ")));
        }
        for m in &root.materials {
            let pbr = &m.pbr_metallic_roughness;
            if m.emissive_texture.as_ref().is_some_and(|t| t.tex_coord != 0) {
                ig.add("emissive textures on texcoord sets other than 0");
            }
            // glTF's default metallicFactor is 1 (metal); a diffuse file says 0.
            // Roughness alone is not reported: it only shapes a specular lobe that a
            // Lambertian renderer drops for every material anyway.
            if pbr.metallic_factor.0 > 0.0 || pbr.metallic_roughness_texture.is_some() {
                ig.add("metalness");
            }
            if m.normal_texture.is_some() {
                ig.add("normal textures");
            }
            if m.occlusion_texture.is_some() {
                ig.add("occlusion textures");
            }
            if pbr.base_color_texture.as_ref().is_some_and(|t| t.tex_coord != 0) {
                ig.add("base colour textures on texcoord sets other than 0");
            }
        }
        if root.samplers.iter().any(|s| s.mag_filter.is_some() || s.min_filter.is_some()) {
            ig.add("sampler filters");
        }
        let repeat = |w: &Checked<WrappingMode>| matches!(w, Checked::Valid(WrappingMode::Repeat));
        if root.samplers.iter().any(|s| !repeat(&s.wrap_s) || !repeat(&s.wrap_t)) {
            ig.add("sampler wrap modes");
        }
        for ext in root.extensions_used.iter().chain(extra_extensions) {
            if !IMPLEMENTED_EXTENSIONS.contains(&ext.as_str()) {
                ig.add(ext.clone());
            }
        }
        ig
    }
}

/// Adds "N things" (plural aware) when `n > 0`.
pub(crate) fn counted(ig: &mut Ignored, n: usize, what: &str) {
    match n {
        0 => {}
        1 => ig.add(format!("1 {what}")),
        n => ig.add(format!("{n} {what}s")),
    }
}

fn semantic_name(s: &Semantic) -> String {
    match s {
        Semantic::Positions => "POSITION".into(),
        Semantic::Normals => "NORMAL".into(),
        Semantic::Tangents => "TANGENT".into(),
        Semantic::Colors(i) => format!("COLOR_{i}"),
        Semantic::TexCoords(i) => format!("TEXCOORD_{i}"),
        Semantic::Joints(i) => format!("JOINTS_{i}"),
        Semantic::Weights(i) => format!("WEIGHTS_{i}"),
        #[allow(unreachable_patterns)]
        _ => "custom".into(),
    }
}
