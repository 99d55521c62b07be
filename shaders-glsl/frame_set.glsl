// The frame set: descriptor set 0 of every pipeline, what a frame binds once at numbers every
// shader shares (crates/renderer/src/frame_set.rs declares the same; the bindings test checks
// every module). A pass's own bindings are in PASS_SET, numbered from 0 in each shader.
#ifndef LEAKLESS_FRAME_SET_GLSL
#define LEAKLESS_FRAME_SET_GLSL

#define FRAME_SET 0
#define PASS_SET 1

// scene.glsl
#define BINDING_VERTEX_POSITIONS 0
#define BINDING_VERTEX_NORMALS 1
#define BINDING_VERTEX_UVS 2
#define BINDING_TRIANGLE_MATERIALS 3
#define BINDING_MATERIALS 4
#define BINDING_TEXELS 5
#define BINDING_SCENE_ADDRESSES 6
// emitters.glsl
#define BINDING_EMITTERS 7
// trace.glsl (ray queries), offset.glsl
#define BINDING_TLAS 8
#define BINDING_TRACE_SCALE 9
// bvh.glsl
#define BINDING_BVH_NODES 10
#define BINDING_BVH_TRIANGLES 11
#define BINDING_BVH_TOP 12
#define BINDING_BVH_INSTANCES 13

#endif
