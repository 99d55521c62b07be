// Types and constants shared by every leakless shader. Each struct here has a #[repr(C)] twin
// in crates/renderer/src/gpu_types.rs; build-time reflection and check_bindings compare sizes and offsets.
#ifndef LEAKLESS_COMMON_GLSL
#define LEAKLESS_COMMON_GLSL

const float PI = 3.14159265358979323846;

// One per frame: camera and output size. Declared as a block (not a struct inside one) so
// reflection sees its members; FRAME_BLOCK(n) declares it at binding n as `frame`.
#define FRAME_BLOCK(n) layout(set = 1, binding = n) uniform Frame { \
    mat4 view_proj; \
    vec4 camera_position; \
    uint width; \
    uint height; \
    uint light_count;   /* punctual lights */ \
    uint emitter_count; /* emissive triangles (emitters.glsl) */ \
} frame

// glTF KHR_lights_punctual, in world space. `intensity` is colour × intensity: radiant
// intensity (W/sr) for point and spot lights, irradiance (W/m²) for directional lights.
const uint LIGHT_POINT = 0u;
const uint LIGHT_SPOT = 1u;
const uint LIGHT_DIRECTIONAL = 2u;
struct Light {
    vec3 position;
    uint kind;
    vec3 direction;  // the direction light travels
    float cos_outer;
    vec3 intensity;
    float cos_inner;
};

// Lambertian material: albedo = base_color × texture (sRGB texels, decoded here).
struct Material {
    vec4 base_color;
    uint texture_offset;  // first texel in the texel buffer
    uint texture_width;   // 0: no texture
    uint texture_height;
    float alpha_cutoff;   // < 0: opaque
    vec3 emission;        // emitted radiance (W/m²/sr) × the emissive texture; 0: not a light
    uint double_sided;    // 1: emits from both faces; 0: from the front (counter-clockwise) face
    uint emission_texture_offset;
    uint emission_texture_width;  // 0: no emissive texture
    uint emission_texture_height;
    uint pad0;
};

// Bit i of the low `bits` bits of v moved to bit stride·i: interleaved, these make the Morton
// numbers of the photon and emission cells (photon_cell.glsl, emission_cell.glsl).
uint spread_cell_bits(uint v, uint bits, uint stride) {
    uint spread = 0u;
    for (uint i = 0u; i < bits; ++i) {
        spread |= ((v >> i) & 1u) << (stride * i);
    }
    return spread;
}

#endif
