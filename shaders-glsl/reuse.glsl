#pragma once
// What temporal and spatial reuse share: they filter and blend irradiance, the indirect layer
// over the surface's albedo, so that texture detail is never smeared; the result is
// modulated back by the same albedo.

vec3 demodulate(vec3 l, vec3 albedo) {
    return vec3(albedo.r > 0.0 ? l.r / albedo.r : 0.0, albedo.g > 0.0 ? l.g / albedo.g : 0.0,
                albedo.b > 0.0 ? l.b / albedo.b : 0.0);
}

float luminance_of(vec3 c) {
    return dot(c, vec3(0.2126, 0.7152, 0.0722));
}

// The gather kernel's radius in pixels at `distance` from the camera, from its radius in pixels
// one metre away: how far a frame's photon noise is correlated on the screen there.
float projected_kernel(float kernel_pixels, float distance) {
    return kernel_pixels / max(distance, 1e-6);
}
