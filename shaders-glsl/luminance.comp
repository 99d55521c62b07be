#version 460
// Luminance statistics of a frame, first stage: each 16×16 tile sums, over its pixels, the
// log of the displayed value (pixels above 1e-6 only) and their count, which give the
// automatic exposure, and the luminance of the indirect and leaked layers, which give the
// leaked energy fraction. A fixed reduction order keeps the result identical run to run.
#include "display.glsl"

layout(local_size_x = 16, local_size_y = 16) in;

layout(set = 1, binding = 0, rgba32f) uniform readonly image2D displayed;
layout(set = 1, binding = 1, rgba32f) uniform readonly image2D indirect;
layout(set = 1, binding = 2, rgba32f) uniform readonly image2D leaked;
layout(set = 1, binding = 3, std430) writeonly buffer Partials { vec4 sums[]; } partials;
layout(push_constant) uniform LuminanceParams {
    uint mode;  // DISPLAY_*
    uint width;
    uint height;
    uint tiles_x;
} params;

#define WORKGROUP_SUM_SIZE 256u
#include "workgroup_sum.glsl"

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    vec4 sums = vec4(0.0);
    if (pixel.x < int(params.width) && pixel.y < int(params.height)) {
        float v = display_value(params.mode, imageLoad(displayed, pixel));
        if (!isnan(v) && !isinf(v) && v > 1e-6) {
            sums.xy = vec2(log(v), 1.0);
        }
        sums.z = luminance(imageLoad(indirect, pixel).rgb);
        sums.w = luminance(imageLoad(leaked, pixel).rgb);
    }
    vec4 total = workgroup_sum(sums);
    if (gl_LocalInvocationIndex == 0u) {
        partials.sums[gl_WorkGroupID.y * params.tiles_x + gl_WorkGroupID.x] = total;
    }
}
