#version 460
// Bounds of the valid view samples, for Morton quantisation: an atomic min/max per axis on
// floats mapped to order-preserving uints (the buffer starts at min = ~0, max = 0).
#include "common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

FRAME_BLOCK(0);
layout(set = 0, binding = 1, rgba32f) uniform readonly image2D gbuffer_position;
layout(set = 0, binding = 2, std430) buffer SampleBounds { uint min_key[3]; uint max_key[3]; } sample_bounds;

uint order_key(float f) {
    uint u = floatBitsToUint(f);
    return (u & 0x80000000u) != 0u ? ~u : (u | 0x80000000u);
}

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (pixel.x >= int(frame.width) || pixel.y >= int(frame.height)) {
        return;
    }
    vec4 p = imageLoad(gbuffer_position, pixel);
    if (p.w <= 0.0) {
        return;
    }
    for (int axis = 0; axis < 3; ++axis) {
        atomicMin(sample_bounds.min_key[axis], order_key(p[axis]));
        atomicMax(sample_bounds.max_key[axis], order_key(p[axis]));
    }
}
