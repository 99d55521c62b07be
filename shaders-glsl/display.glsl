// What the window and the PNG show: the value a pixel of a layer displays as, and how it
// becomes a colour. Shared by the luminance statistics (auto exposure) and the tonemap, so
// both use exactly the same definition.
#ifndef LEAKLESS_DISPLAY_GLSL
#define LEAKLESS_DISPLAY_GLSL

// Display modes (`ViewLayer` in crates/renderer/src/passes/tonemap.rs): a radiance layer, or a heat map of
// one channel of the gather's per-pixel counts.
const uint DISPLAY_RADIANCE = 0u;
const uint DISPLAY_CANDIDATES = 1u;   // photons examined per pixel
const uint DISPLAY_VISIBILITY = 2u;   // visibility rays per pixel
const uint DISPLAY_HISTORY = 3u;      // frames a pixel's temporal history holds (.a)

// Rec.709 luminance of linear RGB.
float luminance(vec3 c) {
    return dot(c, vec3(0.2126, 0.7152, 0.0722));
}

// The scalar a pixel is exposed by: its luminance, or its count for the heat maps.
float display_value(uint mode, vec4 texel) {
    if (mode == DISPLAY_CANDIDATES) {
        return texel.x;
    }
    if (mode == DISPLAY_VISIBILITY) {
        return texel.y;
    }
    if (mode == DISPLAY_HISTORY) {
        return texel.a;
    }
    return luminance(texel.rgb);
}

// Narkowicz's fit of the ACES filmic curve: keeps highlights from clipping flat.
vec3 filmic(vec3 x) {
    return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

vec3 srgb_encode(vec3 x) {
    return mix(12.92 * x, 1.055 * pow(x, vec3(1.0 / 2.4)) - 0.055, greaterThan(x, vec3(0.0031308)));
}

// A perceptually ordered ramp for counts (dark blue → cyan → yellow → red), t in [0, 1].
vec3 heat_ramp(float t) {
    t = clamp(t, 0.0, 1.0);
    vec3 a = vec3(0.05, 0.03, 0.25);
    vec3 b = vec3(0.0, 0.6, 0.85);
    vec3 c = vec3(0.95, 0.9, 0.2);
    vec3 d = vec3(0.85, 0.1, 0.05);
    return t < 0.5 ? mix(a, b, t * 2.0) : (t < 0.8 ? mix(b, c, (t - 0.5) / 0.3) : mix(c, d, (t - 0.8) / 0.2));
}

#endif
