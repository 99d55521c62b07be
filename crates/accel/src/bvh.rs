//! The compute-shader trace backend: a binary BVH over the scene's world-space triangles, built
//! on the CPU (obvhs' PLOC, or our binned SAH when PLOC's tree is too deep for the shader's
//! stack) and flattened into two GPU arrays, [`BvhNode`]s and [`BvhTriangle`]s, that
//! `shaders-glsl/trace_compute.glsl` traverses.
//!
//! Builder choice, measured by `tests::measure` (release build, this 2-core machine, 200k
//! triangles, 100k incoherent rays from inside the scene; work per closest-hit ray counted as
//! nodes visited + triangles tested by the traversal below, on every tree):
//!
//! | scene | builder | build | SAH cost | nodes + tris/ray | depth |
//! |---|---|---|---|---|---|
//! | terrain, 60 spheres, 3.6k thin boxes | obvhs PLOC `medium_build`, leaf ≤ 4 | 145–151 ms | 327 | 97 + 12.5 | 35 |
//! | | binned SAH (ours), leaf ≤ 4, 16 bins | 165–200 ms | 426 | 163 + 13.5 | 24 |
//! | bumpy torus (one dense mesh) | obvhs PLOC `medium_build`, leaf ≤ 4 | 73–97 ms | 45.3 | 13.4 + 1.22 | 23 |
//! | | binned SAH (ours), leaf ≤ 4, 16 bins | 168–175 ms | 41.5 | 12.3 + 1.23 | 19 |
//!
//! Both make 16–17 MB of GPU arrays. In the dev profile (tests; dependencies optimised, this
//! crate not) the mixed scene builds in 0.37 s with PLOC and 1.9 s with binned SAH. PLOC with
//! reinsertion wins clearly where objects overlap, as in real scenes, and builds
//! faster; binned SAH wins by 8% on the single mesh and bounds the depth by construction.
//!
//! [`Bvh::intersect`] is the CPU twin of `trace_bvh` in that file: the same traversal order and
//! the same watertight ray/triangle test ([`intersect_triangle`], Woop, Benthin and Wald 2013),
//! operation for operation, so tests here speak for the shader.
//!
//! Triangles are reordered so that each leaf's are contiguous, and each carries its original
//! scene index, which is what every query returns: material lookups and both trace backends
//! agree on it.

mod builder;
mod intersect;
mod nodes;
mod ploc;
#[cfg(test)]
mod tests;

use std::time::Instant;

use bytemuck::{Pod, Zeroable};
use leakless_device::{rust_layout, RustLayout};
use leakless_scene::Vertex;

use crate::AccelError;
pub use intersect::{intersect_triangle, Ray};
pub use nodes::{pack, BvhNode, ChildRef, TreeNode, BVH_NODE_LAYOUT, EMPTY_BOX, MAX_LEAF_TRIANGLES};

/// The deepest leaf a BVH may have (the root is depth 0). The GLSL traversal pushes at most one
/// node per level, so its stack (`BVH_STACK_SIZE` in trace_compute.glsl, checked equal by a
/// test) needs exactly this many entries. PLOC made trees 33–35 deep for 200k triangles and
/// does not bound the depth: a deeper tree is rebuilt with binned SAH, which switches to
/// median splits near the limit and so never exceeds it.
pub const BVH_MAX_DEPTH: u32 = 64;

/// A child reference holds a leaf's first triangle in 27 bits ([`ChildRef`]): 134M triangles,
/// 5 GiB of them, beyond any device's storage-buffer range.
pub const MAX_TRIANGLES: usize = (1 << 27) - 1;

/// One triangle in BVH order (`struct BvhTriangle` in bvh.glsl), 40 bytes: the raw
/// world-space vertices, since the watertight test needs them (precomputed edges would round
/// differently for the two triangles sharing an edge), and the original scene triangle index.
/// No padding: 40 bytes a triangle is what bounds a scene's size on a 128 MiB storage-buffer
/// range (3.3M triangles), with the vertex positions' 36.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct BvhTriangle {
    pub v0: [f32; 3],
    /// Index of this triangle in the scene's triangle list (`Scene::vertices[3 * i ..]`).
    pub triangle: u32,
    pub v1: [f32; 3],
    pub v2: [f32; 3],
}

pub const BVH_TRIANGLE_LAYOUT: RustLayout = rust_layout!(BvhTriangle { v0, triangle, v1, v2 });

/// What building cost and how good the tree is, for `--stats`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BvhStats {
    /// Wall time of [`Bvh::build`], flattening included.
    pub build_ms: f64,
    pub node_count: u32,
    /// Triangles in the BVH: the scene's, less those [`skipped`](Self::skipped).
    pub triangle_count: u32,
    /// Bytes of the two GPU arrays.
    pub bytes: usize,
    /// Expected cost of a random ray relative to one triangle test, with a node visit costing
    /// as much as a triangle test: Σ_interior A(n)/A(root) + Σ_leaves count·A(l)/A(root).
    pub sah_cost: f32,
    /// Depth of the deepest leaf (root = 0), at most [`BVH_MAX_DEPTH`].
    pub max_depth: u32,
    /// Triangles left out because a vertex position is NaN or infinite: no ray can hit them.
    pub skipped: u32,
    /// Which builder made the tree: [`BUILDER_PLOC`], or [`BUILDER_SAH_FALLBACK`] when PLOC's
    /// tree was deeper than [`BVH_MAX_DEPTH`].
    pub builder: &'static str,
}

pub const BUILDER_PLOC: &str = "obvhs PLOC";
pub const BUILDER_SAH_FALLBACK: &str = "binned SAH (PLOC tree too deep)";
#[cfg(test)]
const BUILDER_SAH: &str = "binned SAH";

/// What a traversal looks for: an intersection of origin + t·dir with t in (`tmin`, `tmax`),
/// the closest, or with `any_hit` the first accepted.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayQuery {
    pub origin: [f32; 3],
    pub dir: [f32; 3],
    pub tmin: f32,
    pub tmax: f32,
    pub any_hit: bool,
}

/// A ray's closest (or, for `any_hit`, first accepted) intersection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub t: f32,
    /// Original scene triangle index.
    pub triangle: u32,
    /// Barycentrics: p = (1-u-v)·v0 + u·v1 + v·v2, as GL_EXT_ray_query reports them.
    pub u: f32,
    pub v: f32,
}

/// A BVH ready for upload: `nodes` to the `bvh_nodes` buffer, `triangles` to `bvh_triangles`.
#[derive(Clone, Debug)]
pub struct Bvh {
    pub nodes: Vec<BvhNode>,
    /// The root's box (padded): no node holds it.
    pub bounds_min: [f32; 3],
    pub bounds_max: [f32; 3],
    pub triangles: Vec<BvhTriangle>,
    pub stats: BvhStats,
}

/// Work counters of one traversal (for measuring tree quality).
#[derive(Clone, Copy, Debug, Default)]
pub struct TraversalCounts {
    /// Nodes fetched and processed (interior or leaf), the root included.
    pub nodes: u64,
    /// Ray/triangle tests.
    pub triangles: u64,
}

impl Bvh {
    /// Builds over a flat triangle list (3 vertices per triangle, world space). Triangles with a
    /// non-finite vertex are left out (counted in [`BvhStats::skipped`]); degenerate (zero-area)
    /// triangles are kept, as the intersection test never reports them.
    pub fn build(vertices: &[Vertex]) -> Result<Self, AccelError> {
        let positions: Vec<[f32; 3]> = vertices.iter().map(|v| v.position).collect();
        Self::build_positions(&positions)
    }

    /// [`Bvh::build`] from positions alone.
    pub fn build_positions(positions: &[[f32; 3]]) -> Result<Self, AccelError> {
        let start = Instant::now();
        let (tris, skipped) = finite_triangles(positions)?;
        let (nodes, order) = ploc::build(&tris, ploc::PARAMS);
        let mut bvh = match Self::flatten(&tris, nodes, &order, skipped, BUILDER_PLOC, BVH_MAX_DEPTH) {
            // PLOC does not bound the depth; binned SAH does, by construction.
            Err(AccelError::TooDeep { .. }) => {
                let built = builder::build(&tris, builder::Params::DEFAULT)?;
                Self::flatten(&tris, built.nodes, &built.order, skipped, BUILDER_SAH_FALLBACK, BVH_MAX_DEPTH)?
            }
            result => result?,
        };
        bvh.stats.build_ms = start.elapsed().as_secs_f64() * 1e3;
        Ok(bvh)
    }

    /// Builds with our binned SAH only (tests and measurement).
    #[cfg(test)]
    pub(crate) fn build_binned(positions: &[[f32; 3]], params: builder::Params) -> Result<Self, AccelError> {
        let start = Instant::now();
        let (tris, skipped) = finite_triangles(positions)?;
        let built = builder::build(&tris, params)?;
        let mut bvh = Self::flatten(&tris, built.nodes, &built.order, skipped, BUILDER_SAH, BVH_MAX_DEPTH)?;
        bvh.stats.build_ms = start.elapsed().as_secs_f64() * 1e3;
        Ok(bvh)
    }

    /// Builds with PLOC only, any depth allowed (measurement: traverse the result with
    /// `traverse_with_stack`, as it may need more than the shader's stack).
    #[cfg(test)]
    pub(crate) fn build_ploc(positions: &[[f32; 3]], params: ::obvhs::BvhBuildParams) -> Result<Self, AccelError> {
        let start = Instant::now();
        let (tris, skipped) = finite_triangles(positions)?;
        let (nodes, order) = ploc::build(&tris, params);
        let mut bvh = Self::flatten(&tris, nodes, &order, skipped, BUILDER_PLOC, u32::MAX)?;
        bvh.stats.build_ms = start.elapsed().as_secs_f64() * 1e3;
        Ok(bvh)
    }

    /// Turns a tree over `tris` (leaves indexing `order`, which maps BVH slots to `tris`) into
    /// the GPU arrays: pads the boxes, reorders the triangles, and measures the result.
    fn flatten(
        tris: &[SceneTriangle],
        mut nodes: Vec<TreeNode>,
        order: &[u32],
        skipped: u32,
        builder: &'static str,
        max_depth_allowed: u32,
    ) -> Result<Self, AccelError> {
        let triangles: Vec<BvhTriangle> = order
            .iter()
            .map(|&i| {
                let t = &tris[i as usize];
                let [v0, v1, v2] = t.v;
                BvhTriangle { v0, triangle: t.index, v1, v2 }
            })
            .collect();
        // The box test is conservative for the exact ray (Ize 2013, see `intersect`), but the
        // triangle test rounds in its own sheared frame: a ray that numerically hits a
        // triangle exactly at its box's face could be culled by the box test. Padding every
        // box by a few ulps of the scene's magnitude (more than the triangle test's rounding
        // for any ray starting within the scene's scale) closes that gap. Equal padding for
        // all nodes keeps children inside their parents.
        let scale =
            nodes[0].bounds_min.iter().chain(&nodes[0].bounds_max).fold(f32::MIN_POSITIVE, |m, c| m.max(c.abs()));
        let pad = scale * BOX_PAD;
        for n in &mut nodes {
            for a in 0..3 {
                n.bounds_min[a] -= pad;
                n.bounds_max[a] += pad;
            }
        }
        let max_depth = depth(&nodes);
        if max_depth > max_depth_allowed {
            return Err(AccelError::TooDeep { depth: max_depth });
        }
        let packed = pack(&nodes)?;
        let stats = BvhStats {
            build_ms: 0.0,
            node_count: nodes.len() as u32,
            triangle_count: triangles.len() as u32,
            bytes: std::mem::size_of_val(packed.as_slice()) + std::mem::size_of_val(triangles.as_slice()),
            sah_cost: sah_cost(&nodes),
            max_depth,
            skipped,
            builder,
        };
        Ok(Self { nodes: packed, bounds_min: nodes[0].bounds_min, bounds_max: nodes[0].bounds_max, triangles, stats })
    }

    /// The closest intersection with `t` in (`tmin`, `tmax`), or with `any_hit` the first one
    /// found. Exactly `trace_bvh` of trace_compute.glsl with every candidate accepted.
    pub fn intersect(&self, origin: [f32; 3], dir: [f32; 3], tmin: f32, tmax: f32, any_hit: bool) -> Option<Hit> {
        self.intersect_filtered(RayQuery { origin, dir, tmin, tmax, any_hit }, |_, _| true)
    }

    /// [`Bvh::intersect`] with `accept(triangle, [u, v])` deciding for each candidate hit, as
    /// `trace_alpha_pass` does in the shader (false: an alpha mask cuts the surface away).
    pub fn intersect_filtered(&self, query: RayQuery, accept: impl FnMut(u32, [f32; 2]) -> bool) -> Option<Hit> {
        self.traverse(query, accept, &mut TraversalCounts::default())
    }

    /// The traversal, counting its work. Keep in step with `trace_bvh` in trace_compute.glsl.
    pub fn traverse(
        &self,
        query: RayQuery,
        accept: impl FnMut(u32, [f32; 2]) -> bool,
        counts: &mut TraversalCounts,
    ) -> Option<Hit> {
        self.traverse_with_stack::<{ BVH_MAX_DEPTH as usize }>(query, accept, counts)
    }

    /// [`Bvh::traverse`] with a stack of `STACK` entries (only for measuring trees deeper than
    /// [`BVH_MAX_DEPTH`]; for ours a larger stack changes nothing).
    pub(crate) fn traverse_with_stack<const STACK: usize>(
        &self,
        query: RayQuery,
        mut accept: impl FnMut(u32, [f32; 2]) -> bool,
        counts: &mut TraversalCounts,
    ) -> Option<Hit> {
        let RayQuery { origin, dir, tmin, tmax, any_hit } = query;
        let ray = Ray::new(origin, dir);
        let mut best: Option<Hit> = None;
        let mut t_best = tmax;
        let mut stack = [ChildRef(0); STACK];
        let mut sp = 0usize;
        // Each node box-tests its children; the root's box is the shader's top level's to test
        // (a part's box), and a ray that misses it visits nothing.
        ray.box_entry(self.bounds_min, self.bounds_max, tmin, t_best)?;
        let mut node = ChildRef::interior(0);
        loop {
            counts.nodes += 1;
            if !node.is_leaf() {
                let n = &self.nodes[node.node() as usize];
                let [(lo0, hi0, left), (lo1, hi1, right)] = [n.child(0), n.child(1)];
                let d0 = ray.box_entry(lo0, hi0, tmin, t_best);
                let d1 = ray.box_entry(lo1, hi1, tmin, t_best);
                match (d0, d1) {
                    (Some(d0), Some(d1)) => {
                        // Near child first: its hits shrink t_best and cull the far one.
                        let (near, far) = if d0 <= d1 { (left, right) } else { (right, left) };
                        if sp < stack.len() {
                            stack[sp] = far;
                            sp += 1;
                        }
                        node = near;
                        continue;
                    }
                    (Some(_), None) => {
                        node = left;
                        continue;
                    }
                    (None, Some(_)) => {
                        node = right;
                        continue;
                    }
                    (None, None) => {}
                }
            } else {
                for i in node.triangles() {
                    counts.triangles += 1;
                    let tri = &self.triangles[i as usize];
                    let Some((t, [u, v])) = intersect_triangle(&ray, tri.v0, tri.v1, tri.v2, tmin, t_best) else {
                        continue;
                    };
                    if !accept(tri.triangle, [u, v]) {
                        continue;
                    }
                    t_best = t;
                    best = Some(Hit { t, triangle: tri.triangle, u, v });
                    if any_hit {
                        return best;
                    }
                }
            }
            if sp == 0 {
                return best;
            }
            sp -= 1;
            node = stack[sp];
        }
    }
}

/// Relative box padding (of the scene's largest coordinate magnitude): 2^-19 ≈ 1.9e-6, above
/// the ~4 ulps by which the sheared triangle test can misplace an edge for rays whose origin
/// lies within a few scene magnitudes of the triangle.
pub(crate) const BOX_PAD: f32 = 1.0 / 524_288.0;

/// A scene triangle that made it into the BVH.
pub(crate) struct SceneTriangle {
    pub v: [[f32; 3]; 3],
    /// Index in the scene's triangle list.
    pub index: u32,
}

impl SceneTriangle {
    pub fn bounds(&self) -> ([f32; 3], [f32; 3]) {
        let mut lo = self.v[0];
        let mut hi = self.v[0];
        for p in &self.v[1..] {
            for a in 0..3 {
                lo[a] = lo[a].min(p[a]);
                hi[a] = hi[a].max(p[a]);
            }
        }
        (lo, hi)
    }
}

/// Groups positions into triangles, leaving out those with a non-finite coordinate (their
/// boxes would poison the build, and no ray hits them). Errors on an empty or ragged list.
fn finite_triangles(positions: &[[f32; 3]]) -> Result<(Vec<SceneTriangle>, u32), AccelError> {
    if positions.len() % 3 != 0 {
        return Err(AccelError::NotTriangles(positions.len()));
    }
    let count = positions.len() / 3;
    if count == 0 {
        return Err(AccelError::Empty);
    }
    if count > MAX_TRIANGLES {
        return Err(AccelError::TooManyTriangles(count));
    }
    let tris: Vec<SceneTriangle> = positions
        .chunks_exact(3)
        .zip(0u32..)
        .filter(|(v, _)| v.iter().flatten().all(|c| c.is_finite()))
        .map(|(v, index)| SceneTriangle { v: [v[0], v[1], v[2]], index })
        .collect();
    if tris.is_empty() {
        return Err(AccelError::NoFiniteTriangles(count));
    }
    let skipped = (count - tris.len()) as u32;
    Ok((tris, skipped))
}

fn half_area(n: &TreeNode) -> f32 {
    let d = [0, 1, 2].map(|a| (n.bounds_max[a] - n.bounds_min[a]).max(0.0));
    d[0] * d[1] + d[1] * d[2] + d[2] * d[0]
}

/// See [`BvhStats::sah_cost`].
fn sah_cost(nodes: &[TreeNode]) -> f32 {
    let root = half_area(&nodes[0]) as f64;
    if !(root > 0.0 && root.is_finite()) {
        return nodes.len() as f32;
    }
    let sum: f64 = nodes.iter().map(|n| half_area(n) as f64 * n.count.max(1) as f64).sum();
    (sum / root) as f32
}

/// Depth of the deepest leaf (root = 0).
fn depth(nodes: &[TreeNode]) -> u32 {
    let mut max = 0;
    let mut stack = vec![(0u32, 0u32)];
    while let Some((i, d)) = stack.pop() {
        let n = &nodes[i as usize];
        if n.count == 0 {
            stack.push((n.left_or_first, d + 1));
            stack.push((n.left_or_first + 1, d + 1));
        } else {
            max = max.max(d);
        }
    }
    max
}
