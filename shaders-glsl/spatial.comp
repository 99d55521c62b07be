#version 460
// Spatial reuse (docs/architecture.md §1, "Motion"): one iteration of an edge-aware à-trous
// filter (a 5×5 B3-spline kernel whose taps are `step` pixels apart) over the demodulated
// indirect irradiance of a moving frame. A tap counts only on the same surface as the pixel:
// facing the same way, and within a slope-aware distance of the pixel's plane. Two rules keep
// the filter from carrying light across geometry that the gather kept apart:
// * a pixel whose estimate is exactly zero stays exactly zero (a sealed room, a shadowed
//   region no photon reached: their zero is exact, and no neighbour's light may replace it);
// * taps on other planes or facing away are skipped, so the lit top of a thin slab gives
//   nothing to its unlit underside.
// The temporal pass weighs the result by the pixel's history (weaker as history grows), and
// still frames are never filtered, so the still view converges as accumulation alone does.
#include "common.glsl"
#include "gbuffer.glsl"
#include "reuse.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

FRAME_BLOCK(0);
GBUFFER_BINDINGS(1)
layout(set = 1, binding = 4, rgba32f) uniform readonly image2D indirect;  // first iteration's input
layout(set = 1, binding = 5, rgba32f) uniform readonly image2D source;    // later iterations' input
layout(set = 1, binding = 6, rgba32f) uniform writeonly image2D filtered;

layout(push_constant) uniform SpatialParams {
    int step;               // pixels between taps
    uint first;             // 1: read the frame's indirect layer and demodulate it
    float plane_tolerance;  // a tap's distance from the pixel's plane, per metre of view distance
    float kernel_pixels;    // the gather kernel's radius in pixels, one metre from the camera
} params;

vec3 irradiance(ivec2 q) {
    if (params.first != 0u) {
        return demodulate(imageLoad(indirect, q).rgb, imageLoad(gbuffer_albedo, q).rgb);
    }
    return imageLoad(source, q).rgb;
}

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = ivec2(frame.width, frame.height);
    if (pixel.x >= size.x || pixel.y >= size.y) {
        return;
    }
    vec4 surface = imageLoad(gbuffer_position, pixel);
    vec3 e = irradiance(pixel);
    float distance = length(surface.xyz - frame.camera_position.xyz);
    // Beyond the kernel's projected radius the noise is its blotches, which the history
    // averages: a later iteration that would reach further passes the pixel through, as it
    // does a pixel without a surface or with an exact zero.
    bool beyond_kernel =
        params.first == 0u && 2.0 * float(params.step) > projected_kernel(params.kernel_pixels, distance);
    if (surface.w == 0.0 || all(equal(e, vec3(0.0))) || beyond_kernel) {
        imageStore(filtered, pixel, vec4(e, 1.0));
        return;
    }
    vec3 n = imageLoad(gbuffer_normal, pixel).xyz;
    float tolerance = params.plane_tolerance * distance;
    const float kernel[3] = float[3](3.0 / 8.0, 1.0 / 4.0, 1.0 / 16.0);
    vec3 sum = vec3(0.0);
    float weight = 0.0;
    for (int y = -2; y <= 2; y++) {
        for (int x = -2; x <= 2; x++) {
            ivec2 q = pixel + params.step * ivec2(x, y);
            if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) {
                continue;
            }
            vec4 s = imageLoad(gbuffer_position, q);
            if (s.w == 0.0 || dot(imageLoad(gbuffer_normal, q).xyz, n) < 0.9
                || abs(dot(n, s.xyz - surface.xyz)) > tolerance) {
                continue;
            }
            float w = kernel[abs(x)] * kernel[abs(y)];
            sum += w * irradiance(q);
            weight += w;
        }
    }
    // The pixel itself always counts, so weight > 0.
    imageStore(filtered, pixel, vec4(sum / weight, 1.0));
}
