// The two-level BVH crates/accel builds on the CPU, as the compute trace backend reads it
// (trace_compute.glsl) and as the photon clearance pass searches it (photon_clearance.comp).
// Rust twins: BvhNode and BvhTriangle in crates/accel/src/bvh.rs, BvhInstance in
// crates/accel/src/instanced.rs (checked by reflection).
//
// Bottom level (built once): every part's BVH in bvh_nodes / bvh_triangles, the static part in
// world space, each animated instance in its mesh space. Top level (uploaded every frame):
// bvh_top over the parts' world boxes, one part per leaf (the leaf's one "triangle" is the
// part's index), and bvh_instances, per part, the map from world into its space and its
// bottom-level root.
#ifndef LEAKLESS_BVH_GLSL
#define LEAKLESS_BVH_GLSL

#include "device_address.glsl"
#include "offset.glsl"

// An interior node with its two children's boxes, so that a traversal step is one load
// (crates/accel/src/bvh/nodes.rs says why). child0 and child1 are child references: an interior
// node's index, or a leaf's triangles (bvh_is_leaf and below). The root is node 0, a part's root
// its BvhInstance's `root`; a tree that is one leaf has a root whose second child is empty.
struct BvhNode {
    vec3 min0;
    uint child0;
    vec3 max0;
    uint child1;
    vec3 min1;
    uint pad0;
    vec3 max1;
    uint pad1;
};

// A leaf reference is BVH_LEAF | (count - 1) << 27 | first: triangles first .. first + count - 1.
// None equals BVH_NO_CHILD, which is trace.glsl's NO_HIT (ChildRef in crates/accel/src/bvh/nodes.rs).
#define BVH_LEAF 0x80000000u
#define BVH_NO_CHILD 0xffffffffu
bool bvh_is_leaf(uint child) {
    return (child & BVH_LEAF) != 0u;
}
uint bvh_leaf_first(uint child) {
    return child & 0x7ffffffu;
}
uint bvh_leaf_count(uint child) {
    return ((child & ~BVH_LEAF) >> 27u) + 1u;
}

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

// The parts' bottom levels, every part's nodes in one array, and their triangles.
layout(set = FRAME_SET, binding = BINDING_BVH_NODES, std430) readonly buffer BvhNodes { BvhNode nodes[]; } bvh_nodes;
layout(set = FRAME_SET, binding = BINDING_BVH_TRIANGLES, std430) readonly buffer BvhTriangles { BvhTriangle triangles[]; } bvh_triangles;

// The traversals read them through their device addresses, which trace_scale holds
// (device_address.glsl); their indices come from the BVH itself, which crates/accel builds and
// tests.
#ifdef LEAKLESS_REFLECTION
#define BVH_NODE(I) bvh_nodes.nodes[I]
#define BVH_TRIANGLE(I) bvh_triangles.triangles[I]
#else
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
ARRAY_AT(BvhWordsAt, uint64_t, 8);
#define BVH_NODE(I) bvh_node(I)
#define BVH_TRIANGLE(I) bvh_triangle_at(I)
// Nodes and triangles are read as 64-bit words: lavapipe gathers a struct across its lanes one
// 32-bit member word at a time (fourteen gathers a node, ten a triangle), and a 64-bit word in
// one (eight, five). A GPU reads the same bytes either way. Only the words of the fields a
// caller uses are loaded: the others' loads are dead code. The words are the std430 layouts
// above, which reflection checks against their Rust twins.

// Four 32-bit words from two 64-bit ones, the first at 64-bit word i of the buffer at `address`.
uvec4 bvh_words(uvec2 address, uint i) {
    BvhWordsAt words = BvhWordsAt(address);
    return uvec4(unpack32(words.values[i]), unpack32(words.values[i + 1u]));
}
BvhNode bvh_node(uint i) {
    uvec4 q0 = bvh_words(trace_scale.bvh_nodes_address, 8u * i);
    uvec4 q1 = bvh_words(trace_scale.bvh_nodes_address, 8u * i + 2u);
    uvec4 q2 = bvh_words(trace_scale.bvh_nodes_address, 8u * i + 4u);
    uvec4 q3 = bvh_words(trace_scale.bvh_nodes_address, 8u * i + 6u);
    return BvhNode(uintBitsToFloat(q0.xyz), q0.w, uintBitsToFloat(q1.xyz), q1.w, uintBitsToFloat(q2.xyz), 0u,
                   uintBitsToFloat(q3.xyz), 0u);
}
// Triangle i's 40 bytes (its stride keeps every triangle 8-byte aligned): v0 and the scene
// triangle, v1 and v2's x, v2's y and z.
BvhTriangle bvh_triangle_at(uint i) {
    uvec4 a = bvh_words(trace_scale.bvh_triangles_address, 5u * i);
    uvec4 b = bvh_words(trace_scale.bvh_triangles_address, 5u * i + 2u);
    uvec2 c = unpack32(BvhWordsAt(trace_scale.bvh_triangles_address).values[5u * i + 4u]);
    vec3 v0 = uintBitsToFloat(a.xyz);
    vec3 v1 = uintBitsToFloat(b.xyz);
    vec3 v2 = uintBitsToFloat(uvec3(b.w, c));
    return BvhTriangle(float[3](v0.x, v0.y, v0.z), a.w, float[3](v1.x, v1.y, v1.z), float[3](v2.x, v2.y, v2.z));
}
#endif

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

// The top level over this frame's pose: its nodes, and each part's transform and root.
layout(set = FRAME_SET, binding = BINDING_BVH_TOP, std430) readonly buffer BvhTop { BvhNode nodes[]; } bvh_top;
layout(set = FRAME_SET, binding = BINDING_BVH_INSTANCES, std430) readonly buffer BvhInstances { BvhInstance items[]; } bvh_instances;

// The top level's traversal stack: median splits keep it ⌈log2 parts⌉ deep, at most
// BVH_TOP_MAX_DEPTH (crates/accel/src/instanced.rs).
#define BVH_TOP_STACK_SIZE 32

#endif
