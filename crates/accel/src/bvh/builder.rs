//! The fallback builder, top-down binned SAH (Wald, "On fast Construction of SAH-based Bounding
//! Volume Hierarchies", 2007): at each node the triangles' centroids are binned along each axis
//! and the plane between bins with the lowest surface-area cost is taken, or a leaf when that
//! is cheaper. Single-threaded. `Bvh::build` uses it when PLOC's tree is too deep, because
//! this one bounds the depth; `tests::measure` compares the two.
//!
//! Depth is bounded by construction: a node at depth d with n triangles is split at its
//! centroid median (children of ⌈n/2⌉ and ⌊n/2⌋) whenever d + ⌈log₂ n⌉ reaches
//! [`BVH_MAX_DEPTH`], which then still reaches single-triangle leaves at that depth at the
//! latest. Nothing here can panic on finite input; non-finite triangles never get here.

use super::{SceneTriangle, TreeNode, BVH_MAX_DEPTH};
use crate::AccelError;

/// Builder settings; [`Params::DEFAULT`] is what `Bvh::build` uses, chosen by `tests::measure`
/// (32 bins: 1.5% fewer nodes per ray for 30% more build time; leaves of 2 or 8: no better).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Params {
    /// Leaves hold at most this many triangles (fewer when SAH says so).
    pub max_leaf: usize,
    /// Bins per axis, at most [`MAX_BINS`].
    pub bins: usize,
}

impl Params {
    pub const DEFAULT: Self = Self { max_leaf: 4, bins: 16 };
}

const MAX_BINS: usize = 32;
/// SAH costs of a node visit and a triangle test; on GPUs they are about equal (a node visit
/// is a 32-byte fetch and two box tests, a triangle a 48-byte fetch and the sheared test).
const COST_NODE: f32 = 1.0;
const COST_TRIANGLE: f32 = 1.0;

/// The tree before flattening: leaves index `order`, which maps BVH slots to input triangles.
pub(crate) struct Built {
    pub nodes: Vec<TreeNode>,
    pub order: Vec<u32>,
}

#[derive(Clone, Copy, Debug)]
struct Aabb {
    lo: [f32; 3],
    hi: [f32; 3],
}

impl Aabb {
    const EMPTY: Self = Self { lo: [f32::INFINITY; 3], hi: [f32::NEG_INFINITY; 3] };

    fn grow(&mut self, o: &Aabb) {
        for a in 0..3 {
            self.lo[a] = self.lo[a].min(o.lo[a]);
            self.hi[a] = self.hi[a].max(o.hi[a]);
        }
    }

    fn grow_point(&mut self, p: &[f32; 3]) {
        self.grow(&Aabb { lo: *p, hi: *p });
    }

    fn extent(&self, a: usize) -> f32 {
        self.hi[a] - self.lo[a]
    }

    /// Half the surface area; 0 for an empty box.
    fn half_area(&self) -> f32 {
        let d = [0, 1, 2].map(|a| self.extent(a).max(0.0));
        d[0] * d[1] + d[1] * d[2] + d[2] * d[0]
    }
}

struct Input {
    bounds: Vec<Aabb>,
    centroids: Vec<[f32; 3]>,
}

pub(crate) fn build(tris: &[SceneTriangle], params: Params) -> Result<Built, AccelError> {
    let params = Params { bins: params.bins.clamp(2, MAX_BINS), max_leaf: params.max_leaf.max(1) };
    let bounds: Vec<Aabb> = tris
        .iter()
        .map(|t| {
            let (lo, hi) = t.bounds();
            Aabb { lo, hi }
        })
        .collect();
    // Halves before adding, so that huge finite coordinates cannot overflow to infinity.
    let centroids = bounds.iter().map(|b| [0, 1, 2].map(|a| b.lo[a] * 0.5 + b.hi[a] * 0.5)).collect();
    let input = Input { bounds, centroids };
    let n = tris.len();
    let mut order: Vec<u32> = (0..n as u32).collect();
    let mut nodes = Vec::with_capacity(2 * n.div_ceil(params.max_leaf).max(1));
    nodes.push(TreeNode::default());
    // (node, first, end, depth), depth first so that a subtree's nodes stay together.
    let mut tasks = vec![(0usize, 0usize, n, 0u32)];
    while let Some((node, first, end, depth)) = tasks.pop() {
        let range = &mut order[first..end];
        let (bounds, centroid_bounds) = range_bounds(&input, range);
        let split = choose_split(&input, params, range, &bounds, &centroid_bounds, depth);
        let n = &mut nodes[node];
        n.bounds_min = bounds.lo;
        n.bounds_max = bounds.hi;
        match split {
            None => {
                n.left_or_first = first as u32;
                n.count = (end - first) as u32;
            }
            Some(mid) => {
                let left = nodes.len();
                nodes[node].left_or_first = left as u32;
                nodes.extend([TreeNode::default(); 2]);
                tasks.push((left + 1, first + mid, end, depth + 1));
                tasks.push((left, first, first + mid, depth + 1));
            }
        }
    }
    if nodes.len() > u32::MAX as usize {
        return Err(AccelError::TooManyTriangles(n));
    }
    Ok(Built { nodes, order })
}

fn range_bounds(input: &Input, range: &[u32]) -> (Aabb, Aabb) {
    let (mut bounds, mut centroids) = (Aabb::EMPTY, Aabb::EMPTY);
    for &i in range {
        bounds.grow(&input.bounds[i as usize]);
        centroids.grow_point(&input.centroids[i as usize]);
    }
    (bounds, centroids)
}

fn ceil_log2(n: usize) -> u32 {
    usize::BITS - (n.max(1) - 1).leading_zeros()
}

/// Decides a node: `None` for a leaf, or `Some(mid)` after partitioning `range` so that
/// `range[..mid]` is the left child and `range[mid..]` the right one (both non-empty).
fn choose_split(
    input: &Input,
    params: Params,
    range: &mut [u32],
    bounds: &Aabb,
    centroids: &Aabb,
    depth: u32,
) -> Option<usize> {
    let (count, max_leaf) = (range.len(), params.max_leaf);
    if count == 1 {
        return None;
    }
    if depth + ceil_log2(count) >= BVH_MAX_DEPTH {
        return (count > max_leaf).then(|| median_split(input, range, centroids));
    }
    let area = bounds.half_area();
    // A flat or point-like node (degenerate triangles only) or one too large for f32 areas
    // has no meaningful SAH: no ray can be helped by splitting it well.
    let best =
        if area > 0.0 && area.is_finite() { best_sah_split(input, params.bins, range, centroids, area) } else { None };
    match best {
        Some(split) if split.cost < COST_TRIANGLE * count as f32 || count > max_leaf => {
            Some(partition(range, |i| split.bins.bin(&input.centroids[i as usize]) <= split.last_left))
        }
        None if count > max_leaf => Some(median_split(input, range, centroids)),
        _ => None,
    }
}

/// Maps centroids to bins along one axis.
#[derive(Clone, Copy)]
struct Binning {
    axis: usize,
    lo: f32,
    scale: f32,
    bins: usize,
}

impl Binning {
    fn bin(&self, c: &[f32; 3]) -> usize {
        // `as` saturates (and maps NaN to 0), so this is always a valid bin.
        (((c[self.axis] - self.lo) * self.scale) as usize).min(self.bins - 1)
    }
}

struct Split {
    bins: Binning,
    /// Bins 0..=last_left go left.
    last_left: usize,
    cost: f32,
}

fn best_sah_split(input: &Input, bins: usize, range: &[u32], centroids: &Aabb, area: f32) -> Option<Split> {
    let binnings: [Option<Binning>; 3] = [0, 1, 2].map(|axis| {
        let extent = centroids.extent(axis);
        (extent > 0.0 && extent.is_finite()).then(|| Binning {
            axis,
            lo: centroids.lo[axis],
            scale: bins as f32 / extent,
            bins,
        })
    });
    let mut bin_bounds = [[Aabb::EMPTY; MAX_BINS]; 3];
    let mut bin_counts = [[0usize; MAX_BINS]; 3];
    for &i in range {
        let (b, c) = (&input.bounds[i as usize], &input.centroids[i as usize]);
        for (axis, binning) in binnings.iter().enumerate() {
            if let Some(binning) = binning {
                let k = binning.bin(c);
                bin_bounds[axis][k].grow(b);
                bin_counts[axis][k] += 1;
            }
        }
    }
    let mut best: Option<Split> = None;
    for binning in binnings.into_iter().flatten() {
        let (boxes, counts) = (&bin_bounds[binning.axis], &bin_counts[binning.axis]);
        // Right-to-left sweep: cost of everything right of each plane.
        let mut right_cost = [0.0f32; MAX_BINS];
        let (mut acc, mut n) = (Aabb::EMPTY, 0);
        for k in (1..bins).rev() {
            acc.grow(&boxes[k]);
            n += counts[k];
            right_cost[k] = acc.half_area() * n as f32;
        }
        let (mut acc, mut n) = (Aabb::EMPTY, 0);
        for k in 0..bins - 1 {
            acc.grow(&boxes[k]);
            n += counts[k];
            if n == 0 || n == range.len() {
                continue; // one side empty: not a split
            }
            let cost = COST_NODE + COST_TRIANGLE * (acc.half_area() * n as f32 + right_cost[k + 1]) / area;
            // `<` is false for NaN, so an overflowing cost is never chosen.
            if cost < best.as_ref().map_or(f32::INFINITY, |b| b.cost) {
                best = Some(Split { bins: binning, last_left: k, cost });
            }
        }
    }
    best
}

/// Centroid median along the widest centroid extent (any halving when all centroids coincide).
fn median_split(input: &Input, range: &mut [u32], centroids: &Aabb) -> usize {
    let axis = (0..3).fold(0, |best, a| if centroids.extent(a) > centroids.extent(best) { a } else { best });
    let mid = range.len() / 2;
    range.select_nth_unstable_by(mid, |&i, &j| {
        input.centroids[i as usize][axis].total_cmp(&input.centroids[j as usize][axis])
    });
    mid
}

/// Moves the items for which `left` holds to the front; returns how many there are.
fn partition(range: &mut [u32], left: impl Fn(u32) -> bool) -> usize {
    let mut mid = 0;
    for i in 0..range.len() {
        if left(range[i]) {
            range.swap(i, mid);
            mid += 1;
        }
    }
    mid
}
