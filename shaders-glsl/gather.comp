#version 460
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
// Gather: one thread per view sample walks the photon lists of its leaf and of every
// ancestor, and for each photon within the radius whose incoming direction faces the sample
// adds flux × kernel to the irradiance; the indirect radiance is ρ/π · E.
//
// Leakage removal (`visibility`): before a photon counts, a visibility segment is traced from
// the sample to the photon, both lifted off their surfaces; a hit means the light leaked
// through geometry: it is dropped from the indirect layer and added to the `leaked` layer.
// With `cap`, at most `cap` photons are gathered per sample (the thesis' per-pixel cap).
//
// Sums are kept in 64-bit fixed point: the splat appends to the lists with atomics, so their
// order changes from run to run, and only an order-independent sum makes a frame
// bit-identical for a fixed seed.
#include "trace.glsl"
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
    uint candidates_lo;   // photons examined (64-bit totals as lo/hi words)
    uint candidates_hi;
    uint accepted_lo;     // within the radius and facing: visibility rays when tracing
    uint accepted_hi;
    uint occluded_lo;     // of those, blocked: leaks removed
    uint occluded_hi;
    uint valid_samples;   // view samples with a surface
    uint capped_samples;  // samples that reached the cap
} gather_counters;
layout(set = 0, binding = 10, rgba32f) uniform writeonly image2D indirect_sum;
layout(set = 0, binding = 11, rgba32f) uniform writeonly image2D leaked;
// Per pixel: photons examined, visibility rays traced, of those blocked (the heat-map layers).
layout(set = 0, binding = 13, rgba32f) uniform writeonly image2D gather_counts;
layout(push_constant) uniform GatherParams {
    float radius;
    float fixed_scale;  // fixed-point units per W/m²; chosen so no sum can overflow
    uint level_count;
    uint sample_count;
    uint image_width;
    uint visibility;    // 1: trace a visibility segment to every photon
    uint cap;           // 0: no cap; else gather at most this many photons per sample
    uint pad0;
} params;

// Adds to a 64-bit counter kept as two words (no 64-bit atomics needed).
#define ADD64(LO, HI, VALUE)                          \
    {                                                 \
        uint before_ = atomicAdd(LO, VALUE);          \
        if (before_ + (VALUE) < before_) {            \
            atomicAdd(HI, 1u);                        \
        }                                             \
    }

// Whether the segment from the sample to the photon is free of geometry.
bool photon_visible(vec3 x, vec3 ng_x, Photon ph) {
    vec3 from = offset_ray(x, ng_x);
    vec3 to = offset_ray(ph.position, ph.normal);
    vec3 d = to - from;
    float dist = length(d);
    if (dist <= 0.0) {
        return true;
    }
    // Stop a relative 2^-12 short of the photon: scale-free, so a scene scaled ×1000 decides
    // the same way, and never counting the photon's own surface.
    return !traceOccluded(from, d / dist, 0.0, dist * (1.0 - 1.0 / 4096.0));
}

void main() {
    uint s = gl_GlobalInvocationID.x;
    if (s >= params.sample_count) {
        return;
    }
    uint pixel = sorted_samples.pixels[s];
    ivec2 xy = ivec2(pixel % params.image_width, pixel / params.image_width);
    if (sorted_keys.keys[s] == INVALID_SAMPLE_KEY) {
        imageStore(indirect_sum, xy, vec4(0.0));
        imageStore(leaked, xy, vec4(0.0));
        imageStore(gather_counts, xy, vec4(0.0));
        return;
    }
    vec4 position = imageLoad(gbuffer_position, xy);
    vec3 x = position.xyz;
    vec3 n = imageLoad(gbuffer_normal, xy).xyz;
    vec3 ng = vec3(0.0);
    if (params.visibility != 0u) {
        ng = triangle_geometric_normal(uint(position.w) - 1u);
        ng = dot(ng, n) < 0.0 ? -ng : ng;
    }
    float r = params.radius;
    i64vec3 kept = i64vec3(0);
    i64vec3 lost = i64vec3(0);
    uint candidates = 0u;
    uint accepted = 0u;
    uint occluded = 0u;
    bool capped = false;
    for (uint l = 0u; l < params.level_count && !capped; ++l) {
        Level lv = levels.levels[l];
        uint node = lv.offset + s / lv.span;
        for (uint e = node_heads.heads[node]; e != END_OF_LIST; e = list_entries.entries[e].next) {
            Photon ph = photons.photons[list_entries.entries[e].photon];
            candidates += 1u;
            float d = distance(x, ph.position);
            if (d >= r || dot(n, -ph.direction) <= 0.0) {
                continue;
            }
            if (params.cap != 0u && accepted == params.cap) {
                capped = true;
                break;
            }
            accepted += 1u;
            i64vec3 contribution = i64vec3(ph.flux * (biweight(d, r) * params.fixed_scale));
            if (params.visibility == 0u || photon_visible(x, ng, ph)) {
                kept += contribution;
            } else {
                occluded += 1u;
                lost += contribution;
            }
        }
    }
    vec3 albedo_over_pi = imageLoad(gbuffer_albedo, xy).rgb / PI;
    imageStore(indirect_sum, xy, vec4(albedo_over_pi * vec3(kept) / params.fixed_scale, 1.0));
    imageStore(leaked, xy, vec4(albedo_over_pi * vec3(lost) / params.fixed_scale, 1.0));
    float rays = params.visibility != 0u ? float(accepted) : 0.0;
    imageStore(gather_counts, xy, vec4(float(candidates), rays, float(occluded), 0.0));
    atomicAdd(gather_counters.valid_samples, 1u);
    if (capped) {
        atomicAdd(gather_counters.capped_samples, 1u);
    }
    ADD64(gather_counters.candidates_lo, gather_counters.candidates_hi, candidates);
    ADD64(gather_counters.accepted_lo, gather_counters.accepted_hi, accepted);
    ADD64(gather_counters.occluded_lo, gather_counters.occluded_hi, occluded);
}
