#version 460
// Temporal reuse of the indirect light (docs/architecture.md §1, "Motion"). The history is
// demodulated irradiance (the indirect layer over albedo, so texture detail is never smeared)
// with the frames it holds in .a, and the surface each pixel saw (position and triangle,
// viewer-facing normal), in history pairs of the graph.
//
// MODE_RESTART: no history; the frame passes through and starts one.
// MODE_MOTION: the camera, a light or an instance moved, and this is the first frame of a new
//   accumulation. Each pixel's surface point is carried back to where it was last frame (the
//   same barycentric point of its triangle for animated instances), projected with last
//   frame's camera, and the history is read bilinearly from the taps that saw the same surface:
//   the same static geometry or the same animated triangle, within a slope-aware distance of
//   its plane, facing the same way. A pixel with no such tap starts anew. The history is
//   clamped to the new frame's pixel and its mean over a few kernels, widened by
//   `clamp_relative`: a photon frame's low-frequency noise is averaged out, a change of the
//   lighting is followed within a few frames. Where the new
//   frame's whole neighbourhood is exactly zero the output is exactly zero: a shut door or a
//   sealed room is black at once. Before the clamp, the history is scaled by how much the light
//   changed around the pixel (`lighting_change`): so a light that moves is followed at once
//   where the change stands out of a frame's noise, rather than over the history's frames
//   within the clamp's margin. Then new = lerp(history, frame, 1/n), n the frames the
//   pixel's history holds with this one, at most `max_history`. What is shown scales the
//   history by the image's lighting level too (lighting_level.comp: a light changing too
//   slowly for any neighbourhood to tell), where the neighbourhood saw no change itself; what
//   is kept does not, and each workgroup sums what the level measures.
// With `spatial`, a moving frame's own estimate is first filtered (spatial.comp). The filter
//   averages noise away but also blurs the light along a surface (towards a corner, beside a
//   shadow, a wall's colour towards the next), and that blur is a bias. The pixel keeps a long
//   mean of its filtered and of its own irradiance (`bias_frames`, a few times the history):
//   their ratio, per channel, is the filter's bias on that surface, and the filtered estimate
//   is divided by it. The new frame's estimate then has
//   the filtered estimate's noise (little, so the image hardly flickers) and, once the ratio is
//   known, the pixel's own mean. A ratio of fewer frames than a history holds is trusted in
//   proportion to them.
// MODE_STILL: nothing moved since the last motion frame, and the progressive accumulation
//   holds the frames since (`still_batches` photon batches). The history is carried unchanged,
//   and the image is their weighted mean, the history counting for the n - 1 frames it holds
//   before the accumulation's first: its weight falls as the accumulation grows, so the still
//   view converges to what accumulation alone converges to.
// The reprojection is in temporal_reproject.glsl, the clamp and the lighting change in
// temporal_clamp.glsl: one kernel, since two passes (the reprojection's results through four
// images) cost more on a CPU driver (docs/results.md, §1.17).
#include "common.glsl"
#include "gbuffer.glsl"
#include "reuse.glsl"
#include "scene.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

const uint MODE_RESTART = 0u;
const uint MODE_MOTION = 1u;
const uint MODE_STILL = 2u;

FRAME_BLOCK(0);
GBUFFER_BINDINGS(1)
layout(set = 1, binding = 4, rgba32f) uniform readonly image2D direct;
layout(set = 1, binding = 5, rgba32f) uniform readonly image2D indirect;
layout(set = 1, binding = 6, rgba32f) uniform readonly image2D history_previous;
layout(set = 1, binding = 7, rgba32f) uniform writeonly image2D history_current;
layout(set = 1, binding = 8, rgba32f) uniform readonly image2D surface_previous;
layout(set = 1, binding = 9, rgba32f) uniform writeonly image2D surface_current;
layout(set = 1, binding = 10, rgba32f) uniform readonly image2D normal_previous;
layout(set = 1, binding = 11, rgba32f) uniform writeonly image2D normal_current;
layout(set = 1, binding = 12, rgba32f) uniform writeonly image2D reused_indirect;
layout(set = 1, binding = 13, rgba32f) uniform writeonly image2D reused_radiance;
layout(set = 1, binding = 15, rgba32f) uniform readonly image2D radiance;
// The frame's irradiance after spatial reuse (read only when `spatial`).
layout(set = 1, binding = 16, rgba32f) uniform readonly image2D filtered;
// The long means of the filtered (.rgb, over .a frames) and of the own (.rgb) irradiance.
layout(set = 1, binding = 17, rgba32f) uniform readonly image2D filtered_mean_previous;
layout(set = 1, binding = 18, rgba32f) uniform writeonly image2D filtered_mean_current;
layout(set = 1, binding = 20, rgba32f) uniform readonly image2D own_mean_previous;
layout(set = 1, binding = 21, rgba32f) uniform writeonly image2D own_mean_current;
// The light's level (lighting_level.comp): .r the factor a moving frame's shown history is
// scaled by, measured over the frames before.
layout(set = 1, binding = 19, rgba32f) uniform readonly image2D level_previous;
// Per workgroup, Σ luminance of the new estimate and of the history it is blended with, over the
// pixels that have one (.xy), and their count (.z).
layout(set = 1, binding = 22, std430) writeonly buffer LevelPartials { vec4 sums[]; } level_partials;
// The animated instances' vertex positions as they were in the history's frame, from the first
// moving triangle's first vertex on (read only when `instances_moved`).
layout(set = 1, binding = 14, std430) readonly buffer PreviousPositions { float xyz[]; } previous_positions;

layout(push_constant) uniform TemporalParams {
    mat4 previous_view_proj;  // the history's frame's camera
    vec4 previous_camera;     // its position (.xyz)
    uint mode;
    float max_history;        // frames a history holds at most
    float still_batches;      // MODE_STILL: photon batches in the accumulation's mean
    uint first_moving_triangle;
    uint instances_moved;     // 1: previous_positions differ from the scene's vertices
    float clamp_relative;
    uint spatial;             // 1: `filtered` holds this frame's spatially reused irradiance
    float bias_frames;        // frames the filter's bias is measured over at most
    float kernel_pixels;      // the gather kernel's radius in pixels, one metre from the camera
    float clamp_kernels;      // the clamp's footprint's half width, in kernel radii
    uint level;               // 1: the shown history is scaled by level_previous's factor
    uint pad1;
} params;

// The frame's irradiance at `p`, spatially reused when it was.
vec3 irradiance_at(ivec2 p) {
    if (params.spatial != 0u) {
        return imageLoad(filtered, p).rgb;
    }
    return demodulate(imageLoad(indirect, p).rgb, imageLoad(gbuffer_albedo, p).rgb);
}

#include "temporal_reproject.glsl"
#include "temporal_clamp.glsl"

// Reuses the pixel's history, showing it scaled by `factor` (the image's level); `level`: the
// luminance of its new estimate and of the history it was blended with, and 1 (all 0 where it
// had none).
void reuse_pixel(ivec2 pixel, float factor, out vec3 level) {
    level = vec3(0.0);
    vec4 surface = imageLoad(gbuffer_position, pixel);
    vec3 n = imageLoad(gbuffer_normal, pixel).xyz;
    vec4 l = imageLoad(indirect, pixel);
    vec3 albedo = imageLoad(gbuffer_albedo, pixel).rgb;
    vec3 l_direct = imageLoad(direct, pixel).rgb;
    // Where nothing is reused the frame passes through bit for bit.
    vec3 reused = l.rgb;
    if (params.mode == MODE_STILL) {
        vec4 history = imageLoad(history_previous, pixel);
        imageStore(history_current, pixel, history);
        imageStore(filtered_mean_current, pixel, imageLoad(filtered_mean_previous, pixel));
        imageStore(own_mean_current, pixel, imageLoad(own_mean_previous, pixel));
        imageStore(surface_current, pixel, imageLoad(surface_previous, pixel));
        imageStore(normal_current, pixel, imageLoad(normal_previous, pixel));
        float w = history.a - 1.0;
        if (w > 0.0 && surface.w != 0.0) {
            vec3 e = demodulate(l.rgb, albedo);
            reused = albedo * ((params.still_batches * e + w * history.rgb) / (params.still_batches + w));
        }
    } else {
        vec3 e = demodulate(l.rgb, albedo);
        float frames = surface.w != 0.0 ? 1.0 : 0.0;
        vec4 filtered_mean_out = vec4(e, frames);
        vec3 own_mean_out = e;
        if (params.mode == MODE_MOTION && surface.w != 0.0) {
            vec3 smooth_e = params.spatial != 0u ? imageLoad(filtered, pixel).rgb : e;
            vec4 filtered_mean;
            vec3 own_mean;
            vec2 at;
            vec4 history = reprojected_history(surface.xyz, uint(surface.w) - 1u, n, filtered_mean, own_mean, at);
            filtered_mean_out.rgb = smooth_e;
            if (history.a > 0.0) {
                frames = min(history.a + 1.0, params.max_history);
                // The filter's bias on this surface, per channel: its long mean over the
                // pixel's own.
                float count = min(filtered_mean.a + 1.0, params.bias_frames);
                filtered_mean_out = vec4(mix(filtered_mean.rgb, smooth_e, 1.0 / count), count);
                own_mean_out = mix(own_mean, e, 1.0 / count);
                vec3 ratio = vec3(1.0);
                for (int c = 0; c < 3; c++) {
                    if (filtered_mean_out[c] > 0.0) {
                        ratio[c] = clamp(own_mean_out[c] / filtered_mean_out[c], 0.5, 2.0);
                    }
                }
                ratio = mix(vec3(1.0), ratio, min((count - 1.0) / max(params.max_history - 1.0, 1.0), 1.0));
                vec3 current = smooth_e * ratio;
                vec3 mean, lo, hi;
                float mean_noise;
                bool moving = uint(surface.w) - 1u >= params.first_moving_triangle;
                float stride = clamp_stride(length(surface.xyz - frame.camera_position.xyz));
                neighbourhood(pixel, current, stride, n, moving, mean, mean_noise, lo, hi);
                vec3 change = lighting_change(mean, mean_noise, history_neighbourhood(at, stride, n, moving));
                frames = mix(1.0, frames, change.y);
                e = mix(clamp(change.x * history.rgb, lo, hi), current, 1.0 / frames);
                level = vec3(luminance_of(current), luminance_of(history.rgb), 1.0);
                // What is shown: where no neighbourhood tells a change from noise, the history
                // scaled by the image's level (a slow change of the light, lighting_level.comp),
                // within the same range. The history kept is not, so the level's measurement
                // of the history's lag never feeds on itself.
                float shown = mix(factor, change.x, change.z);
                reused = albedo * mix(clamp(shown * history.rgb, lo, hi), current, 1.0 / frames);
            } else {
                // A disocclusion has nothing else: the filtered estimate as it is.
                e = smooth_e;
                reused = albedo * e;
            }
        }
        imageStore(history_current, pixel, vec4(e, frames));
        imageStore(filtered_mean_current, pixel, filtered_mean_out);
        imageStore(own_mean_current, pixel, vec4(own_mean_out, 0.0));
        imageStore(surface_current, pixel, surface);
        imageStore(normal_current, pixel, vec4(n, 0.0));
    }
    imageStore(reused_indirect, pixel, vec4(reused, l.a));
    vec4 composed = reused == l.rgb ? imageLoad(radiance, pixel) : vec4(l_direct + reused, 1.0);
    imageStore(reused_radiance, pixel, composed);
}

#define WORKGROUP_SUM_SIZE 64u
#include "workgroup_sum.glsl"

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    vec3 level = vec3(0.0);
    // Every invocation reaches the barrier below.
    if (pixel.x < int(frame.width) && pixel.y < int(frame.height)) {
        float factor = params.level != 0u ? imageLoad(level_previous, ivec2(0)).r : 1.0;
        reuse_pixel(pixel, factor, level);
    }
    vec4 total = workgroup_sum(vec4(level, 0.0));
    if (gl_LocalInvocationIndex == 0u) {
        uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
        level_partials.sums[group] = total;
    }
}
