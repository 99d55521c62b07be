#version 460
// Final image: radiance = direct + indirect, where the indirect layer is a running sum scaled
// by `indirect_scale` (1/spp for the reference; 0 when the method has no indirect light), and
// zero leaked and gather-count layers for methods that do not gather photons.
#include "common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

FRAME_BLOCK(0);
layout(set = 1, binding = 1, rgba32f) uniform readonly image2D direct;
layout(set = 1, binding = 2, rgba32f) uniform readonly image2D indirect_sum;
layout(set = 1, binding = 3, rgba32f) uniform writeonly image2D indirect;
layout(set = 1, binding = 4, rgba32f) uniform writeonly image2D radiance;
layout(push_constant) uniform ComposeParams {
    float indirect_scale;
    uint gathered;  // 0: no gather wrote the leaked and count layers this frame; they become zero
    uint pad1;
    uint pad2;
} params;
layout(set = 1, binding = 5, rgba32f) uniform writeonly image2D leaked;
layout(set = 1, binding = 6, rgba32f) uniform writeonly image2D gather_counts;

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (pixel.x >= int(frame.width) || pixel.y >= int(frame.height)) {
        return;
    }
    // Never read the sum when it is not used: its content is then undefined.
    vec4 sum = params.indirect_scale == 0.0 ? vec4(0.0, 0.0, 0.0, 1.0) : imageLoad(indirect_sum, pixel);
    vec3 l_indirect = sum.rgb * params.indirect_scale;
    vec3 l_direct = imageLoad(direct, pixel).rgb;
    // .a: the gather's visible-disk mass, which accumulation weighs the frame by (1 otherwise).
    imageStore(indirect, pixel, vec4(l_indirect, params.gathered != 0u ? sum.a : 1.0));
    imageStore(radiance, pixel, vec4(l_direct + l_indirect, 1.0));
    if (params.gathered == 0u) {
        imageStore(leaked, pixel, vec4(0.0));
        imageStore(gather_counts, pixel, vec4(0.0));
    }
}
