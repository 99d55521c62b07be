// Material lookups: the texel buffer holds every texture's RGBA8 texels (sRGB colour, linear
// alpha); sampling is bilinear with repeat wrapping, in linear space.
#ifndef LEAKLESS_MATERIAL_GLSL
#define LEAKLESS_MATERIAL_GLSL
#include "common.glsl"

vec3 srgb_to_linear(vec3 c) {
    return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), greaterThan(c, vec3(0.04045)));
}

// One texture of the texel buffer: its first texel and size.
struct TextureRef {
    uint offset;
    ivec2 size;
};

vec4 fetch_texel(TextureRef t, ivec2 p) {
    p = ((p % t.size) + t.size) % t.size;
    vec4 c = unpackUnorm4x8(SCENE_TEXEL(t.offset + uint(p.y) * uint(t.size.x) + uint(p.x)));
    return vec4(srgb_to_linear(c.rgb), c.a);
}

vec4 sample_texture(TextureRef t, vec2 uv) {
    vec2 p = uv * vec2(t.size) - 0.5;
    ivec2 i = ivec2(floor(p));
    vec2 f = p - vec2(i);
    return mix(mix(fetch_texel(t, i), fetch_texel(t, i + ivec2(1, 0)), f.x),
               mix(fetch_texel(t, i + ivec2(0, 1)), fetch_texel(t, i + ivec2(1, 1)), f.x), f.y);
}

// Base colour × texture at `uv`; `texels` must be declared by the including shader.
vec4 material_albedo(Material m, vec2 uv) {
    if (m.texture_width == 0u) {
        return m.base_color;
    }
    return m.base_color * sample_texture(TextureRef(m.texture_offset, ivec2(m.texture_width, m.texture_height)), uv);
}

// Emitted radiance (W/m²/sr) at `uv` toward a side of the surface: `front` is whether that
// side is the one the counter-clockwise winding faces. Zero for surfaces that are not lights.
vec3 material_emission(Material m, vec2 uv, bool front) {
    if (m.emission == vec3(0.0) || (!front && m.double_sided == 0u)) {
        return vec3(0.0);
    }
    if (m.emission_texture_width == 0u) {
        return m.emission;
    }
    TextureRef t = TextureRef(m.emission_texture_offset, ivec2(m.emission_texture_width, m.emission_texture_height));
    return m.emission * sample_texture(t, uv).rgb;
}

#endif
