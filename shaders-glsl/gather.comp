#version 460
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
// Gather: one thread per view sample walks the photon lists of its leaf and of every
// ancestor, and for each photon within the radius whose incoming direction faces the sample
// adds flux × kernel to the irradiance; the indirect radiance is ρ/π · E.
//
// The sum is kept in 64-bit fixed point: the splat appends to the lists with atomics, so
// their order changes from run to run, and only an order-independent sum makes a frame
// bit-identical for a fixed seed.
#include "common.glsl"
#include "hierarchy.glsl"
#include "photon.glsl"

layout(local_size_x = 64) in;

layout(set = 0, binding = 0, rgba32f) uniform readonly image2D gbuffer_position;
layout(set = 0, binding = 1, rgba32f) uniform readonly image2D gbuffer_normal;
layout(set = 0, binding = 2, rgba32f) uniform readonly image2D gbuffer_albedo;
layout(set = 0, binding = 3, std430) readonly buffer SortedKeys { uint keys[]; } sorted_keys;
layout(set = 0, binding = 4, std430) readonly buffer SortedSamples { uint pixels[]; } sorted_samples;
layout(set = 0, binding = 5, std430) readonly buffer Levels { Level levels[]; } levels;
layout(set = 0, binding = 6, std430) readonly buffer Photons { Photon photons[]; } photons;
layout(set = 0, binding = 7, std430) readonly buffer NodeHeads { uint heads[]; } node_heads;
layout(set = 0, binding = 8, std430) readonly buffer ListEntries { ListEntry entries[]; } list_entries;
layout(set = 0, binding = 9, std430) buffer GatherCounters {
    uint candidates_lo;   // photons examined, 64-bit
    uint candidates_hi;
    uint accepted_lo;     // photons within the radius and facing, 64-bit
    uint accepted_hi;
    uint valid_samples;   // view samples with a surface
    uint pad0;
    uint pad1;
    uint pad2;
} gather_counters;
layout(set = 0, binding = 10, rgba32f) uniform writeonly image2D indirect_sum;
layout(set = 0, binding = 11) uniform GatherParams {
    float radius;
    float fixed_scale;  // fixed-point units per W/m²; chosen so no sum can overflow
    uint level_count;
    uint sample_count;
    uint image_width;
    uint pad0;
    uint pad1;
    uint pad2;
} params;


void main() {
    uint s = gl_GlobalInvocationID.x;
    if (s >= params.sample_count) {
        return;
    }
    uint pixel = sorted_samples.pixels[s];
    ivec2 xy = ivec2(pixel % params.image_width, pixel / params.image_width);
    if (sorted_keys.keys[s] == INVALID_SAMPLE_KEY) {
        imageStore(indirect_sum, xy, vec4(0.0));
        return;
    }
    vec3 x = imageLoad(gbuffer_position, xy).xyz;
    vec3 n = imageLoad(gbuffer_normal, xy).xyz;
    float r = params.radius;
    i64vec3 sum = i64vec3(0);
    uint candidates = 0u;
    uint accepted = 0u;
    for (uint l = 0u; l < params.level_count; ++l) {
        Level lv = levels.levels[l];
        uint node = lv.offset + s / lv.span;
        for (uint e = node_heads.heads[node]; e != END_OF_LIST; e = list_entries.entries[e].next) {
            Photon ph = photons.photons[list_entries.entries[e].photon];
            candidates += 1u;
            float d = distance(x, ph.position);
            if (d < r && dot(n, -ph.direction) > 0.0) {
                accepted += 1u;
                sum += i64vec3(ph.flux * (biweight(d, r) * params.fixed_scale));
            }
        }
    }
    vec3 irradiance = vec3(sum) / params.fixed_scale;
    vec3 albedo = imageLoad(gbuffer_albedo, xy).rgb;
    imageStore(indirect_sum, xy, vec4(albedo / PI * irradiance, 1.0));
    atomicAdd(gather_counters.valid_samples, 1u);
    // Counters: one atomic pair per thread (64-bit totals without 64-bit atomics).
    uint lo = atomicAdd(gather_counters.candidates_lo, candidates);
    if (lo + candidates < lo) {
        atomicAdd(gather_counters.candidates_hi, 1u);
    }
    lo = atomicAdd(gather_counters.accepted_lo, accepted);
    if (lo + accepted < lo) {
        atomicAdd(gather_counters.accepted_hi, 1u);
    }
}
