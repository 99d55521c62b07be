#version 460
// Luminance statistics of a frame, second stage: one workgroup sums the tiles' partial sums
// (each thread a fixed stride of them, then a tree), into
// (Σ log value, lit pixels, Σ indirect luminance, Σ leaked luminance).

layout(local_size_x = 256) in;

layout(set = 0, binding = 0, std430) readonly buffer Partials { vec4 sums[]; } partials;
layout(set = 0, binding = 1, std430) writeonly buffer LuminanceStats {
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

shared vec4 partial[256];

void main() {
    uint i = gl_LocalInvocationIndex;
    vec4 sum = vec4(0.0);
    for (uint t = i; t < params.tiles; t += 256u) {
        sum += partials.sums[t];
    }
    partial[i] = sum;
    barrier();
    for (uint stride = 128u; stride > 0u; stride >>= 1u) {
        if (i < stride) {
            partial[i] += partial[i + stride];
        }
        barrier();
    }
    if (i == 0u) {
        stats.log_sum = partial[0].x;
        stats.lit_pixels = partial[0].y;
        stats.indirect_sum = partial[0].z;
        stats.leaked_sum = partial[0].w;
    }
}
