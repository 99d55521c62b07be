#version 460
// The image's lighting level (docs/architecture.md §1, "Motion"): how far the history lags the
// light, over the whole image, for what temporal.comp shows next frame.
//
// Why: a neighbourhood tells a change of the light from a frame's noise only when it stands
// out by a few deviations of that noise, and a photon frame's noise over a few kernels is
// tens of percent. A light that moves slowly (the moving light's indirect light grows about 1%
// a frame) stays below that everywhere, and a history of n frames lags such a ramp by about
// n − 1 frames of it: 7% dark at the moving light's last frame. Over the whole image the
// frame's noise is a few percent, and the ratio of the new estimates to the histories they are
// blended with measures the lag.
//
// How: temporal.comp sums, per workgroup, the luminance of each pixel's new estimate and of
// its reprojected history; this sums the workgroups and keeps a short mean of their ratio and
// of its spread (`most_frames`). Where that mean stands out from 1 by more than `sigmas`
// deviations of itself, the factor is the mean (in proportion between `sigmas` and twice that);
// otherwise 1. temporal.comp scales the history it shows by the factor, not the one it keeps:
// a correction fed back into the history rings (the loop's determinant is 1 − 1/n whatever
// the gain), and here the kept history is a plain running mean whose lag the ratio measures.
// A frame that does not move (or starts anew) resets the level to 1.

layout(local_size_x = 256) in;

layout(set = 1, binding = 0, std430) readonly buffer LevelPartials { vec4 sums[]; } level_partials;
// .r the factor, .g the ratio's short mean, .b the spread (mean square deviation) of a frame's
// ratio, .a the frames the mean holds.
layout(set = 1, binding = 1, rgba32f) uniform readonly image2D level_previous;
layout(set = 1, binding = 2, rgba32f) uniform writeonly image2D level_current;
layout(push_constant) uniform LevelParams {
    uint groups;        // temporal.comp's workgroups
    uint measure;       // 1: a moving frame with last frame's level; 0: reset
    float most_frames;  // frames the ratio's mean holds at most
    float sigmas;       // how many of its deviations the mean must stand out by
} params;

// Fewer pixels with a history than this measure nothing.
const float MIN_PIXELS = 64.0;

#define WORKGROUP_SUM_SIZE 256u
#include "workgroup_sum.glsl"

void main() {
    uint i = gl_LocalInvocationIndex;
    vec4 sum = vec4(0.0);
    for (uint g = i; g < params.groups; g += WORKGROUP_SUM_SIZE) {
        sum.xyz += level_partials.sums[g].xyz;
    }
    vec3 total = workgroup_sum(sum).xyz;
    if (i != 0u) {
        return;
    }
    vec4 level = vec4(1.0, 1.0, 0.0, 0.0);
    if (params.measure != 0u && total.z >= MIN_PIXELS && total.y > 0.0) {
        vec4 before = imageLoad(level_previous, ivec2(0));
        float ratio = total.x / total.y;
        float frames = min(before.a + 1.0, params.most_frames);
        float weight = 1.0 / frames;
        float mean = mix(before.g, ratio, weight);
        float spread = mix(before.b, (ratio - before.g) * (ratio - before.g), weight);
        // The deviation of a running mean of independent ratios: √(w / (2 − w)) of one's.
        float tolerance = params.sigmas * sqrt(spread * weight / (2.0 - weight));
        float beyond = tolerance > 0.0 ? clamp((abs(mean - 1.0) - tolerance) / tolerance, 0.0, 1.0) : 0.0;
        level = vec4(1.0 + beyond * (mean - 1.0), mean, spread, frames);
    }
    imageStore(level_current, ivec2(0), level);
}
