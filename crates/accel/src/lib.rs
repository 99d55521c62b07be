//! Acceleration structures of leakless (docs/architecture.md §3 "Trace backends").
//!
//! * [`rayquery`]: the ray-query backend's BLASes (one per part: the static triangles, each
//!   animated instance) and TLAS, built on the device; the TLAS is rebuilt in the frame's graph
//!   when parts move.
//! * [`bvh`]: the compute-shader backend. A binary BVH built on the CPU over a flat triangle
//!   list and flattened into two storage buffers ([`BvhNode`]: an interior node with both
//!   children's boxes, [`BvhTriangle`]) that
//!   `shaders-glsl/trace_compute.glsl` traverses; [`Bvh::intersect`] is its exact CPU twin.
//! * [`instanced`]: the compute backend's two levels: one [`Bvh`] per part, concatenated, and
//!   a top level over the parts' world boxes rebuilt on the host when they move.

pub mod bvh;
pub mod instanced;
pub mod rayquery;

pub use bvh::{
    intersect_triangle, Bvh, BvhNode, BvhStats, BvhTriangle, Hit, Ray, RayQuery, BVH_MAX_DEPTH, BVH_NODE_LAYOUT,
    BVH_TRIANGLE_LAYOUT,
};
pub use instanced::{BvhInstance, InstancedBvh, PartInput, TopLevel, BVH_INSTANCE_LAYOUT, BVH_TOP_MAX_DEPTH};
pub use rayquery::{RayQueryAccel, RayQueryStats};

/// Why an acceleration structure could not be built; each variant prints as one line.
#[derive(Debug, thiserror::Error)]
pub enum AccelError {
    #[error(transparent)]
    Device(#[from] leakless_device::DeviceError),
    #[error("the scene has no triangles: there is nothing to trace rays against")]
    Empty,
    #[error("the triangle list has {0} vertices, which is not a multiple of 3")]
    NotTriangles(usize),
    #[error("none of the scene's {0} triangles has finite vertex positions: there is nothing to trace rays against")]
    NoFiniteTriangles(usize),
    #[error("the scene has {0} triangles; the compute BVH indexes at most {max}", max = bvh::MAX_TRIANGLES)]
    TooManyTriangles(usize),
    #[error("the scene has {0} static and animated parts; the compute BVH's top level holds at most {max}", max = instanced::MAX_PARTS)]
    TooManyParts(usize),
    #[error("a BVH leaf holds {0} triangles; a child reference counts at most {max}", max = bvh::MAX_LEAF_TRIANGLES)]
    LeafTooLarge(u32),
    #[error("the BVH is {depth} levels deep; the traversal stack holds {max} (BVH_STACK_SIZE in trace_compute.glsl)", max = BVH_MAX_DEPTH)]
    TooDeep { depth: u32 },
}
