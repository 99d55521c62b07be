//! The tree as the builders make it ([`TreeNode`]: a binary node with its own box) and as the
//! traversals read it ([`BvhNode`]: an interior node holding both children's boxes).
//!
//! A traversal step tests both children of the node it holds. With each node's box in the node
//! itself, that step loads the node (for its children's index) and then the two children (for
//! their boxes): two loads, the second waiting on the first. With the children's boxes in the
//! parent, one 64-byte load serves the step, and leaves need no node of their own: a child
//! reference says where a leaf's triangles are. The same memory as before (interior nodes are
//! half the tree, at twice the size), the same boxes tested in the same order.

use bytemuck::{Pod, Zeroable};
use leakless_device::{rust_layout, RustLayout};

use crate::AccelError;

/// A node of the binary tree the builders make, children adjacent. `count == 0`: interior,
/// children `left_or_first` and `left_or_first + 1`; `count > 0`: a leaf with triangles
/// `left_or_first .. left_or_first + count`. The root is node 0.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TreeNode {
    pub bounds_min: [f32; 3],
    pub left_or_first: u32,
    pub bounds_max: [f32; 3],
    pub count: u32,
}

/// An interior node as the GPU reads it (`struct BvhNode` in bvh.glsl), 64 bytes: the boxes of
/// its two children and a [child reference](ChildRef) to each. The root is node 0 (a part's, in
/// the concatenation of `InstancedBvh`, its `root`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct BvhNode {
    pub min0: [f32; 3],
    pub child0: u32,
    pub max0: [f32; 3],
    pub child1: u32,
    pub min1: [f32; 3],
    pub pad0: u32,
    pub max1: [f32; 3],
    pub pad1: u32,
}

pub const BVH_NODE_LAYOUT: RustLayout = rust_layout!(BvhNode { min0, child0, max0, child1, min1, pad0, max1, pad1 });

impl BvhNode {
    /// Child `i` (0 or 1)'s box and reference.
    pub fn child(&self, i: usize) -> ([f32; 3], [f32; 3], ChildRef) {
        debug_assert!(i < 2, "a node has two children");
        match i {
            0 => (self.min0, self.max0, ChildRef(self.child0)),
            _ => (self.min1, self.max1, ChildRef(self.child1)),
        }
    }
}

/// A box no ray enters and no distance query comes near: a one-leaf tree's second child, a
/// hidden instance.
pub const EMPTY_BOX: ([f32; 3], [f32; 3]) = ([f32::MAX; 3], [-f32::MAX; 3]);

/// Where a child is (`bvh_is_leaf` … in bvh.glsl): an interior node's index, or a leaf's
/// triangles as `LEAF | (count - 1) << 27 | first`. A leaf holds at most
/// [`MAX_LEAF_TRIANGLES`], its triangles lie below 2²⁷ ([`MAX_TRIANGLES`](super::MAX_TRIANGLES)),
/// so no reference is the shaders' `NO_HIT` (0xffffffff).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ChildRef(pub u32);

const LEAF: u32 = 1 << 31;
const COUNT_SHIFT: u32 = 27;
const FIRST_MASK: u32 = (1 << COUNT_SHIFT) - 1;

/// The most triangles (or, in the top level, parts) a leaf may hold.
pub const MAX_LEAF_TRIANGLES: u32 = 16;

impl ChildRef {
    pub fn interior(node: u32) -> Self {
        debug_assert!(node < LEAF);
        ChildRef(node)
    }

    pub fn leaf(first: u32, count: u32) -> Self {
        debug_assert!((1..=MAX_LEAF_TRIANGLES).contains(&count) && first + count <= FIRST_MASK);
        ChildRef(LEAF | (count - 1) << COUNT_SHIFT | first)
    }

    pub fn is_leaf(self) -> bool {
        self.0 & LEAF != 0
    }

    /// An interior child's node index.
    pub fn node(self) -> u32 {
        self.0
    }

    /// A leaf's triangles (parts, in the top level).
    pub fn triangles(self) -> std::ops::Range<u32> {
        let first = self.0 & FIRST_MASK;
        first..first + ((self.0 & !LEAF) >> COUNT_SHIFT) + 1
    }

    /// The same child with its node and triangle indices moved by `nodes` and `triangles`
    /// (a part's tree placed after others).
    pub fn offset(self, nodes: u32, triangles: u32) -> Self {
        if self.is_leaf() {
            let r = self.triangles();
            ChildRef::leaf(r.start + triangles, r.len() as u32)
        } else {
            ChildRef::interior(self.0 + nodes)
        }
    }
}

/// The tree's interior nodes with their children's boxes, in the tree's order (a subtree's
/// nodes stay together). A tree that is one leaf becomes one node whose second child is empty.
pub fn pack(tree: &[TreeNode]) -> Result<Vec<BvhNode>, AccelError> {
    let mut index = vec![0u32; tree.len()];
    let mut interior = 0u32;
    for (i, n) in tree.iter().enumerate() {
        if n.count == 0 {
            index[i] = interior;
            interior += 1;
        } else if n.count > MAX_LEAF_TRIANGLES {
            return Err(AccelError::LeafTooLarge(n.count));
        }
    }
    let child = |c: u32| {
        let n = &tree[c as usize];
        let r =
            if n.count == 0 { ChildRef::interior(index[c as usize]) } else { ChildRef::leaf(n.left_or_first, n.count) };
        (n.bounds_min, n.bounds_max, r)
    };
    let node = |(min0, max0, c0): ([f32; 3], [f32; 3], ChildRef), (min1, max1, c1): ([f32; 3], [f32; 3], ChildRef)| {
        BvhNode { min0, child0: c0.0, max0, child1: c1.0, min1, max1, ..Default::default() }
    };
    if tree[0].count != 0 {
        let (lo, hi, leaf) = child(0);
        return Ok(vec![node((lo, hi, leaf), (EMPTY_BOX.0, EMPTY_BOX.1, leaf))]);
    }
    Ok(tree.iter().filter(|n| n.count == 0).map(|n| node(child(n.left_or_first), child(n.left_or_first + 1))).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A leaf reference gives back its triangles at the ends of its ranges, is told from an
    /// interior one, and is never the shaders' NO_HIT; offsets move each kind by its own base.
    #[test]
    fn child_references_round_trip_and_never_read_as_no_hit() {
        let last = super::super::MAX_TRIANGLES as u32;
        for (first, count) in
            [(0, 1), (0, MAX_LEAF_TRIANGLES), (last - MAX_LEAF_TRIANGLES, MAX_LEAF_TRIANGLES), (last - 1, 1)]
        {
            let leaf = ChildRef::leaf(first, count);
            assert!(leaf.is_leaf());
            assert_eq!(leaf.triangles(), first..first + count);
            assert_ne!(leaf.0, u32::MAX);
        }
        let interior = ChildRef::interior(7);
        assert!(!interior.is_leaf());
        assert_eq!(interior.offset(10, 100), ChildRef::interior(17));
        assert_eq!(ChildRef::leaf(3, 2).offset(10, 100).triangles(), 103..105);
    }

    /// A three-leaf tree packs into two nodes whose children carry the tree's boxes; a leaf of
    /// more triangles than a reference counts is an error.
    #[test]
    fn packing_keeps_interior_nodes_with_their_childrens_boxes() {
        let b = |lo: f32, hi: f32| ([lo; 3], [hi; 3]);
        let node = |(bounds_min, bounds_max): ([f32; 3], [f32; 3]), left_or_first, count| TreeNode {
            bounds_min,
            left_or_first,
            bounds_max,
            count,
        };
        // 0 → (1, 2); 1 → (3, 4); leaves 2, 3, 4.
        let tree = [
            node(b(0.0, 4.0), 1, 0),
            node(b(0.0, 2.0), 3, 0),
            node(b(3.0, 4.0), 4, 1),
            node(b(0.0, 1.0), 0, 2),
            node(b(1.0, 2.0), 2, 2),
        ];
        let packed = pack(&tree).expect("small leaves");
        assert_eq!(packed.len(), 2);
        assert_eq!(packed[0].child(0), (b(0.0, 2.0).0, b(0.0, 2.0).1, ChildRef::interior(1)));
        assert_eq!(packed[0].child(1), (b(3.0, 4.0).0, b(3.0, 4.0).1, ChildRef::leaf(4, 1)));
        assert_eq!(packed[1].child(0).2.triangles(), 0..2);
        assert_eq!(packed[1].child(1).2.triangles(), 2..4);
        let big = [node(b(0.0, 1.0), 0, MAX_LEAF_TRIANGLES + 1)];
        assert!(matches!(pack(&big), Err(AccelError::LeafTooLarge(17))));
    }
}
