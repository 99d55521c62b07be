// Temporal reuse's clamp (temporal.comp includes it after its bindings): the range the history
// may take around the new frame's neighbourhood mean, and how much the light changed between the
// two, measured over the same footprint of last frame's history.

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
