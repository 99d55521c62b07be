#version 460
// G-buffer, vertex stage: scene vertices are already in world space.
#include "common.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec2 in_uv;

FRAME_BLOCK(0);

layout(location = 0) out vec3 out_position;
layout(location = 1) out vec3 out_normal;
layout(location = 2) out vec2 out_uv;
// Vertices are an unindexed triangle list, so the triangle index is gl_VertexIndex / 3; passing
// it flat avoids gl_PrimitiveID, which needs the geometry-shader feature in fragment shaders.
layout(location = 3) flat out uint out_triangle;

void main() {
    out_position = in_position;
    out_normal = in_normal;
    out_uv = in_uv;
    out_triangle = uint(gl_VertexIndex) / 3u;
    gl_Position = frame.view_proj * vec4(in_position, 1.0);
}
