//! The scene model of `leakless`: the small part of glTF 2.0 the renderer needs.
//!
//! DESIGN.md §4 ("model no more than a scene needs") fixes the subset: triangle
//! meshes flattened to world space, Lambertian albedo (`baseColorFactor` ×
//! `baseColorTexture`), `alphaMode: MASK` cut-outs, the first perspective camera and
//! `KHR_lights_punctual` lights. Everything else in a file is ignored with one
//! warning line, never an error, so that any exporter's output loads.
//!
//! The geometry is an unindexed world-space triangle list because every consumer
//! (BLAS/BVH builders, the G-buffer raster, the photon tracer) wants exactly that,
//! and the scenes the project renders are small enough that instancing would only
//! add code paths to keep in agreement across two trace backends.
//!
//! Loading never panics on bad input: the glTF is validated, every index and byte
//! range is bounds-checked here (the `gltf` crate's own readers assume well-formed
//! data), and each failure becomes one [`SceneError`] line.

mod accessor;
mod bounds;
mod camera;
mod error;
mod ignored;
mod light;
mod load;
mod material;
mod mesh;
mod uri;

use std::path::Path;

pub use bounds::Aabb;
pub use camera::Camera;
pub use error::SceneError;
pub use light::{Light, LightKind};
pub use material::{Material, Texture};

/// One vertex of the flat triangle list, laid out for direct upload to a GPU buffer
/// (std430-compatible: 8 floats, 32 bytes, no padding).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Vertex {
    /// World-space position (metres in the project's own scenes).
    pub position: [f32; 3],
    /// World-space unit shading normal. Surfaces are two-sided, so its sign only
    /// matters relative to the triangle's winding, which the loader keeps consistent
    /// (see [`Scene::vertices`]).
    pub normal: [f32; 3],
    /// Texture coordinates of set 0 (0,0 when the primitive has none).
    pub uv: [f32; 2],
}

const _: () = assert!(std::mem::size_of::<Vertex>() == 32);

/// A loaded scene, flattened to world space.
#[derive(Clone, Debug)]
pub struct Scene {
    /// The file stem, used in messages, EXR headers and statistics.
    pub name: String,
    /// World-space vertices, three per triangle (an unindexed triangle list). The
    /// winding is counter-clockwise around the shading normal as in the file, also
    /// under mirroring node transforms (the loader swaps two vertices there).
    pub vertices: Vec<Vertex>,
    /// Index into [`Scene::materials`] for each triangle.
    pub triangle_material: Vec<u32>,
    /// Never empty: a white 0.8 material stands in for primitives without one.
    pub materials: Vec<Material>,
    /// Base colour textures referenced by [`Material::texture`].
    pub textures: Vec<Texture>,
    /// The first perspective camera met in a depth-first walk of the scene's nodes.
    pub camera: Option<Camera>,
    /// Punctual lights in world space; never empty after [`Scene::load`].
    pub lights: Vec<Light>,
    /// Human-readable warnings (ignored features, skipped primitives, ...), one
    /// line each, for the caller to print.
    pub warnings: Vec<String>,
    /// The raw JSON of the glTF scene's `extras`, if any. The project's scenes put
    /// their analytic constants there (e.g. `sphere.gltf`: radius, albedo and light
    /// intensity) so that tests read them from the file rather than repeat them.
    pub extras: Option<String>,
}

impl Scene {
    /// Loads a `.gltf` (embedded or external buffers) or `.glb` file.
    pub fn load(path: &Path) -> Result<Scene, SceneError> {
        load::load(path)
    }

    /// Axis-aligned bounds of all vertices (a zero box at the origin if there are
    /// none).
    pub fn bounds(&self) -> Aabb {
        Aabb::from_points(self.vertices.iter().map(|v| glam::Vec3::from(v.position)))
    }

    /// The file's camera, else one that frames [`Scene::bounds`]: see
    /// [`Camera::framing`].
    pub fn camera_or_framing(&self) -> Camera {
        self.camera.clone().unwrap_or_else(|| Camera::framing(&self.bounds()))
    }

    /// Number of triangles (`vertices.len() / 3`).
    pub fn triangle_count(&self) -> usize {
        self.vertices.len() / 3
    }
}
