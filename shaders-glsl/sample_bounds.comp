#version 460
// Bounds of the valid view samples, for Morton quantisation: floats mapped to
// order-preserving uints, reduced over the workgroup in shared memory, then one atomic min/max
// per axis per workgroup (the buffer starts at min = ~0, max = 0).
//
// Why the reduction: an atomic per axis per sample made every sample of the frame contend for
// the same six words, which on lavapipe cost 62 ms of a 612 ms 640×480 atrium frame, more
// than the splat. A tree in shared memory needs no atomics (on CPU drivers each shared atomic
// is a locked instruction per lane, sort_histogram.comp) and leaves 64 times fewer global ones.
#include "common.glsl"
#include "gbuffer.glsl"

#define BOUNDS_THREADS 64u
layout(local_size_x = 8, local_size_y = 8) in;

FRAME_BLOCK(0);
GBUFFER_BINDINGS(1)
layout(set = 1, binding = 4, std430) buffer SampleBounds { uint min_key[3]; uint max_key[3]; } sample_bounds;

shared uvec3 s_min[BOUNDS_THREADS];
shared uvec3 s_max[BOUNDS_THREADS];

uint order_key(float f) {
    uint u = floatBitsToUint(f);
    return (u & 0x80000000u) != 0u ? ~u : (u | 0x80000000u);
}

void main() {
    // No early return: every thread reaches the barriers. A thread without a valid sample
    // brings the empty box.
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    uvec3 lo = uvec3(0xffffffffu);
    uvec3 hi = uvec3(0u);
    if (pixel.x < int(frame.width) && pixel.y < int(frame.height)) {
        vec4 p = imageLoad(gbuffer_position, pixel);
        if (p.w > 0.0) {
            lo = uvec3(order_key(p.x), order_key(p.y), order_key(p.z));
            hi = lo;
        }
    }
    uint t = gl_LocalInvocationIndex;
    s_min[t] = lo;
    s_max[t] = hi;
    barrier();
    for (uint stride = BOUNDS_THREADS / 2u; stride > 0u; stride >>= 1u) {
        if (t < stride) {
            s_min[t] = min(s_min[t], s_min[t + stride]);
            s_max[t] = max(s_max[t], s_max[t + stride]);
        }
        barrier();
    }
    // A workgroup with a valid sample has min ≤ max; an empty one has min = ~0 > max = 0.
    if (t == 0u && s_min[0].x <= s_max[0].x) {
        for (int axis = 0; axis < 3; ++axis) {
            atomicMin(sample_bounds.min_key[axis], s_min[0][axis]);
            atomicMax(sample_bounds.max_key[axis], s_max[0][axis]);
        }
    }
}
