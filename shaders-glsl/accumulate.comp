#version 460
// Progressive accumulation of photon frames (docs/architecture.md §1): adds this frame's
// direct, indirect and leaked layers to running sums kept from frame to frame, and writes
// their means, which are the image. The direct layer is one estimate per frame; the photon
// layers are `batches` estimates (a frame traces that many batches of photons at one radius),
// so they weigh that much in their mean. The first frame of an accumulation overwrites the
// sums, so a reset needs no clear, and its means equal the frame itself bit for bit
// (x · 1.0 = x: a first frame is one batch).
#include "common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

FRAME_BLOCK(0);
layout(set = 0, binding = 1, rgba32f) uniform readonly image2D direct;
layout(set = 0, binding = 2, rgba32f) uniform readonly image2D indirect;
layout(set = 0, binding = 3, rgba32f) uniform readonly image2D leaked;
layout(set = 0, binding = 4, rgba32f) uniform image2D sum_direct;
layout(set = 0, binding = 5, rgba32f) uniform image2D sum_indirect;
layout(set = 0, binding = 6, rgba32f) uniform image2D sum_leaked;
layout(set = 0, binding = 7, rgba32f) uniform writeonly image2D mean_direct;
layout(set = 0, binding = 8, rgba32f) uniform writeonly image2D mean_indirect;
layout(set = 0, binding = 9, rgba32f) uniform writeonly image2D mean_leaked;
layout(set = 0, binding = 10, rgba32f) uniform writeonly image2D mean_radiance;
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
    vec3 i = imageLoad(indirect, pixel).rgb * params.batches;
    vec3 l = imageLoad(leaked, pixel).rgb * params.batches;
    if (params.first == 0u) {
        d += imageLoad(sum_direct, pixel).rgb;
        i += imageLoad(sum_indirect, pixel).rgb;
        l += imageLoad(sum_leaked, pixel).rgb;
    }
    imageStore(sum_direct, pixel, vec4(d, 1.0));
    imageStore(sum_indirect, pixel, vec4(i, 1.0));
    imageStore(sum_leaked, pixel, vec4(l, 1.0));
    vec3 md = d * params.inv_frames;
    vec3 mi = i * params.inv_batches;
    imageStore(mean_direct, pixel, vec4(md, 1.0));
    imageStore(mean_indirect, pixel, vec4(mi, 1.0));
    imageStore(mean_leaked, pixel, vec4(l * params.inv_batches, 1.0));
    imageStore(mean_radiance, pixel, vec4(md + mi, 1.0));
}
