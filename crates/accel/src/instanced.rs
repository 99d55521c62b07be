//! The compute backend's two levels, for scenes that move (docs/architecture.md §3 "Scenes
//! that move"). The bottom level is built once: one [`Bvh`] over the static triangles (world
//! space) and one per animated instance (mesh space), concatenated into one node array and one
//! triangle array with their indices offset, so the GPU buffers are uploaded once. The top
//! level is a small binary tree over the parts' world boxes, with one part per leaf, rebuilt
//! on the host every frame from the instances' transforms ([`InstancedBvh::top_level`]) and
//! uploaded with the frame: rebuilding a tree over a handful of boxes costs microseconds,
//! while refitting would need the same upload anyway.
//!
//! The static part is traced in world space without any transform, so a scene without
//! animation traces exactly as with one BVH. An instance's ray is moved into mesh space by the
//! inverse of its transform (an affine map keeps the ray parameter t, so hits compare across
//! parts); the watertight triangle test then runs on the mesh-space vertices, which is why a
//! played animation and a scene frozen at the same time trace bit for bit alike: both test the
//! same mesh-space triangles with the same matrices.

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};
use leakless_device::{rust_layout, RustLayout};
use leakless_scene::Vertex;

use crate::bvh::{pack, Bvh, BvhNode, BvhStats, BvhTriangle, ChildRef, TreeNode, BOX_PAD};
use crate::AccelError;

/// The deepest leaf the top level may have; its traversal stack (`BVH_TOP_STACK_SIZE` in
/// trace_compute.glsl) holds this many entries. Median splits make it ⌈log2 parts⌉, so this
/// allows far more parts than [`MAX_PARTS`].
pub const BVH_TOP_MAX_DEPTH: u32 = 32;

/// At most this many parts (the static geometry and the instances): a triangle records its
/// part in 16 bits of the GPU data it carries anyway, and no scene here comes near it.
pub const MAX_PARTS: usize = 65_535;

/// One part of the top level as the GPU sees it (`struct BvhInstance` in bvh.glsl), 64
/// bytes: the rows of the map from world to the part's space, and the root of its bottom level.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct BvhInstance {
    pub local_from_world0: [f32; 4],
    pub local_from_world1: [f32; 4],
    pub local_from_world2: [f32; 4],
    /// Node index of the part's bottom-level root in the node array.
    pub root: u32,
    /// 1 for the static part: its ray is the world ray, untransformed.
    pub identity: u32,
    pub pad0: u32,
    pub pad1: u32,
}

pub const BVH_INSTANCE_LAYOUT: RustLayout =
    rust_layout!(BvhInstance { local_from_world0, local_from_world1, local_from_world2, root, identity, pad0, pad1 });

/// One bottom-level BVH of the concatenation.
#[derive(Clone, Debug)]
pub struct Part {
    /// Node index of its root.
    pub root: u32,
    /// Its root box (padded), in its own space.
    pub bounds_min: [f32; 3],
    pub bounds_max: [f32; 3],
    /// The static part: world space, never moves.
    pub identity: bool,
}

/// What goes into [`InstancedBvh::build`]: a part's triangles, in the space it is traced in.
pub struct PartInput<'a> {
    /// Three per triangle.
    pub vertices: &'a [Vertex],
    /// Index of the part's first triangle in the scene's triangle list (what hits report).
    pub first_triangle: u32,
}

/// The bottom level of every part, concatenated.
#[derive(Clone, Debug)]
pub struct InstancedBvh {
    pub nodes: Vec<BvhNode>,
    pub triangles: Vec<BvhTriangle>,
    /// The static part first when there is one (`identity`), then the instances in order.
    pub parts: Vec<Part>,
    /// Summed over the parts (build time, nodes, bytes, skipped triangles; the deepest part's
    /// depth; the SAH cost is the static part's, or the first part's).
    pub stats: BvhStats,
}

/// The top level of one frame: `nodes` for `bvh_top` (a leaf's one "triangle" is its part),
/// `instances` (one per part, in part order) for `bvh_instances`.
#[derive(Clone, Debug, PartialEq)]
pub struct TopLevel {
    pub nodes: Vec<BvhNode>,
    pub instances: Vec<BvhInstance>,
}

impl InstancedBvh {
    /// Builds the bottom levels: `static_part` (world space; `None` when every triangle moves)
    /// and one per instance (mesh space). Every box is padded by [`BOX_PAD`] of `magnitude`
    /// (the scene's largest coordinate), not just of its own part's, since an instance's rays
    /// start anywhere in the scene.
    pub fn build(
        static_part: Option<PartInput<'_>>,
        instances: &[PartInput<'_>],
        magnitude: f32,
    ) -> Result<Self, AccelError> {
        let count = static_part.is_some() as usize + instances.len();
        if count == 0 {
            return Err(AccelError::Empty);
        }
        if count > MAX_PARTS {
            return Err(AccelError::TooManyParts(count));
        }
        let mut out =
            InstancedBvh { nodes: Vec::new(), triangles: Vec::new(), parts: Vec::new(), stats: BvhStats::default() };
        let inputs = static_part.iter().map(|p| (p, true)).chain(instances.iter().map(|p| (p, false)));
        for (input, identity) in inputs {
            let bvh = Bvh::build(input.vertices)?;
            out.append(bvh, input.first_triangle, identity, magnitude)?;
        }
        Ok(out)
    }

    fn append(&mut self, bvh: Bvh, first_triangle: u32, identity: bool, magnitude: f32) -> Result<(), AccelError> {
        let node_base = self.nodes.len() as u32;
        let triangle_base = self.triangles.len() as u32;
        if self.triangles.len() + bvh.triangles.len() > crate::bvh::MAX_TRIANGLES {
            return Err(AccelError::TooManyTriangles(self.triangles.len() + bvh.triangles.len()));
        }
        // Bvh::build padded by its own magnitude; top up to the scene's.
        let own = bvh.bounds_min.iter().chain(&bvh.bounds_max).fold(f32::MIN_POSITIVE, |m, c| m.max(c.abs()));
        let extra = ((magnitude - own) * BOX_PAD).max(0.0);
        let (lower, raise) = (|v: [f32; 3]| v.map(|c| c - extra), |v: [f32; 3]| v.map(|c| c + extra));
        self.nodes.extend(bvh.nodes.iter().map(|n| BvhNode {
            min0: lower(n.min0),
            child0: ChildRef(n.child0).offset(node_base, triangle_base).0,
            max0: raise(n.max0),
            child1: ChildRef(n.child1).offset(node_base, triangle_base).0,
            min1: lower(n.min1),
            max1: raise(n.max1),
            ..Default::default()
        }));
        self.triangles
            .extend(bvh.triangles.iter().map(|t| BvhTriangle { triangle: t.triangle + first_triangle, ..*t }));
        let (bounds_min, bounds_max) = (lower(bvh.bounds_min), raise(bvh.bounds_max));
        self.parts.push(Part { root: node_base, bounds_min, bounds_max, identity });
        let s = &mut self.stats;
        let b = &bvh.stats;
        if self.parts.len() == 1 {
            s.sah_cost = b.sah_cost;
            s.builder = b.builder;
        }
        s.build_ms += b.build_ms;
        s.node_count += b.node_count;
        s.triangle_count += b.triangle_count;
        s.bytes += b.bytes;
        s.max_depth = s.max_depth.max(b.max_depth);
        s.skipped += b.skipped;
        Ok(())
    }

    /// Number of animated instances (parts that are not static).
    pub fn instance_count(&self) -> usize {
        self.parts.iter().filter(|p| !p.identity).count()
    }

    /// The top level for the instances placed by `transforms` (world from mesh space, one per
    /// instance in order; the static part needs none). A transform that cannot be inverted
    /// (a node scaled to zero) hides its instance: its box becomes empty and no ray enters it.
    pub fn top_level(&self, transforms: &[Mat4]) -> TopLevel {
        let mut transforms = transforms.iter();
        let mut instances = Vec::with_capacity(self.parts.len());
        let mut boxes = Vec::with_capacity(self.parts.len());
        for (index, part) in self.parts.iter().enumerate() {
            let lo = Vec3::from(part.bounds_min);
            let hi = Vec3::from(part.bounds_max);
            let (rows, identity, bounds) = if part.identity {
                (Mat4::IDENTITY, 1, Some((lo, hi)))
            } else {
                let m = transforms.next().copied().unwrap_or(Mat4::IDENTITY);
                let inverse = m.inverse();
                if m.determinant() == 0.0 || !inverse.is_finite() {
                    (Mat4::IDENTITY, 0, None)
                } else {
                    (inverse, 0, Some(world_box(&m, lo, hi)))
                }
            };
            let row = |r: usize| rows.row(r).to_array();
            instances.push(BvhInstance {
                local_from_world0: row(0),
                local_from_world1: row(1),
                local_from_world2: row(2),
                root: part.root,
                identity,
                ..Default::default()
            });
            // An empty box (min > max) fails every box test and every distance query.
            let (lo, hi) = bounds.unwrap_or((Vec3::splat(f32::MAX), Vec3::splat(-f32::MAX)));
            boxes.push((index as u32, lo, hi));
        }
        let mut tree = vec![TreeNode::default()];
        build_top(&mut tree, &mut boxes, 0);
        let nodes = pack(&tree).expect("top-level leaves hold one part");
        TopLevel { nodes, instances }
    }
}

/// The world box of a part's mesh-space box under `m`: its eight corners transformed, padded by
/// [`BOX_PAD`] of the result's magnitude for the rounding of the transform (the ray's transform
/// into mesh space rounds too; the bottom level's own padding covers the triangle test).
fn world_box(m: &Mat4, lo: Vec3, hi: Vec3) -> (Vec3, Vec3) {
    let corners = leakless_scene::Aabb { min: lo, max: hi }.corners().map(|c| m.transform_point3(c));
    let min = corners.iter().fold(Vec3::splat(f32::INFINITY), |a, &c| a.min(c));
    let max = corners.iter().fold(Vec3::splat(f32::NEG_INFINITY), |a, &c| a.max(c));
    let pad = min.abs().max(max.abs()).max_element() * BOX_PAD * 4.0;
    (min - pad, max + pad)
}

/// Median split on the longest axis of the centres, children adjacent (as in the bottom
/// level): `nodes[at]` becomes the node over `items`.
fn build_top(nodes: &mut Vec<TreeNode>, items: &mut [(u32, Vec3, Vec3)], at: usize) {
    let lo = items.iter().fold(Vec3::splat(f32::MAX), |a, i| a.min(i.1));
    let hi = items.iter().fold(Vec3::splat(-f32::MAX), |a, i| a.max(i.2));
    if let [(part, ..)] = items {
        nodes[at] = TreeNode { bounds_min: lo.to_array(), left_or_first: *part, bounds_max: hi.to_array(), count: 1 };
        return;
    }
    let left = nodes.len();
    nodes.extend([TreeNode::default(); 2]);
    nodes[at] = TreeNode { bounds_min: lo.to_array(), left_or_first: left as u32, bounds_max: hi.to_array(), count: 0 };
    // Centres of empty boxes are 0 (MAX + -MAX): they sort among the rest harmlessly.
    let centre = |i: &(u32, Vec3, Vec3)| (i.1 + i.2) * 0.5;
    let c_lo = items.iter().fold(Vec3::splat(f32::MAX), |a, i| a.min(centre(i)));
    let c_hi = items.iter().fold(Vec3::splat(-f32::MAX), |a, i| a.max(centre(i)));
    let axis = (c_hi - c_lo).max_position();
    items.sort_by(|a, b| centre(a)[axis].total_cmp(&centre(b)[axis]).then(a.0.cmp(&b.0)));
    let mid = items.len() / 2;
    let (l, r) = items.split_at_mut(mid);
    build_top(nodes, l, left);
    build_top(nodes, r, left + 1);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad(z: f32) -> Vec<Vertex> {
        let v = |x: f32, y: f32| Vertex { position: [x, y, z], normal: [0.0, 0.0, 1.0], uv: [0.0; 2] };
        vec![v(0.0, 0.0), v(1.0, 0.0), v(1.0, 1.0), v(0.0, 0.0), v(1.0, 1.0), v(0.0, 1.0)]
    }

    #[test]
    fn parts_are_concatenated_with_offset_indices_and_tagged() {
        let (a, b) = (quad(0.0), quad(2.0));
        let bvh = InstancedBvh::build(
            Some(PartInput { vertices: &a, first_triangle: 0 }),
            &[PartInput { vertices: &b, first_triangle: 2 }],
            4.0,
        )
        .unwrap();
        assert_eq!(bvh.parts.len(), 2);
        assert!(bvh.parts[0].identity && !bvh.parts[1].identity);
        let root1 = bvh.parts[1].root as usize;
        assert!(root1 > 0);
        // Each part's triangles follow the previous part's, renumbered into the scene's list.
        let mut seen: Vec<u32> = bvh.triangles.iter().map(|t| t.triangle).collect();
        seen[..2].sort();
        seen[2..].sort();
        assert_eq!(seen, vec![0, 1, 2, 3]);
        // Every child of the second part's nodes is in the second part's nodes or triangles.
        for n in &bvh.nodes[root1..] {
            for i in 0..2 {
                let (.., child) = n.child(i);
                if child.is_leaf() {
                    assert!(child.triangles().start >= 2);
                } else {
                    assert!(child.node() as usize > root1);
                }
            }
        }
    }

    #[test]
    fn the_top_level_holds_every_part_once_within_its_box() {
        let quads: Vec<Vec<Vertex>> = (0..5).map(|i| quad(i as f32)).collect();
        let inputs: Vec<PartInput> =
            quads.iter().enumerate().map(|(i, q)| PartInput { vertices: q, first_triangle: 2 * i as u32 }).collect();
        let bvh = InstancedBvh::build(None, &inputs, 10.0).unwrap();
        let moves: Vec<Mat4> = (0..5).map(|i| Mat4::from_translation(Vec3::new(3.0 * i as f32, 0.0, 0.0))).collect();
        let top = bvh.top_level(&moves);
        assert_eq!(top.instances.len(), 5);
        assert_eq!(top.nodes.len(), 4, "a binary tree over 5 leaves has 4 interior nodes");
        let leaves: Vec<_> =
            top.nodes.iter().flat_map(|n| [n.child(0), n.child(1)]).filter(|c| c.2.is_leaf()).collect();
        let mut parts: Vec<u32> = leaves.iter().map(|(.., c)| c.triangles().start).collect();
        parts.sort();
        assert_eq!(parts, vec![0, 1, 2, 3, 4]);
        for (lo, hi, child) in leaves {
            assert_eq!(child.triangles().len(), 1);
            let x = 3.0 * child.triangles().start as f32;
            assert!(lo[0] <= x && hi[0] >= x + 1.0, "{lo:?} {hi:?}");
            // The row maps world back to mesh space.
            let inst = &top.instances[child.triangles().start as usize];
            assert_eq!(inst.local_from_world0[3], -x);
        }
    }

    #[test]
    fn a_degenerate_transform_hides_its_instance() {
        let q = quad(0.0);
        let bvh = InstancedBvh::build(None, &[PartInput { vertices: &q, first_triangle: 0 }], 1.0).unwrap();
        let top = bvh.top_level(&[Mat4::from_scale(Vec3::ZERO)]);
        assert!(top.nodes[0].min0[0] > top.nodes[0].max0[0]);
    }
}
