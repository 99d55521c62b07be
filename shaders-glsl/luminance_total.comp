#version 460
// Luminance statistics of a frame, second stage: one workgroup sums the tiles' partial sums
// (each thread a fixed stride of them, then a tree), into
// (Σ log value, lit pixels, Σ indirect luminance, Σ leaked luminance).

layout(local_size_x = 256) in;

layout(set = 1, binding = 0, std430) readonly buffer Partials { vec4 sums[]; } partials;
layout(set = 1, binding = 1, std430) writeonly buffer LuminanceStats {
    float log_sum;
    float lit_pixels;
    float indirect_sum;
    float leaked_sum;
} stats;
layout(push_constant) uniform TotalParams {
    uint tiles;
    uint pad0;
    uint pad1;
    uint pad2;
} params;

#define WORKGROUP_SUM_SIZE 256u
#include "workgroup_sum.glsl"

void main() {
    uint i = gl_LocalInvocationIndex;
    vec4 sum = vec4(0.0);
    for (uint t = i; t < params.tiles; t += WORKGROUP_SUM_SIZE) {
        sum += partials.sums[t];
    }
    vec4 total = workgroup_sum(sum);
    if (i == 0u) {
        stats.log_sum = total.x;
        stats.lit_pixels = total.y;
        stats.indirect_sum = total.z;
        stats.leaked_sum = total.w;
    }
}
