//! The default builder: obvhs' PLOC (Meister and Bittner, "Parallel Locally-Ordered Clustering
//! for Bounding Volume Hierarchy Construction", 2018) with its reinsertion optimisation and
//! SAH leaf collapsing, re-laid out depth first with adjacent children as our nodes want.
//!
//! Chosen over our binned SAH by `tests::measure` (numbers in the `bvh` module's docs): on a
//! scene of many overlapping objects it visits ~40% fewer nodes per ray and builds faster; on
//! a single dense mesh the two are within 10%. PLOC does not bound the depth, so `Bvh::build`
//! falls back to binned SAH when the tree is deeper than the shader's stack.

use obvhs::aabb::Aabb;
use obvhs::bvh2::leaf_collapser::collapse;
use obvhs::bvh2::reinsertion::ReinsertionOptimizer;
use obvhs::ploc::PlocBuilder;
use obvhs::BvhBuildParams;

use super::{SceneTriangle, TreeNode};

/// obvhs' `medium_build` ("about embree's build time, faster traversal"), with leaves of at
/// most 4 triangles and a node visit costing as much as a triangle test in the collapse, as
/// in our binned SAH: on GPUs a node (32-byte fetch, two box tests) and a triangle (48-byte
/// fetch, the sheared test) cost about the same. Measured: obvhs' own leaves of 8 take ~45%
/// more triangle tests for ~2% fewer node visits.
pub(crate) const PARAMS: BvhBuildParams =
    BvhBuildParams { max_prims_per_leaf: 4, collapse_traversal_cost: 1.0, ..BvhBuildParams::medium_build() };

/// Builds over `tris` (at least one); returns our nodes and the BVH-slot → `tris` order.
pub(crate) fn build(tris: &[SceneTriangle], params: BvhBuildParams) -> (Vec<TreeNode>, Vec<u32>) {
    let aabbs: Vec<Aabb> = tris
        .iter()
        .map(|t| {
            let (lo, hi) = t.bounds();
            Aabb { min: lo.into(), max: hi.into() }
        })
        .collect();
    // obvhs::bvh2::builder::build_bvh2 without its debug-build validation pass.
    let indices = (0..tris.len() as u32).collect();
    let mut bvh = PlocBuilder::with_capacity(tris.len()).build(
        params.ploc_search_distance,
        &aabbs,
        indices,
        params.sort_precision,
        params.search_depth_threshold,
    );
    let mut reinsertion = ReinsertionOptimizer::default();
    reinsertion.run(&mut bvh, params.reinsertion_batch_ratio, None);
    collapse(&mut bvh, params.max_prims_per_leaf.clamp(1, 255), params.collapse_traversal_cost);
    let post_collapse = params.reinsertion_batch_ratio * params.post_collapse_reinsertion_batch_ratio_multiplier;
    reinsertion.run(&mut bvh, post_collapse, None);

    // Walk from the root: obvhs may leave unused nodes in its array, and we want a subtree's
    // nodes together, children adjacent, and each leaf's triangles contiguous.
    let mut nodes = vec![TreeNode::default()];
    let mut order = Vec::with_capacity(tris.len());
    let mut stack = vec![(0usize, 0usize)]; // (theirs, ours)
    while let Some((theirs, ours)) = stack.pop() {
        let n = &bvh.nodes[theirs];
        nodes[ours].bounds_min = n.aabb.min.into();
        nodes[ours].bounds_max = n.aabb.max.into();
        if n.prim_count == 0 {
            let left = nodes.len();
            nodes[ours].left_or_first = left as u32;
            nodes.extend([TreeNode::default(); 2]);
            stack.push((n.first_index as usize + 1, left + 1));
            stack.push((n.first_index as usize, left));
        } else {
            nodes[ours].left_or_first = order.len() as u32;
            nodes[ours].count = n.prim_count;
            let first = n.first_index as usize;
            order.extend_from_slice(&bvh.primitive_indices[first..first + n.prim_count as usize]);
        }
    }
    (nodes, order)
}
