#version 460
// G-buffer, fragment stage: world position, viewer-facing shading normal and albedo of the
// nearest surface. Every surface is two-sided, so the normal is flipped toward the camera.
#include "common.glsl"

FRAME_BLOCK(0);
layout(set = 0, binding = 1, std430) readonly buffer Materials { Material materials[]; } materials;
layout(set = 0, binding = 2, std430) readonly buffer TriangleMaterials { uint ids[]; } triangle_materials;
layout(set = 0, binding = 3, std430) readonly buffer Texels { uint words[]; } texels;

#include "material.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec2 in_uv;
layout(location = 3) flat in uint in_triangle;

layout(location = 0) out vec4 out_position;  // w = 1 where a surface was hit
layout(location = 1) out vec4 out_normal;
layout(location = 2) out vec4 out_albedo;

void main() {
    Material m = materials.materials[triangle_materials.ids[in_triangle]];
    vec4 albedo = material_albedo(m, in_uv);
    if (m.alpha_cutoff >= 0.0 && albedo.a < m.alpha_cutoff) {
        discard;
    }
    vec3 n = normalize(in_normal);
    vec3 to_eye = frame.camera_position.xyz - in_position;
    if (dot(n, to_eye) < 0.0) {
        n = -n;
    }
    out_position = vec4(in_position, 1.0);
    out_normal = vec4(n, 0.0);
    out_albedo = vec4(albedo.rgb, 1.0);
}
