//! Mesh primitives flattened to world-space triangles.
//!
//! Normals go through the inverse transpose of the node matrix (correct under
//! non-uniform scale). A mirroring node (negative determinant) would reverse every
//! triangle's winding relative to its normal, so two vertices are swapped there:
//! downstream code may then rely on `cross(b - a, c - a)` agreeing in sign with
//! the shading normal, whatever the transform.

use glam::{Mat3, Mat4, Vec2, Vec3};
use gltf::json;
use json::accessor::Type;
use json::mesh::{Mode, Semantic};
use json::validation::Checked;

use crate::accessor::Data;
use crate::Vertex;

/// Triangles gathered so far, plus what was skipped (for the warnings).
#[derive(Default)]
pub(crate) struct Geometry {
    pub vertices: Vec<Vertex>,
    pub triangle_material: Vec<u32>,
    /// Primitive modes that are not triangles, with how often they were skipped.
    pub skipped_modes: Vec<(&'static str, usize)>,
    pub without_positions: usize,
    pub ragged_indices: usize,
}

pub(crate) enum MeshError {
    Buffer(String),
    NonFinite,
}

impl Geometry {
    /// Appends every triangle primitive of `mesh` under the world transform `world`.
    /// `material` maps a primitive's material index to the scene's.
    pub fn append(
        &mut self,
        mesh: &json::Mesh,
        world: Mat4,
        data: &Data,
        mut material: impl FnMut(Option<usize>) -> u32,
    ) -> Result<(), MeshError> {
        let normal_matrix = Mat3::from_mat4(world).inverse().transpose();
        let mirrored = world.determinant() < 0.0;
        for prim in &mesh.primitives {
            let mode = match prim.mode {
                Checked::Valid(m) => m,
                Checked::Invalid => Mode::Triangles,
            };
            if !matches!(mode, Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan) {
                self.skip_mode(mode_name(mode));
                continue;
            }
            let attr = |s: Semantic| prim.attributes.get(&Checked::Valid(s)).map(|i| i.value());
            let Some(pos_acc) = attr(Semantic::Positions) else {
                self.without_positions += 1;
                continue;
            };
            let positions = data.floats(pos_acc, Type::Vec3).map_err(MeshError::Buffer)?;
            let n = positions.len() / 3;
            let normals = match attr(Semantic::Normals) {
                Some(a) => Some(same_count(data.floats(a, Type::Vec3), 3, n, "NORMAL")?),
                None => None,
            };
            let uvs = match attr(Semantic::TexCoords(0)) {
                Some(a) => Some(same_count(data.floats(a, Type::Vec2), 2, n, "TEXCOORD_0")?),
                None => None,
            };
            let list: Vec<u32> = match prim.indices {
                Some(i) => data.indices(i.value()).map_err(MeshError::Buffer)?,
                None => (0..n as u32).collect(),
            };
            if let Some(&bad) = list.iter().find(|&&i| i as usize >= n) {
                return Err(MeshError::Buffer(format!("vertex index {bad} >= vertex count {n}")));
            }
            let tris = triangles(mode, &list);
            if mode == Mode::Triangles && list.len() % 3 != 0 {
                self.ragged_indices += 1;
            }
            let mat = material(prim.material.map(|m| m.value()));
            for mut t in tris {
                if mirrored {
                    t.swap(1, 2);
                }
                let p = t.map(|i| {
                    let i = i as usize;
                    world.transform_point3(Vec3::new(positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]))
                });
                if !p.iter().all(|v| v.is_finite()) {
                    return Err(MeshError::NonFinite);
                }
                // Degenerate triangles keep a valid (arbitrary) normal so no NaN
                // reaches a shader; they are never hit anyway.
                let face = unit((p[1] - p[0]).cross(p[2] - p[0])).unwrap_or(Vec3::Y);
                for (k, &i) in t.iter().enumerate() {
                    let i = i as usize;
                    let normal = normals
                        .as_ref()
                        .and_then(|ns| unit(normal_matrix * Vec3::new(ns[3 * i], ns[3 * i + 1], ns[3 * i + 2])))
                        .unwrap_or(face);
                    // A non-finite coordinate (a float from a corrupt buffer) would reach
                    // the sampler as NaN: it reads as 0, as for a primitive without UVs.
                    let uv = uvs.as_ref().map_or(Vec2::ZERO, |u| Vec2::new(u[2 * i], u[2 * i + 1]));
                    let uv = Vec2::select(uv.is_finite_mask(), uv, Vec2::ZERO);
                    self.vertices.push(Vertex {
                        position: p[k].to_array(),
                        normal: normal.to_array(),
                        uv: uv.to_array(),
                    });
                }
                self.triangle_material.push(mat);
            }
        }
        Ok(())
    }

    fn skip_mode(&mut self, name: &'static str) {
        match self.skipped_modes.iter_mut().find(|(m, _)| *m == name) {
            Some((_, count)) => *count += 1,
            None => self.skipped_modes.push((name, 1)),
        }
    }
}

/// `v` at unit length, or `None` for a zero or non-finite vector. Divided by its
/// largest component first: a tiny vector's squared length is subnormal (a huge
/// one's overflows), and normalizing that directly gives a length well off 1.
pub(crate) fn unit(v: Vec3) -> Option<Vec3> {
    let m = v.abs().max_element();
    if !(m.is_finite() && m > 0.0) {
        return None;
    }
    (v / m).try_normalize()
}

/// Requires an attribute to have as many elements as the positions.
fn same_count(r: Result<Vec<f32>, String>, dims: usize, n: usize, what: &str) -> Result<Vec<f32>, MeshError> {
    let v = r.map_err(MeshError::Buffer)?;
    if v.len() != dims * n {
        return Err(MeshError::Buffer(format!("{what} has {} elements but POSITION has {n}", v.len() / dims)));
    }
    Ok(v)
}

/// Triangle vertex indices of a triangle list, strip or fan (both of the latter
/// are still triangles, so they are converted rather than skipped), each
/// counter-clockwise as glTF defines it.
fn triangles(mode: Mode, list: &[u32]) -> Vec<[u32; 3]> {
    match mode {
        Mode::TriangleStrip => (2..list.len())
            .map(|i| if i % 2 == 0 { [list[i - 2], list[i - 1], list[i]] } else { [list[i - 1], list[i - 2], list[i]] })
            .collect(),
        Mode::TriangleFan => (2..list.len()).map(|i| [list[0], list[i - 1], list[i]]).collect(),
        _ => list.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
    }
}

fn mode_name(mode: Mode) -> &'static str {
    match mode {
        Mode::Points => "POINTS",
        Mode::Lines => "LINES",
        Mode::LineLoop => "LINE_LOOP",
        Mode::LineStrip => "LINE_STRIP",
        Mode::Triangles => "TRIANGLES",
        Mode::TriangleStrip => "TRIANGLE_STRIP",
        Mode::TriangleFan => "TRIANGLE_FAN",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Strips alternate winding and fans pivot on the first vertex; every
    /// triangle keeps glTF's counter-clockwise order (up to rotation).
    #[test]
    fn strips_and_fans_become_triangles() {
        let l = [0, 1, 2, 3, 4];
        assert_eq!(triangles(Mode::TriangleStrip, &l), vec![[0, 1, 2], [2, 1, 3], [2, 3, 4]]);
        assert_eq!(triangles(Mode::TriangleFan, &l), vec![[0, 1, 2], [0, 2, 3], [0, 3, 4]]);
        assert_eq!(triangles(Mode::Triangles, &l), vec![[0, 1, 2]]);
        assert!(triangles(Mode::TriangleStrip, &l[..2]).is_empty());
    }
}
