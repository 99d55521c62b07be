//! The scene model of `leakless`: the small part of glTF 2.0 the renderer needs.
//!
//! docs/architecture.md §4 ("model no more than a scene needs") fixes the subset: triangle
//! meshes flattened to world space, Lambertian albedo (`baseColorFactor` ×
//! `baseColorTexture`), `alphaMode: MASK` cut-outs, the first perspective camera,
//! `KHR_lights_punctual` lights, emissive materials (area lights: `emissiveFactor` ×
//! `emissiveTexture` × `KHR_materials_emissive_strength`) and node animation (below). Everything else in a
//! file is ignored with one warning line, never an error, so that any exporter's
//! output loads.
//!
//! The geometry is an unindexed world-space triangle list because every consumer
//! (BLAS/BVH builders, the G-buffer raster, the photon tracer) wants exactly that,
//! and the scenes the project renders are small enough that instancing static
//! meshes would only add code paths to keep in agreement across two trace backends.
//!
//! # Animation
//!
//! Dynamic scenes (a door swinging shut, a light walking through a doorway) are
//! rigid parts moving, which is exactly glTF node animation: channels driving a
//! node's `translation`, `rotation` or `scale` through `STEP`, `LINEAR` (slerp for
//! rotations) or `CUBICSPLINE` samplers (glTF 2.0 §3.11 and Appendix C). What is
//! modelled, and no more:
//!
//! * One clock, in seconds. Every animation in the file plays at once on it: glTF
//!   does not say which to play, and a scene file here describes one motion, which
//!   an exporter may split over several animations. Where two channels drive the
//!   same property of one node, the later in file order wins. A channel holds its
//!   first key's value before that key and its last key's after the last, as glTF
//!   specifies, so from [`Scene::duration`] on the scene is at rest.
//! * A mesh node that a channel moves, itself or through an ancestor, becomes an
//!   [`Instance`]: its triangles in mesh space, and its world transform at any time
//!   ([`Scene::instance_transforms`], [`Scene::instance_world_vertices`]). All other
//!   triangles stay static. [`Scene::vertices`] is the pose at t = 0, static
//!   triangles first in the usual order and then each instance's, so a renderer
//!   rebuilds only the instances' ranges, and a file without animation loads
//!   exactly as it would without this feature.
//! * Lights and the camera follow their nodes ([`Scene::lights_at`],
//!   [`Scene::camera_at`]). Which lights exist and which camera is used is decided
//!   at t = 0.
//! * [`Scene::frozen_at`] bakes one time into a scene without animation, for
//!   reference renders and for tests that a played animation matches it.
//!
//! Left out, and why:
//!
//! * Skins and morph targets (and `weights` channels): they deform meshes per
//!   vertex, which would need a second vertex path in both trace backends for
//!   scenes the project does not have. Such meshes load in their bind pose or base
//!   shape, and the "ignored" line names them.
//! * `KHR_animation_pointer` (animated materials, light intensities, fields of
//!   view): material, light power and projection are fixed per scene in the
//!   renderer. Its channels have no `target.node`, which the `gltf` crate's parser
//!   requires, so such a file is refused as malformed rather than half-played.
//! * Channel paths other than the four of glTF 2.0: ignored, and reported.
//! * Playback policy (looping, speed, choosing one animation): the caller's, by the
//!   time it passes in.
//!
//! A bad channel (times not finite and strictly increasing, an output count that
//! does not match, a missing target node, a target node with a `matrix`) fails the
//! load with one [`SceneError::Animation`] line naming the animation and channel: a
//! half-played animation would show a scene the file does not describe.
//!
//! Loading never panics on bad input: the glTF is validated, every index and byte
//! range is bounds-checked here (the `gltf` crate's own readers assume well-formed
//! data), and each failure becomes one [`SceneError`] line.

mod accessor;
mod adjacency;
mod animation;
mod bounds;
mod camera;
mod error;
mod ignored;
mod instance;
mod light;
mod load;
mod material;
mod mesh;
mod uri;

use std::path::Path;

pub use adjacency::NO_NEIGHBOUR;
pub use bounds::Aabb;
pub use camera::Camera;
pub use error::SceneError;
pub use instance::Instance;
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

/// A loaded scene, flattened to world space (at t = 0 when it is animated).
#[derive(Clone, Debug)]
pub struct Scene {
    /// The file stem, used in messages, EXR headers and statistics.
    pub name: String,
    /// World-space vertices, three per triangle (an unindexed triangle list). The
    /// winding is counter-clockwise around the shading normal as in the file, also
    /// under mirroring node transforms (the loader swaps two vertices there).
    ///
    /// Static triangles come first ([`Scene::static_triangle_count`]), then each
    /// [`Instance`]'s contiguously, posed at t = 0.
    pub vertices: Vec<Vertex>,
    /// Index into [`Scene::materials`] for each triangle.
    pub triangle_material: Vec<u32>,
    /// Never empty: a white 0.8 material stands in for primitives without one.
    pub materials: Vec<Material>,
    /// Base colour textures referenced by [`Material::texture`].
    pub textures: Vec<Texture>,
    /// The first perspective camera met in a depth-first walk of the scene's nodes
    /// (at t = 0: [`Scene::camera_at`]).
    pub camera: Option<Camera>,
    /// Punctual lights in world space; never empty after [`Scene::load`] (at t = 0:
    /// [`Scene::lights_at`]).
    pub lights: Vec<Light>,
    /// Human-readable warnings (ignored features, skipped primitives, ...), one
    /// line each, for the caller to print.
    pub warnings: Vec<String>,
    /// The raw JSON of the glTF scene's `extras`, if any. The project's scenes put
    /// their analytic constants there (e.g. `sphere.gltf`: radius, albedo and light
    /// intensity) so that tests read them from the file rather than repeat them.
    pub extras: Option<String>,
    /// The animated mesh nodes, in the order of their triangles (empty for a scene
    /// without animation).
    pub instances: Vec<Instance>,
    /// The placed node hierarchy and its channels.
    rig: animation::Rig,
}

impl Scene {
    /// A scene made in code, without animation: world-space triangles (three vertices each),
    /// one material index per triangle, lights and an optional camera. For tests and tools
    /// that build geometry instead of loading a file.
    pub fn from_triangles(
        name: impl Into<String>,
        vertices: Vec<Vertex>,
        triangle_material: Vec<u32>,
        materials: Vec<Material>,
        lights: Vec<Light>,
        camera: Option<Camera>,
    ) -> Scene {
        Scene {
            name: name.into(),
            vertices,
            triangle_material,
            materials,
            textures: Vec::new(),
            camera,
            lights,
            warnings: Vec::new(),
            extras: None,
            instances: Vec::new(),
            rig: animation::Rig::default(),
        }
    }

    /// Loads a `.gltf` (embedded or external buffers) or `.glb` file.
    pub fn load(path: &Path) -> Result<Scene, SceneError> {
        let mut scene = load::load(path)?;
        // One line each, whatever names and extension strings the file holds.
        for w in &mut scene.warnings {
            let line = error::one_line(w);
            if line != w.as_str() {
                *w = line.into_owned();
            }
        }
        Ok(scene)
    }

    /// Axis-aligned bounds of all vertices (a zero box at the origin if there are
    /// none): of the t = 0 pose when the scene is animated, so that what is derived
    /// from them (the framing camera, scale-aware epsilons, default radii) does not
    /// change while it plays. A scene from [`Scene::frozen_at`] keeps the bounds of
    /// the scene it was frozen from, for the same reason: rendering it must give
    /// what rendering the playing scene gives. Geometry that moves can leave these
    /// bounds: see [`Scene::animated_bounds`].
    pub fn bounds(&self) -> Aabb {
        if let Some((b, _)) = self.rig.frozen_bounds {
            return b;
        }
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

    /// Number of static triangles: they come first in [`Scene::vertices`] and
    /// never move. All triangles when there are no instances.
    pub fn static_triangle_count(&self) -> usize {
        self.instances.first().map_or(self.triangle_count(), |i| i.first_triangle as usize)
    }

    /// Whether any animation channel moves a node of the scene (false for a file
    /// without animations and for [`Scene::frozen_at`]'s result).
    pub fn is_animated(&self) -> bool {
        self.rig.is_animated()
    }

    /// Seconds until everything is at rest: the last key time of any channel that
    /// moves a node of the scene (0 without animation).
    pub fn duration(&self) -> f32 {
        self.rig.channels.iter().map(|c| c.end()).fold(0.0, f32::max)
    }

    /// The world transform of each of [`Scene::instances`] at time `t` (seconds;
    /// clamped to the keys as glTF specifies): the product down the node hierarchy
    /// with the animated translation, rotation and scale substituted. Together
    /// with [`Scene::instance_world_vertices`] it gives exactly the loader's t = 0
    /// vertices for `t = 0.0`.
    pub fn instance_transforms(&self, t: f32) -> Vec<glam::Mat4> {
        if self.instances.is_empty() {
            return Vec::new();
        }
        let world = self.rig.world_at(t);
        self.instances.iter().map(|i| world[i.slot]).collect()
    }

    /// The world-space vertices of instance `instance` under `transform`: positions
    /// by the matrix, normals by its inverse transpose (normalised), and the winding
    /// swap of mirroring transforms, exactly as for static triangles. This is the
    /// one function that places instances (the loader uses it for t = 0), so equal
    /// matrices give bit-identical vertices. Panics if `instance` is out of range.
    pub fn instance_world_vertices(&self, instance: usize, transform: &glam::Mat4) -> Vec<Vertex> {
        instance::world_vertices(&self.instances[instance].local_vertices, transform)
    }

    /// [`Scene::lights`] at time `t`: the same lights in the same order, with the
    /// position and direction of those on animated nodes recomputed. A light whose
    /// node transform is degenerate at `t` (say, scaled to zero) keeps its t = 0
    /// placement. `lights_at(0.0)` equals [`Scene::lights`].
    pub fn lights_at(&self, t: f32) -> Vec<Light> {
        let mut lights = self.lights.clone();
        if !self.rig.is_animated() || self.rig.lights.is_empty() {
            return lights;
        }
        let world = self.rig.world_at(t);
        for (i, slot, index, def) in &self.rig.lights {
            if let (Some(l), Ok(placed)) = (lights.get_mut(*i), light::from_json(*index, def, world[*slot])) {
                l.position = placed.position;
                l.direction = placed.direction;
            }
        }
        lights
    }

    /// [`Scene::camera`] at time `t`: its view follows an animated camera node
    /// (projection unchanged). A degenerate node transform at `t` keeps the t = 0
    /// view. `camera_at(0.0)` equals [`Scene::camera`].
    pub fn camera_at(&self, t: f32) -> Option<Camera> {
        let mut cam = self.camera.clone()?;
        if let (true, Some((slot, index, def))) = (self.rig.is_animated(), &self.rig.camera) {
            let world = self.rig.world_at(t);
            if let Ok(placed) = camera::from_json(*index, def, world[*slot]) {
                cam.world_from_camera = placed.world_from_camera;
            }
        }
        Some(cam)
    }

    /// A copy of the scene at time `t` without animation: the same instances (same
    /// local vertices, now fixed at their transforms at `t`), and vertices, lights
    /// and camera evaluated at `t`. Rendering it is rendering this scene played to
    /// `t`: its [`Scene::instance_transforms`] are this scene's at `t` for any time,
    /// bit for bit, and its [`Scene::bounds`] and [`Scene::animated_bounds`] are
    /// this scene's (not those of its own vertices).
    pub fn frozen_at(&self, t: f32) -> Scene {
        let mut vertices = self.vertices.clone();
        for (i, m) in self.instance_transforms(t).iter().enumerate() {
            let first = self.instances[i].first_triangle as usize * 3;
            let placed = self.instance_world_vertices(i, m);
            vertices[first..first + placed.len()].copy_from_slice(&placed);
        }
        let mut rig = self.rig.frozen_at(t);
        rig.frozen_bounds = Some((self.bounds(), self.animated_bounds()));
        Scene { vertices, camera: self.camera_at(t), lights: self.lights_at(t), rig, ..self.clone() }
    }

    /// Bounds that cover the scene throughout its animation, approximately: the
    /// union of [`Scene::bounds`] (t = 0) and each instance's mesh-space box,
    /// transformed, at every key time of every channel and three evenly spaced
    /// times between consecutive keys (at most 4096 times in all). Motion between
    /// those times (a fast spin, a spline overshooting) can leave it; pad it if that
    /// matters. Equals [`Scene::bounds`] without animation.
    pub fn animated_bounds(&self) -> Aabb {
        if let Some((_, a)) = self.rig.frozen_bounds {
            return a;
        }
        let b = self.bounds();
        if !self.is_animated() || self.instances.is_empty() {
            return b;
        }
        let local: Vec<[glam::Vec3; 8]> = self
            .instances
            .iter()
            .map(|i| Aabb::from_points(i.local_vertices.iter().map(|v| glam::Vec3::from(v.position))).corners())
            .collect();
        let mut points = vec![b.min, b.max];
        for t in self.rig.bounds_times() {
            for (m, corners) in self.instance_transforms(t).iter().zip(&local) {
                points.extend(corners.iter().map(|&c| m.transform_point3(c)).filter(|p| p.is_finite()));
            }
        }
        Aabb::from_points(points)
    }
}
