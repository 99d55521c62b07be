// The scene's buffers, for shaders that look up surfaces by triangle index (G-buffer
// materials, alpha tests during tracing, photon and path hits). Names are what passes bind.
#ifndef LEAKLESS_SCENE_GLSL
#define LEAKLESS_SCENE_GLSL
#include "common.glsl"

#define SCENE_BINDING 20

// leakless_scene::Vertex: world-space position, shading normal, texcoord (32 bytes).
struct SceneVertex {
    float position[3];
    float normal[3];
    vec2 uv;
};

layout(set = 0, binding = SCENE_BINDING, std430) readonly buffer SceneVertices { SceneVertex vertices[]; } scene_vertices;
layout(set = 0, binding = SCENE_BINDING + 1, std430) readonly buffer TriangleMaterials { uint ids[]; } triangle_materials;
layout(set = 0, binding = SCENE_BINDING + 2, std430) readonly buffer Materials { Material materials[]; } materials;
layout(set = 0, binding = SCENE_BINDING + 3, std430) readonly buffer Texels { uint words[]; } texels;

#include "material.glsl"

vec3 vertex_position(uint v) {
    SceneVertex s = scene_vertices.vertices[v];
    return vec3(s.position[0], s.position[1], s.position[2]);
}

vec3 vertex_normal(uint v) {
    SceneVertex s = scene_vertices.vertices[v];
    return vec3(s.normal[0], s.normal[1], s.normal[2]);
}

// Barycentric interpolation with the ray-query convention: p = (1-u-v) v0 + u v1 + v v2.
vec3 bary_weights(vec2 b) {
    return vec3(1.0 - b.x - b.y, b.x, b.y);
}

vec2 triangle_uv(uint triangle, vec2 b) {
    vec3 w = bary_weights(b);
    return w.x * scene_vertices.vertices[3u * triangle].uv + w.y * scene_vertices.vertices[3u * triangle + 1u].uv
         + w.z * scene_vertices.vertices[3u * triangle + 2u].uv;
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
    return materials.materials[triangle_materials.ids[triangle]];
}

#endif
