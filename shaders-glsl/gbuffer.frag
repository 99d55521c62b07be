#version 460
// G-buffer, fragment stage: world position and triangle, viewer-facing shading normal and
// albedo of the nearest surface. Every surface is two-sided, so the normal is flipped toward
// the camera.
#include "common.glsl"
#include "scene.glsl"

FRAME_BLOCK(0);

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec2 in_uv;
layout(location = 3) flat in uint in_triangle;

layout(location = 0) out vec4 out_position;  // w = triangle + 1 (exact below 2^24), 0 = no surface
layout(location = 1) out vec4 out_normal;
layout(location = 2) out vec4 out_albedo;

void main() {
    Material m = triangle_material(in_triangle);
    vec4 albedo = material_albedo(m, in_uv);
    if (m.alpha_cutoff >= 0.0 && albedo.a < m.alpha_cutoff) {
        discard;
    }
    vec3 n = normalize(in_normal);
    vec3 to_eye = frame.camera_position.xyz - in_position;
    if (dot(n, to_eye) < 0.0) {
        n = -n;
    }
    out_position = vec4(in_position, float(in_triangle + 1u));
    out_normal = vec4(n, 0.0);
    out_albedo = vec4(albedo.rgb, 1.0);
}
