// The two-level BVH crates/accel builds on the CPU, as the compute trace backend reads it
// (trace_compute.glsl) and as the photon clearance pass searches it (photon_clearance.comp).
// Rust twins: BvhNode and BvhTriangle in crates/accel/src/bvh.rs, BvhInstance in
// crates/accel/src/instanced.rs (checked by reflection).
//
// Bottom level (built once): every part's BVH in bvh_nodes / bvh_triangles, the static part in
// world space, each animated instance in its mesh space. Top level (uploaded every frame):
// bvh_top over the parts' world boxes, one part per leaf (left_or_first = part index), and
// bvh_instances, per part, the map from world into its space and its bottom-level root.
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

// Raw vertices (in the part's space), since the watertight test needs them, and the original
// scene triangle index, which is what a Hit reports (triangles are stored in BVH order). Packed
// in 40 bytes (float[3], not vec3, which std430 aligns to 16): a 3M-triangle scene's fit
// lavapipe's 128 MiB storage-buffer range.
struct BvhTriangle {
    float v0[3];
    uint triangle;
    float v1[3];
    float v2[3];
};

vec3 bvh_vertex(float v[3]) {
    return vec3(v[0], v[1], v[2]);
}

layout(set = 0, binding = TRACE_BINDING, std430) readonly buffer BvhNodes {
    BvhNode nodes[];
} bvh_nodes;

layout(set = 0, binding = TRACE_BINDING + 1, std430) readonly buffer BvhTriangles {
    BvhTriangle triangles[];
} bvh_triangles;

// identity != 0: the static part, traced in world space as is.
struct BvhInstance {
    vec4 local_from_world0;
    vec4 local_from_world1;
    vec4 local_from_world2;
    uint root;
    uint identity;
    uint pad0;
    uint pad1;
};

// The top level's nodes at TRACE_BINDING + 2; the scene's bindings (scene.glsl) follow at 20-23.
layout(set = 0, binding = TRACE_BINDING + 2, std430) readonly buffer BvhTop {
    BvhNode nodes[];
} bvh_top;

layout(set = 0, binding = TRACE_BINDING + 8, std430) readonly buffer BvhInstances {
    BvhInstance items[];
} bvh_instances;

// The top level's traversal stack: median splits keep it ⌈log2 parts⌉ deep, at most
// BVH_TOP_MAX_DEPTH (crates/accel/src/instanced.rs).
#define BVH_TOP_STACK_SIZE 32

#endif
