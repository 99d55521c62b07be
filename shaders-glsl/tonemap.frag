#version 460
// Tonemap: the displayed layer, exposed so that the log-average of its lit pixels maps to
// middle grey (or by a fixed exposure), through the filmic curve, sRGB-encoded unless the
// target's format encodes. Heat maps go through a colour ramp instead. The same pass writes
// the window's swapchain image and the PNG a render saves.
#include "display.glsl"

layout(set = 1, binding = 0, rgba32f) uniform readonly image2D displayed;
layout(set = 1, binding = 1, std430) readonly buffer LuminanceStats {
    float log_sum;
    float lit_pixels;
    float indirect_sum;
    float leaked_sum;
} stats;
layout(push_constant) uniform TonemapParams {
    uint mode;          // DISPLAY_*
    float exposure;     // > 0: fixed; 0: automatic
    uint encode_srgb;   // 1: the target is UNORM, encode here; 0: its format encodes
    uint pad0;
    vec2 source_scale;  // layer pixels per target pixel (the app renders below window size)
    uint pad1;
    uint pad2;
} params;

layout(location = 0) out vec4 out_color;

void main() {
    ivec2 pixel = min(ivec2(gl_FragCoord.xy * params.source_scale), imageSize(displayed) - 1);
    vec4 texel = imageLoad(displayed, pixel);
    float exposure = params.exposure;
    if (exposure <= 0.0) {
        exposure = stats.lit_pixels > 0.0 ? 0.18 / exp(stats.log_sum / stats.lit_pixels) : 1.0;
    }
    vec3 color;
    if (params.mode == DISPLAY_RADIANCE) {
        color = filmic(max(texel.rgb, vec3(0.0)) * exposure);
    } else if (params.mode == DISPLAY_HISTORY) {
        // Frames held over the longest history (the exposure): a fixed scale, linear.
        color = heat_ramp(display_value(params.mode, texel) * exposure);
    } else {
        // Exposed like radiance: the log-average count lands a little below the ramp's middle.
        float v = display_value(params.mode, texel);
        color = v > 0.0 ? heat_ramp(filmic(vec3(v * exposure)).x) : vec3(0.0);
    }
    if (params.encode_srgb != 0u) {
        color = srgb_encode(color);
    }
    out_color = vec4(color, 1.0);
}
