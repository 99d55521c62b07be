#version 460
// G-buffer, vertex stage: scene vertices are already in world space. They are read from the
// scene's buffers by index (no vertex input): the corners' attributes live in one buffer each
// (scene.glsl), which every other pass reads by triangle too.
#include "common.glsl"
#include "scene.glsl"

FRAME_BLOCK(0);

layout(location = 0) out vec3 out_position;
layout(location = 1) out vec3 out_normal;
layout(location = 2) out vec2 out_uv;
// Vertices are an unindexed triangle list, so the triangle index is gl_VertexIndex / 3; passing
// it flat avoids gl_PrimitiveID, which needs the geometry-shader feature in fragment shaders.
layout(location = 3) flat out uint out_triangle;

void main() {
    uint v = uint(gl_VertexIndex);
    vec3 p = vertex_position(v);
    out_position = p;
    out_normal = vertex_normal(v);
    out_uv = vertex_uv(v);
    out_triangle = v / 3u;
    gl_Position = frame.view_proj * vec4(p, 1.0);
}
