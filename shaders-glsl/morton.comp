#version 460
// 30-bit Morton code of every pixel's view sample, quantised to the view-sample bounds, with
// the pixel index as value. Pixels without a surface get INVALID_SAMPLE_KEY and sort last.
#include "common.glsl"
#include "gbuffer.glsl"
#include "hierarchy.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

FRAME_BLOCK(0);
GBUFFER_BINDINGS(1)
layout(set = 1, binding = 4, std430) readonly buffer SampleBounds { uint min_key[3]; uint max_key[3]; } sample_bounds;
layout(set = 1, binding = 5, std430) writeonly buffer MortonKeys { uint keys[]; } morton_keys;
layout(set = 1, binding = 6, std430) writeonly buffer MortonValues { uint values[]; } morton_values;

float from_order_key(uint k) {
    return uintBitsToFloat((k & 0x80000000u) != 0u ? (k & 0x7fffffffu) : ~k);
}

// Spreads the low 10 bits of v so that two zero bits separate each.
uint spread_bits(uint v) {
    v &= 0x3ffu;
    v = (v | (v << 16u)) & 0x030000ffu;
    v = (v | (v << 8u)) & 0x0300f00fu;
    v = (v | (v << 4u)) & 0x030c30c3u;
    v = (v | (v << 2u)) & 0x09249249u;
    return v;
}

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (pixel.x >= int(frame.width) || pixel.y >= int(frame.height)) {
        return;
    }
    uint index = uint(pixel.y) * frame.width + uint(pixel.x);
    vec4 p = imageLoad(gbuffer_position, pixel);
    uint key = INVALID_SAMPLE_KEY;
    if (p.w > 0.0) {
        vec3 lo = vec3(from_order_key(sample_bounds.min_key[0]), from_order_key(sample_bounds.min_key[1]), from_order_key(sample_bounds.min_key[2]));
        vec3 hi = vec3(from_order_key(sample_bounds.max_key[0]), from_order_key(sample_bounds.max_key[1]), from_order_key(sample_bounds.max_key[2]));
        vec3 q = clamp((p.xyz - lo) / max(hi - lo, vec3(1e-30)), 0.0, 1.0) * 1023.0;
        uvec3 c = uvec3(q + 0.5);
        key = (spread_bits(c.x) << 2u) | (spread_bits(c.y) << 1u) | spread_bits(c.z);
    }
    morton_keys.keys[index] = key;
    morton_values.values[index] = index;
}
