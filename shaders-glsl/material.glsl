// Albedo lookup: the texel buffer holds every texture's RGBA8 texels (sRGB colour, linear
// alpha); sampling is bilinear with repeat wrapping, in linear space.
#ifndef LEAKLESS_MATERIAL_GLSL
#define LEAKLESS_MATERIAL_GLSL
#include "common.glsl"

vec3 srgb_to_linear(vec3 c) {
    return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), greaterThan(c, vec3(0.04045)));
}

vec4 fetch_texel(Material m, ivec2 p) {
    ivec2 size = ivec2(m.texture_width, m.texture_height);
    p = ((p % size) + size) % size;
    vec4 t = unpackUnorm4x8(texels.words[m.texture_offset + uint(p.y) * m.texture_width + uint(p.x)]);
    return vec4(srgb_to_linear(t.rgb), t.a);
}

// Base colour × texture at `uv`; `texels` must be declared by the including shader.
vec4 material_albedo(Material m, vec2 uv) {
    if (m.texture_width == 0u) {
        return m.base_color;
    }
    vec2 p = uv * vec2(m.texture_width, m.texture_height) - 0.5;
    ivec2 i = ivec2(floor(p));
    vec2 f = p - vec2(i);
    vec4 t = mix(mix(fetch_texel(m, i), fetch_texel(m, i + ivec2(1, 0)), f.x),
                 mix(fetch_texel(m, i + ivec2(0, 1)), fetch_texel(m, i + ivec2(1, 1)), f.x), f.y);
    return m.base_color * t;
}

#endif
