//! Instances: the triangles of animated mesh nodes, kept in mesh space so that a
//! renderer can re-place them every frame.

use glam::{Mat3, Mat4, Vec3};

use crate::mesh::unit;
use crate::Vertex;

/// The triangles of one animated mesh node (a mesh node that an animation channel,
/// or one on any of its ancestors, moves). They occupy
/// `first_triangle..first_triangle + triangle_count` of [`Scene::vertices`] and
/// [`Scene::triangle_material`], placed there at t = 0.
///
/// [`Scene::vertices`]: crate::Scene::vertices
/// [`Scene::triangle_material`]: crate::Scene::triangle_material
#[derive(Clone, Debug)]
pub struct Instance {
    /// The node's name, else its mesh's, else `node N`.
    pub name: String,
    /// Index of the instance's first triangle in the scene's triangle list.
    pub first_triangle: u32,
    pub triangle_count: u32,
    /// Mesh-space vertices, three per triangle, wound as in the file (no mirroring
    /// swap: [`Scene::instance_world_vertices`](crate::Scene::instance_world_vertices)
    /// applies it for the transform at hand). Normals are unit length; a primitive
    /// without normals gets its flat mesh-space face normals.
    pub local_vertices: Vec<Vertex>,
    /// The node's slot in the scene's rig.
    pub(crate) slot: usize,
}

impl Instance {
    /// The instance's triangle indices in the scene's triangle list.
    pub fn triangles(&self) -> std::ops::Range<usize> {
        self.first_triangle as usize..(self.first_triangle + self.triangle_count) as usize
    }
}

/// Mesh-space triangles to world space under `m`, exactly as the static loader
/// treats a node's triangles (see `mesh.rs`): positions by `m`, normals by its
/// inverse transpose and normalised (a normal that cannot be normalised becomes the
/// triangle's face normal), and the second and third vertex swapped when `m`
/// mirrors (negative determinant), so that the winding still agrees with the
/// normals.
pub(crate) fn world_vertices(local: &[Vertex], m: &Mat4) -> Vec<Vertex> {
    let normal_matrix = Mat3::from_mat4(*m).inverse().transpose();
    let mirrored = m.determinant() < 0.0;
    let mut out = Vec::with_capacity(local.len());
    for tri in local.chunks_exact(3) {
        let t = if mirrored { [tri[0], tri[2], tri[1]] } else { [tri[0], tri[1], tri[2]] };
        let p = t.map(|v| m.transform_point3(Vec3::from(v.position)));
        let face = unit((p[1] - p[0]).cross(p[2] - p[0])).unwrap_or(Vec3::Y);
        for (k, v) in t.iter().enumerate() {
            let normal = unit(normal_matrix * Vec3::from(v.normal)).unwrap_or(face);
            out.push(Vertex { position: p[k].to_array(), normal: normal.to_array(), uv: v.uv });
        }
    }
    out
}
