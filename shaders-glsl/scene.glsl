// The scene's buffers, for shaders that look up surfaces by triangle index (G-buffer
// materials, alpha tests during tracing, photon and path hits). Names are what passes bind.
#ifndef LEAKLESS_SCENE_GLSL
#define LEAKLESS_SCENE_GLSL
#include "common.glsl"
#include "device_address.glsl"
#include "frame_set.glsl"

// The corners of the triangles, three per triangle in world space (leakless_scene::Vertex),
// one buffer per attribute: 36 bytes a triangle in the largest, so that a 3M-triangle scene
// fits lavapipe's 128 MiB maxStorageBufferRange (one 96-byte buffer held 1.4M).
layout(set = FRAME_SET, binding = BINDING_VERTEX_POSITIONS, std430) readonly buffer VertexPositions { float xyz[]; } vertex_positions;
layout(set = FRAME_SET, binding = BINDING_VERTEX_NORMALS, std430) readonly buffer VertexNormals { float xyz[]; } vertex_normals;
layout(set = FRAME_SET, binding = BINDING_VERTEX_UVS, std430) readonly buffer VertexUvs { float uv[]; } vertex_uvs;
layout(set = FRAME_SET, binding = BINDING_TRIANGLE_MATERIALS, std430) readonly buffer TriangleMaterials { uint ids[]; } triangle_materials;
layout(set = FRAME_SET, binding = BINDING_MATERIALS, std430) readonly buffer Materials { Material materials[]; } materials;
layout(set = FRAME_SET, binding = BINDING_TEXELS, std430) readonly buffer Texels { uint words[]; } texels;

// The same buffers' device addresses: the shaders read the surfaces through them
// (device_address.glsl); the bindings above are what reflection checks and what orders passes
// after the instance vertices are written.
layout(set = FRAME_SET, binding = BINDING_SCENE_ADDRESSES) uniform SceneAddresses {
    uvec2 positions;
    uvec2 normals;
    uvec2 uvs;
    uvec2 triangle_materials;
    uvec2 materials;
    uvec2 texels;
} scene_addresses;

#ifdef LEAKLESS_REFLECTION
#define SCENE_POSITION(I) vertex_positions.xyz[I]
#define SCENE_NORMAL(I) vertex_normals.xyz[I]
#define SCENE_UV(I) vertex_uvs.uv[I]
#define SCENE_TRIANGLE_MATERIAL(I) triangle_materials.ids[I]
#define SCENE_MATERIAL(I) materials.materials[I]
#define SCENE_TEXEL(I) texels.words[I]
#else
ARRAY_AT(SceneFloatsAt, float, 4);
ARRAY_AT(SceneWordsAt, uint, 4);
ARRAY_AT(SceneMaterialsAt, Material, 16);
#define SCENE_POSITION(I) SceneFloatsAt(scene_addresses.positions).values[I]
#define SCENE_NORMAL(I) SceneFloatsAt(scene_addresses.normals).values[I]
#define SCENE_UV(I) SceneFloatsAt(scene_addresses.uvs).values[I]
#define SCENE_TRIANGLE_MATERIAL(I) SceneWordsAt(scene_addresses.triangle_materials).values[I]
#define SCENE_MATERIAL(I) SceneMaterialsAt(scene_addresses.materials).values[I]
#define SCENE_TEXEL(I) SceneWordsAt(scene_addresses.texels).values[I]
#endif

#include "material.glsl"

vec3 vertex_position(uint v) {
    return vec3(SCENE_POSITION(3u * v), SCENE_POSITION(3u * v + 1u), SCENE_POSITION(3u * v + 2u));
}

vec3 vertex_normal(uint v) {
    return vec3(SCENE_NORMAL(3u * v), SCENE_NORMAL(3u * v + 1u), SCENE_NORMAL(3u * v + 2u));
}

vec2 vertex_uv(uint v) {
    return vec2(SCENE_UV(2u * v), SCENE_UV(2u * v + 1u));
}

// Barycentric interpolation with the ray-query convention: p = (1-u-v) v0 + u v1 + v v2.
vec3 bary_weights(vec2 b) {
    return vec3(1.0 - b.x - b.y, b.x, b.y);
}

vec2 triangle_uv(uint triangle, vec2 b) {
    vec3 w = bary_weights(b);
    return w.x * vertex_uv(3u * triangle) + w.y * vertex_uv(3u * triangle + 1u) + w.z * vertex_uv(3u * triangle + 2u);
}

vec3 triangle_position(uint triangle, vec2 b) {
    vec3 w = bary_weights(b);
    return w.x * vertex_position(3u * triangle) + w.y * vertex_position(3u * triangle + 1u) + w.z * vertex_position(3u * triangle + 2u);
}

vec3 triangle_shading_normal(uint triangle, vec2 b) {
    vec3 w = bary_weights(b);
    vec3 n = w.x * vertex_normal(3u * triangle) + w.y * vertex_normal(3u * triangle + 1u) + w.z * vertex_normal(3u * triangle + 2u);
    return normalize(n);
}

// Unit normal of the triangle's plane (orientation from the winding; callers orient it).
vec3 triangle_geometric_normal(uint triangle) {
    vec3 v0 = vertex_position(3u * triangle);
    return normalize(cross(vertex_position(3u * triangle + 1u) - v0, vertex_position(3u * triangle + 2u) - v0));
}

Material triangle_material(uint triangle) {
    return SCENE_MATERIAL(SCENE_TRIANGLE_MATERIAL(triangle));
}

#endif
