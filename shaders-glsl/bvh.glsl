// The BVH crates/accel builds on the CPU, as the compute trace backend reads it
// (trace_compute.glsl) and as the photon clearance pass searches it (photon_clearance.comp).
// Rust twins: BvhNode and BvhTriangle in crates/accel/src/bvh.rs (checked by reflection).
#ifndef LEAKLESS_BVH_GLSL
#define LEAKLESS_BVH_GLSL

#include "offset.glsl"

// count == 0: interior node, children left_or_first and left_or_first + 1; count > 0: a leaf
// with triangles left_or_first .. left_or_first + count - 1. The root is node 0.
struct BvhNode {
    vec3 bounds_min;
    uint left_or_first;
    vec3 bounds_max;
    uint count;
};

// Raw vertices, since the watertight test needs them, and the original scene triangle index,
// which is what a Hit reports (triangles are stored in BVH order).
struct BvhTriangle {
    vec3 v0;
    uint triangle;
    vec3 v1;
    uint pad0;
    vec3 v2;
    uint pad1;
};

layout(set = 0, binding = TRACE_BINDING, std430) readonly buffer BvhNodes {
    BvhNode nodes[];
} bvh_nodes;

layout(set = 0, binding = TRACE_BINDING + 1, std430) readonly buffer BvhTriangles {
    BvhTriangle triangles[];
} bvh_triangles;

#endif
