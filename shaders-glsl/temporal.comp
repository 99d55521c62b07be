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
layout(set = 0, binding = 4, rgba32f) uniform readonly image2D direct;
layout(set = 0, binding = 5, rgba32f) uniform readonly image2D indirect;
layout(set = 0, binding = 6, rgba32f) uniform readonly image2D history_previous;
layout(set = 0, binding = 7, rgba32f) uniform writeonly image2D history_current;
layout(set = 0, binding = 8, rgba32f) uniform readonly image2D surface_previous;
layout(set = 0, binding = 9, rgba32f) uniform writeonly image2D surface_current;
layout(set = 0, binding = 10, rgba32f) uniform readonly image2D normal_previous;
layout(set = 0, binding = 11, rgba32f) uniform writeonly image2D normal_current;
layout(set = 0, binding = 12, rgba32f) uniform writeonly image2D reused_indirect;
layout(set = 0, binding = 13, rgba32f) uniform writeonly image2D reused_radiance;
layout(set = 0, binding = 15, rgba32f) uniform readonly image2D radiance;
// The frame's irradiance after spatial reuse (read only when `spatial`).
layout(set = 0, binding = 16, rgba32f) uniform readonly image2D filtered;
// The long means of the filtered (.rgb, over .a frames) and of the own (.rgb) irradiance.
layout(set = 0, binding = 17, rgba32f) uniform readonly image2D filtered_mean_previous;
layout(set = 0, binding = 18, rgba32f) uniform writeonly image2D filtered_mean_current;
layout(set = 0, binding = 24, rgba32f) uniform readonly image2D own_mean_previous;
layout(set = 0, binding = 25, rgba32f) uniform writeonly image2D own_mean_current;
// The light's level (lighting_level.comp): .r the factor a moving frame's shown history is
// scaled by, measured over the frames before.
layout(set = 0, binding = 19, rgba32f) uniform readonly image2D level_previous;
// Per workgroup, Σ luminance of the new estimate and of the history it is blended with, over the
// pixels that have one (.xy), and their count (.z).
layout(set = 0, binding = 26, std430) writeonly buffer LevelPartials { vec4 sums[]; } level_partials;
// The animated instances' vertex positions as they were in the history's frame, from the first
// moving triangle's first vertex on (read only when `instances_moved`).
layout(set = 0, binding = 14, std430) readonly buffer PreviousPositions { float xyz[]; } previous_positions;

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

vec3 previous_vertex(uint v) {
    uint i = 3u * (v - 3u * params.first_moving_triangle);
    return vec3(previous_positions.xyz[i], previous_positions.xyz[i + 1u], previous_positions.xyz[i + 2u]);
}

// Where the surface point `p` of `triangle` was in the history's frame.
vec3 previous_position(vec3 p, uint triangle) {
    if (params.instances_moved == 0u || triangle < params.first_moving_triangle) {
        return p;
    }
    vec3 a = vertex_position(3u * triangle), b = vertex_position(3u * triangle + 1u);
    vec3 c = vertex_position(3u * triangle + 2u);
    vec3 ab = b - a, ac = c - a, ap = p - a;
    float d00 = dot(ab, ab), d01 = dot(ab, ac), d11 = dot(ac, ac);
    float d20 = dot(ap, ab), d21 = dot(ap, ac);
    float det = d00 * d11 - d01 * d01;
    float v = det > 0.0 ? (d11 * d20 - d01 * d21) / det : 0.0;
    float w = det > 0.0 ? (d00 * d21 - d01 * d20) / det : 0.0;
    return (1.0 - v - w) * previous_vertex(3u * triangle) + v * previous_vertex(3u * triangle + 1u)
         + w * previous_vertex(3u * triangle + 2u);
}

// The history at the surface point `p` of `triangle` with normal `n` (.a = its frames; 0 when
// no tap of last frame saw the same surface), the filter's bias there, and where the point was
// on last frame's screen.
vec4 reprojected_history(vec3 p, uint triangle, vec3 n, out vec4 filtered_mean, out vec3 own_mean, out vec2 at) {
    filtered_mean = vec4(0.0);
    own_mean = vec3(0.0);
    at = vec2(-1.0);
    vec3 was = previous_position(p, triangle);
    vec4 clip = params.previous_view_proj * vec4(was, 1.0);
    if (clip.w <= 0.0) {
        return vec4(0.0);
    }
    vec2 size = vec2(frame.width, frame.height);
    at = (clip.xy / clip.w * 0.5 + 0.5) * size - 0.5;
    ivec2 base = ivec2(floor(at));
    vec2 f = at - vec2(base);
    // Slope-aware: the distance from the tap's point to the plane of this one, against a
    // tolerance growing with the distance to the camera (the raster's precision).
    float tolerance = 0.01 * length(was - params.previous_camera.xyz) + 1e-4;
    bool moving = triangle >= params.first_moving_triangle;
    vec4 sum = vec4(0.0);
    float weight = 0.0;
    for (int k = 0; k < 4; k++) {
        ivec2 q = base + ivec2(k & 1, k >> 1);
        if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, ivec2(size)))) {
            continue;
        }
        vec4 s = imageLoad(surface_previous, q);
        if (s.w == 0.0) {
            continue;
        }
        uint t = uint(s.w) - 1u;
        bool same = moving ? t == triangle : t < params.first_moving_triangle;
        vec3 nq = imageLoad(normal_previous, q).xyz;
        if (!same || abs(dot(nq, s.xyz - was)) > tolerance || (!moving && dot(nq, n) < 0.9)) {
            continue;
        }
        float w = (k & 1) == 1 ? f.x : 1.0 - f.x;
        w *= (k >> 1) == 1 ? f.y : 1.0 - f.y;
        if (w > 0.0) {
            sum += w * imageLoad(history_previous, q);
            filtered_mean += w * imageLoad(filtered_mean_previous, q);
            own_mean += w * imageLoad(own_mean_previous, q).rgb;
            weight += w;
        }
    }
    // A history read mostly from taps of other surfaces is not this surface's.
    filtered_mean = weight > 0.25 ? filtered_mean / weight : vec4(0.0);
    own_mean = weight > 0.25 ? own_mean / weight : vec3(0.0);
    return weight > 0.25 ? sum / weight : vec4(0.0);
}

// The spacing in pixels of the clamp's 7×7 taps at `view_distance`: `clamp_kernels`
// gather-kernel radii on each side (19×19 pixels at least, 97 at most).
float clamp_stride(float view_distance) {
    if (params.clamp_kernels <= 0.0) {
        return 3.0;
    }
    return clamp(params.clamp_kernels * projected_kernel(params.kernel_pixels, view_distance) / 3.0, 3.0, 16.0);
}

// Whether a tap whose surface is `t` (triangle + 1; 0 for none) with normal `tap_normal` counts
// in a neighbourhood of a pixel of the kind `moving` (on an animated instance or not) facing
// `n`: another wall's light, or what a doorway shows, would widen the range where the light is
// changing.
bool same_kind(float t, vec3 tap_normal, vec3 n, bool moving) {
    return t != 0.0 && (uint(t) - 1u >= params.first_moving_triangle) == moving && dot(tap_normal, n) >= 0.9;
}

// The range the history may take at `pixel`, whose new estimate is `e`: within
// `clamp_relative` of the span between `e` and the new frame's mean over the taps `stride`
// pixels apart (`same_kind` of the pixel, normal `n`); with that mean and its noise (the
// deviation of its luminance). A single photon frame's noise is correlated over the kernel's
// footprint and often larger than its mean, so a box of the footprint's extremes or a few
// deviations would clamp the history to this frame's blotches and average nothing, and so
// would the mean of a footprint inside one blotch; the mean over a few kernels is steadier,
// and a change of the lighting moves it. Holding `e` in the range keeps a sharp feature that a
// still camera sees the same every frame. Where every tap is exactly zero, `e` and the mean
// are, and so is the range.
void neighbourhood(ivec2 pixel, vec3 e, float stride, vec3 n, bool moving, out vec3 mean, out float mean_noise,
                   out vec3 lo, out vec3 hi) {
    vec3 sum = vec3(0.0);
    float count = 0.0, squares = 0.0;
    ivec2 size = ivec2(frame.width, frame.height);
    for (int y = -3; y <= 3; y++) {
        for (int x = -3; x <= 3; x++) {
            ivec2 q = clamp(pixel + ivec2(round(stride * vec2(x, y))), ivec2(0), size - 1);
            if (!same_kind(imageLoad(gbuffer_position, q).w, imageLoad(gbuffer_normal, q).xyz, n, moving)) {
                continue;
            }
            vec3 i = irradiance_at(q);
            sum += i;
            squares += luminance_of(i) * luminance_of(i);
            count += 1.0;
        }
    }
    // The pixel's own tap always counts.
    mean = sum / max(count, 1.0);
    // The deviation of the mean's luminance: the taps' spread over the root of their number,
    // a quarter of them counted, since a frame's noise is correlated over a kernel.
    float y = luminance_of(mean);
    mean_noise = sqrt(max(squares / max(count, 1.0) - y * y, 0.0) / max(0.25 * count, 1.0));
    lo = max(1.0 - params.clamp_relative, 0.0) * min(e, mean);
    hi = (1.0 + params.clamp_relative) * max(e, mean);
}

// The history's mean over the clamp's footprint around `at` on last frame's screen, of the taps
// on the pixel's kind of surface (.a: how many; 0 when none).
vec4 history_neighbourhood(vec2 at, float stride, vec3 n, bool moving) {
    vec3 sum = vec3(0.0);
    float count = 0.0;
    ivec2 size = ivec2(frame.width, frame.height);
    ivec2 centre = ivec2(round(at));
    for (int y = -3; y <= 3; y++) {
        for (int x = -3; x <= 3; x++) {
            ivec2 q = centre + ivec2(round(stride * vec2(x, y)));
            if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) {
                continue;
            }
            if (!same_kind(imageLoad(surface_previous, q).w, imageLoad(normal_previous, q).xyz, n, moving)) {
                continue;
            }
            sum += imageLoad(history_previous, q).rgb;
            count += 1.0;
        }
    }
    return vec4(sum / max(count, 1.0), count);
}

// How much the light changed around the pixel since the history's frame: the new frame's mean
// over the clamp's footprint against the history's there. A change within LAG_SIGMAS of the
// new mean's noise is that noise and changes nothing; one beyond twice that is a change of the
// lighting, and the history takes the new level at once (.x, the factor it is scaled by)
// instead of lagging behind it over its frames. A history black around the pixel has no level
// to scale: it counts for fewer of its frames instead (.y, the share it keeps). .z: how far the
// change stands out (0 within LAG_SIGMAS, 1 beyond twice that). Chosen with `bench motion
// --size 128x72 --spp 16 --truth-spp 1024`, the last frame's HDR-FLIP ratio of the moving light
// and the atrium (without the lighting level): two deviations 0.57× and 0.42×, three 0.61× and
// 0.37×, four 0.66× and 0.36×, none (the clamp alone) 0.73× and 0.35×.
const float LAG_SIGMAS = 3.0;
vec3 lighting_change(vec3 mean_now, float noise, vec4 mean_then) {
    float now = luminance_of(mean_now), then = luminance_of(mean_then.rgb);
    float tolerance = LAG_SIGMAS * noise;
    if (mean_then.a == 0.0 || tolerance <= 0.0) {
        return vec3(1.0, 1.0, 0.0);
    }
    float beyond = clamp((abs(now - then) - tolerance) / tolerance, 0.0, 1.0);
    return then > 0.0 ? vec3(mix(1.0, now / then, beyond), 1.0, beyond) : vec3(1.0, 1.0 - beyond, beyond);
}

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
