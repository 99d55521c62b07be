//! Coplanar neighbours: for each triangle, the triangle across each of its edges that lies in
//! the same plane, so that a point over either lies on one flat surface.
//!
//! The renderer's visible-disk pass asks, for points around a view sample, whether the
//! sample's own surface lies under them. Over the sample's own triangle that needs no ray;
//! walking across coplanar neighbours extends that to the rest of a flat face (a wall is two
//! triangles at least, and a disk often crosses the diagonal), where it would otherwise trace
//! a short ray down per point.
//!
//! Only what stays true while the scene plays is linked: the two triangles share the edge
//! exactly (the same vertex positions), belong to the same rigid part (the static triangles,
//! or one instance: an instance moving away from a wall must not stay its neighbour), are
//! coplanar (affine motion keeps them so), both opaque (a cut-out hole is no surface), and
//! are the only two triangles on that edge.

use glam::DVec3;

use crate::Scene;

/// No coplanar neighbour across that edge.
pub const NO_NEIGHBOUR: u32 = u32::MAX;

/// 1 − |cos| of the angle between two triangles' normals below which they count as one
/// plane: about 0.8°, far inside what the visible disk's ray down would accept (a surface
/// facing like the sample within 60°, within its 10° band), so linking them changes no answer.
const COPLANAR_TOLERANCE: f64 = 1e-4;

/// An edge's end as a hashable key: the bit pattern of its position (−0 taken as +0).
fn point_key(p: [f32; 3]) -> [u32; 3] {
    p.map(|c| (c + 0.0).to_bits())
}

impl Scene {
    /// For each triangle, its coplanar neighbour across edge k (vertices k and k + 1 mod 3),
    /// or [`NO_NEIGHBOUR`] (see the module's conditions).
    pub fn coplanar_neighbours(&self) -> Vec<[u32; 3]> {
        let mut neighbours = vec![[NO_NEIGHBOUR; 3]; self.triangle_count()];
        let instances = self.instances.iter().map(|i| {
            let first = i.first_triangle as usize;
            first..first + i.triangle_count as usize
        });
        for part in std::iter::once(0..self.static_triangle_count()).chain(instances) {
            self.link_part(part, &mut neighbours);
        }
        neighbours
    }

    fn link_part(&self, part: std::ops::Range<usize>, neighbours: &mut [[u32; 3]]) {
        let position = |t: usize, k: usize| self.vertices[3 * t + k % 3].position;
        let normal = |t: usize| {
            let [a, b, c] = [0, 1, 2].map(|k| DVec3::from(position(t, k).map(f64::from)));
            (b - a).cross(c - a).normalize_or_zero()
        };
        let opaque = |t: usize| self.materials[self.triangle_material[t] as usize].alpha_cutoff.is_none();
        // Each triangle side as (its undirected edge, triangle, edge index), sorted so that the
        // sides on one edge are adjacent: a sort, not a map of lists, so that a 3M-triangle
        // scene's 9M sides cost one allocation (the map spent 10 s in malloc and hashing).
        let mut sides: Vec<([[u32; 3]; 2], u32, u8)> = Vec::with_capacity(3 * part.len());
        for t in part.filter(|&t| opaque(t) && normal(t) != DVec3::ZERO) {
            for k in 0..3 {
                let (a, b) = (point_key(position(t, k)), point_key(position(t, k + 1)));
                if a != b {
                    sides.push((if a < b { [a, b] } else { [b, a] }, t as u32, k as u8));
                }
            }
        }
        sides.sort_unstable();
        for edge in sides.chunk_by(|x, y| x.0 == y.0) {
            if let [(_, t, k), (_, u, j)] = *edge {
                let (t, u) = (t as usize, u as usize);
                if 1.0 - normal(t).dot(normal(u)).abs() < COPLANAR_TOLERANCE {
                    neighbours[t][k as usize] = u as u32;
                    neighbours[u][j as usize] = t as u32;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Material, Vertex};

    fn vertex(p: [f32; 3]) -> Vertex {
        Vertex { position: p, normal: [0.0, 1.0, 0.0], uv: [0.0, 0.0] }
    }

    fn scene(triangles: &[[[f32; 3]; 3]], materials: Vec<u32>) -> Scene {
        let vertices = triangles.iter().flat_map(|t| t.map(vertex)).collect();
        let mut cutout = Material::default_white();
        cutout.alpha_cutoff = Some(0.5);
        Scene::from_triangles("t", vertices, materials, vec![Material::default_white(), cutout], vec![], None)
    }

    const A: [f32; 3] = [0.0, 0.0, 0.0];
    const B: [f32; 3] = [1.0, 0.0, 0.0];
    const C: [f32; 3] = [1.0, 0.0, 1.0];
    const D: [f32; 3] = [0.0, 0.0, 1.0];

    #[test]
    fn a_quad_split_on_its_diagonal_is_one_surface() {
        // Opposite windings too: surfaces are two-sided.
        let s = scene(&[[A, B, C], [A, D, C]], vec![0, 0]);
        // Edge 2 of the first (C → A) is edge 2 of the second (C → A).
        assert_eq!(s.coplanar_neighbours(), vec![[NO_NEIGHBOUR, NO_NEIGHBOUR, 1], [NO_NEIGHBOUR, NO_NEIGHBOUR, 0]]);
    }

    #[test]
    fn a_fold_a_cut_out_or_a_gap_is_not() {
        let fold = scene(&[[A, B, C], [A, C, [0.5, 1.0, 0.5]]], vec![0, 0]);
        assert_eq!(fold.coplanar_neighbours(), vec![[NO_NEIGHBOUR; 3]; 2]);
        let cutout = scene(&[[A, B, C], [A, D, C]], vec![0, 1]);
        assert_eq!(cutout.coplanar_neighbours(), vec![[NO_NEIGHBOUR; 3]; 2]);
        // The second triangle's edge ends a hair away from the first's: not the same edge.
        let gap = scene(&[[A, B, C], [[0.0, 0.0, 1e-6], D, C]], vec![0, 0]);
        assert_eq!(gap.coplanar_neighbours(), vec![[NO_NEIGHBOUR; 3]; 2]);
    }

    #[test]
    fn an_edge_shared_by_three_triangles_links_none() {
        let s = scene(&[[A, B, C], [A, D, C], [A, C, [2.0, 0.0, -1.0]]], vec![0, 0, 0]);
        assert_eq!(s.coplanar_neighbours(), vec![[NO_NEIGHBOUR; 3]; 3]);
    }
}
