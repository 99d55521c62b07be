#version 460
// Progressive accumulation of photon frames (docs/architecture.md §1): adds this frame's
// direct, indirect and leaked layers to running sums kept from frame to frame, and writes
// their means, which are the image. The direct layer is one estimate per frame. The photon
// layers weigh `batches` (a frame traces that many batches of photons at one radius) times
// the pixel's visible-disk mass m (the indirect layer's .a; 1 without the visible disk): the
// indirect mean is Σ w·m·(flux/m) / Σ w·m, the flux summed over frames divided by the mass
// summed over them. A mean of per-frame ratios would keep E[1/m̂] > 1/m, a bias that
// accumulating never removes, and each frame's noise in m̂; the ratio of sums converges. The
// first frame of an accumulation overwrites the sums, so a reset needs no clear, and its
// means are the frame itself, bit for bit.
#include "common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

FRAME_BLOCK(0);
layout(set = 1, binding = 1, rgba32f) uniform readonly image2D direct;
layout(set = 1, binding = 2, rgba32f) uniform readonly image2D indirect;
layout(set = 1, binding = 3, rgba32f) uniform readonly image2D leaked;
layout(set = 1, binding = 4, rgba32f) uniform image2D sum_direct;
layout(set = 1, binding = 5, rgba32f) uniform image2D sum_indirect;
layout(set = 1, binding = 6, rgba32f) uniform image2D sum_leaked;
layout(set = 1, binding = 7, rgba32f) uniform writeonly image2D mean_direct;
layout(set = 1, binding = 8, rgba32f) uniform writeonly image2D mean_indirect;
layout(set = 1, binding = 9, rgba32f) uniform writeonly image2D mean_leaked;
layout(set = 1, binding = 10, rgba32f) uniform writeonly image2D mean_radiance;
layout(push_constant) uniform AccumulateParams {
    uint first;         // 1: this frame starts the sums
    float inv_frames;   // 1 / frames in the sums after this one
    float batches;      // photon batches this frame traced: its photon layers' weight
    float inv_batches;  // 1 / photon batches in the sums after this one
} params;

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (pixel.x >= int(frame.width) || pixel.y >= int(frame.height)) {
        return;
    }
    vec3 d = imageLoad(direct, pixel).rgb;
    vec4 frame_indirect = imageLoad(indirect, pixel);
    vec3 frame_leaked = imageLoad(leaked, pixel).rgb;
    if (params.first != 0u) {
        imageStore(sum_direct, pixel, vec4(d, 1.0));
        imageStore(sum_indirect, pixel, vec4(frame_indirect.rgb * frame_indirect.a, frame_indirect.a));
        imageStore(sum_leaked, pixel, vec4(frame_leaked, 1.0));
        imageStore(mean_direct, pixel, vec4(d, 1.0));
        imageStore(mean_indirect, pixel, vec4(frame_indirect.rgb, 1.0));
        imageStore(mean_leaked, pixel, vec4(frame_leaked, 1.0));
        imageStore(mean_radiance, pixel, vec4(d + frame_indirect.rgb, 1.0));
        return;
    }
    float w = params.batches * frame_indirect.a;
    d += imageLoad(sum_direct, pixel).rgb;
    vec4 i = imageLoad(sum_indirect, pixel) + vec4(frame_indirect.rgb * w, w);
    vec3 l = imageLoad(sum_leaked, pixel).rgb + frame_leaked * params.batches;
    imageStore(sum_direct, pixel, vec4(d, 1.0));
    imageStore(sum_indirect, pixel, i);
    imageStore(sum_leaked, pixel, vec4(l, 1.0));
    vec3 md = d * params.inv_frames;
    vec3 mi = i.a > 0.0 ? i.rgb / i.a : vec3(0.0);
    imageStore(mean_direct, pixel, vec4(md, 1.0));
    imageStore(mean_indirect, pixel, vec4(mi, 1.0));
    imageStore(mean_leaked, pixel, vec4(l * params.inv_batches, 1.0));
    imageStore(mean_radiance, pixel, vec4(md + mi, 1.0));
}
