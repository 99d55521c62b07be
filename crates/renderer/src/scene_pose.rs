//! Where the scene's animated instances are at the renderer's time (docs/architecture.md §3
//! "Scenes that move"): their transforms, their world-space vertices and the compute backend's
//! top level, computed on the host when the time changes. The frame then copies the vertices
//! into the scene's vertex buffer and rebuilds the TLAS (`frame.rs`), once per change.
//!
//! The world-space vertices come from [`Scene::instance_world_vertices`], the function the
//! loader and [`Scene::frozen_at`] place instances with, so a scene played to t and the same
//! scene frozen at t hold the same vertices bit for bit.

use std::time::Instant;

use glam::Mat4;
use leakless_accel::{InstancedBvh, TopLevel};
use leakless_scene::{Scene, Vertex};

pub struct ScenePose {
    /// Seconds on the scene's clock.
    pub time: f32,
    /// World from mesh space, one per instance.
    pub transforms: Vec<Mat4>,
    /// Every instance's world-space vertices in order: the tail of the scene's vertex buffer.
    pub vertices: Vec<Vertex>,
    /// The compute backend's top level over the parts.
    pub top: TopLevel,
    /// Bumped whenever the transforms change; the GPU copies remember the version they hold.
    pub version: u64,
    /// Host time of the last change (transforms, vertices, top level), in milliseconds.
    pub update_ms: f64,
    /// Whether the scene has static triangles: the first part, which never moves.
    has_static: bool,
}

impl ScenePose {
    /// The pose at time 0, which is what the scene's vertex buffer holds after upload.
    pub fn new(scene: &Scene, bvh: &InstancedBvh) -> ScenePose {
        let transforms = scene.instance_transforms(0.0);
        let first = scene.static_triangle_count() * 3;
        ScenePose {
            time: 0.0,
            top: bvh.top_level(&transforms),
            transforms,
            vertices: scene.vertices[first..].to_vec(),
            version: 0,
            update_ms: 0.0,
            has_static: first > 0,
        }
    }

    /// Moves to time `t`; returns whether anything moved.
    pub fn set_time(&mut self, scene: &Scene, bvh: &InstancedBvh, t: f32) -> bool {
        self.time = t;
        let start = Instant::now();
        let transforms = scene.instance_transforms(t);
        if transforms == self.transforms {
            return false;
        }
        self.vertices.clear();
        for (i, m) in transforms.iter().enumerate() {
            self.vertices.extend(scene.instance_world_vertices(i, m));
        }
        self.top = bvh.top_level(&transforms);
        self.transforms = transforms;
        self.version += 1;
        self.update_ms = start.elapsed().as_secs_f64() * 1e3;
        true
    }

    /// The TLAS's transforms, one per part: the static part's identity first when the scene
    /// has static triangles, then each instance's, row-major 3×4.
    pub fn tlas_transforms(&self) -> Vec<[f32; 12]> {
        let rows = |m: &Mat4| {
            let r = |i: usize| m.row(i).to_array();
            let (a, b, c) = (r(0), r(1), r(2));
            [a[0], a[1], a[2], a[3], b[0], b[1], b[2], b[3], c[0], c[1], c[2], c[3]]
        };
        let identity = self.has_static.then_some(leakless_accel::rayquery::IDENTITY);
        identity.into_iter().chain(self.transforms.iter().map(rows)).collect()
    }
}
