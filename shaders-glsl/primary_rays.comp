#version 460
// Primary visibility by ray casting: the G-buffer (world position and triangle, viewer-facing
// shading normal, albedo of the nearest surface) that gbuffer.vert + gbuffer.frag rasterise,
// from one closest-hit ray per pixel through its centre. `--primary` chooses, `auto` per device
// (docs/architecture.md §1.1): a CPU driver rasterises a large scene slowly whatever the image
// size (the basilica's 210k triangles), and a ray per pixel costs in proportion to the pixels.
// The surface and its attributes follow gbuffer.frag's: the same triangle, interpolated at the
// ray's hit, an alpha-masked surface cut away where the raster discards it (trace_alpha_pass).
#include "trace.glsl"
#include "common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

FRAME_BLOCK(0);
layout(set = 1, binding = 1, rgba32f) uniform writeonly image2D gbuffer_position;
layout(set = 1, binding = 2, rgba32f) uniform writeonly image2D gbuffer_normal;
layout(set = 1, binding = 3, rgba32f) uniform writeonly image2D gbuffer_albedo;
layout(push_constant) uniform PrimaryRaysParams {
    mat4 world_from_clip;  // the inverse of frame.view_proj
    uint finite_far;       // 1: the projection has a far plane (depth 0), beyond which nothing is seen
    uint pad0;
    uint pad1;
    uint pad2;
} params;

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (pixel.x >= int(frame.width) || pixel.y >= int(frame.height)) {
        return;
    }
    // The pixel's centre on the near plane (depth 1: the projection is reverse-Z), where the
    // raster's view volume begins.
    vec2 ndc = (vec2(pixel) + 0.5) / vec2(frame.width, frame.height) * 2.0 - 1.0;
    vec4 near = params.world_from_clip * vec4(ndc, 1.0, 1.0);
    vec3 origin = near.xyz / near.w;
    vec3 dir = normalize(origin - frame.camera_position.xyz);
    float tmax = 1e30;
    if (params.finite_far != 0u) {
        vec4 far = params.world_from_clip * vec4(ndc, 0.0, 1.0);
        tmax = distance(origin, far.xyz / far.w);
    }
    Hit hit = traceClosest(origin, dir, 0.0, tmax);
    if (hit.triangle == NO_HIT) {
        imageStore(gbuffer_position, pixel, vec4(0.0));
        imageStore(gbuffer_normal, pixel, vec4(0.0));
        imageStore(gbuffer_albedo, pixel, vec4(0.0));
        return;
    }
    vec3 p = triangle_position(hit.triangle, hit.barycentrics);
    vec3 n = triangle_shading_normal(hit.triangle, hit.barycentrics);
    if (dot(n, frame.camera_position.xyz - p) < 0.0) {
        n = -n;
    }
    vec4 albedo = material_albedo(triangle_material(hit.triangle), triangle_uv(hit.triangle, hit.barycentrics));
    imageStore(gbuffer_position, pixel, vec4(p, float(hit.triangle + 1u)));
    imageStore(gbuffer_normal, pixel, vec4(n, 0.0));
    imageStore(gbuffer_albedo, pixel, vec4(albedo.rgb, 1.0));
}
