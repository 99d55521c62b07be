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
// Most segments need no ray (`prove_clear`): photon_clearance.comp gives each photon a ball
// around its lifted position that holds no triangle except those lying wholly on or under the
// plane τ (a quarter of the photon's lift) above the photon's surface. A segment from a lifted
// sample inside the ball, more than 2τ above the surface, to the lifted photon stays in the
// ball (which is convex) and above that plane (a half-space): it meets no triangle, so
// tracing it would find nothing. The images are bit-identical either way
// (tests/leak.rs checks it on every leak scene and both backends).
//
// Sums are kept in 64-bit fixed point: the splat appends to the lists with atomics, so their
// order changes from run to run, and only an order-independent sum makes a frame
// bit-identical for a fixed seed.
#include "trace.glsl"
#include "common.glsl"
#include "hierarchy.glsl"
#include "photon.glsl"
#include "random.glsl"

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
    uint accepted_lo;     // within the radius and facing: visibility tests when tracing
    uint accepted_hi;
    uint occluded_lo;     // of those, blocked: leaks removed
    uint occluded_hi;
    uint proven_lo;       // of the tests, proven clear without a ray
    uint proven_hi;
    uint valid_samples;   // view samples with a surface
    uint capped_samples;  // samples that reached the cap
    uint pad0;
    uint pad1;
} gather_counters;
layout(set = 0, binding = 10, rgba32f) uniform writeonly image2D indirect_sum;
layout(set = 0, binding = 11, rgba32f) uniform writeonly image2D leaked;
// Per pixel: photons examined, visibility rays traced, blocked rays (the heat-map layers).
layout(set = 0, binding = 13, rgba32f) uniform writeonly image2D gather_counts;
layout(push_constant) uniform GatherParams {
    float radius;
    float fixed_scale;  // fixed-point units per W/m²; chosen so no sum can overflow
    uint level_count;
    uint sample_count;
    uint image_width;
    uint visibility;    // 1: trace a visibility segment to every photon
    uint cap;           // 0: no cap; else gather at most this many photons per sample
    uint prove_clear;   // 1: skip the rays photon_clearance.comp proves clear
    vec3 eye;           // the camera's position (segments leave from a point nudged toward it)
    uint visible_disk;  // 1: normalise by the kernel's visible part of the disk (see below)
    uint seed;          // this frame's seed (the disk probes' rotation)
    uint pad0;
    uint pad1;
    uint pad2;
} params;
// Per photon (photon_clearance.comp): its lifted position and its clearance radius.
layout(set = 0, binding = 14, std430) readonly buffer Clearances { Clearance items[]; } clearance;

// Adds to a 64-bit counter kept as two words (no 64-bit atomics needed).
#define ADD64(LO, HI, VALUE)                          \
    {                                                 \
        uint before_ = atomicAdd(LO, VALUE);          \
        if (before_ + (VALUE) < before_) {            \
            atomicAdd(HI, 1u);                        \
        }                                             \
    }

// Whether the segment from the lifted sample `from` to the photon is free of geometry;
// `proven` when that needed no ray.
//
// The segment ends straight above the photon, at half its lift: on the photon's side of its
// own surface (a segment arriving from behind a zero-thickness wall still crosses it), and
// on the photon's side of everything else too. Ending it short of the photon along the
// segment instead would carry the end across a wall standing within that distance of the
// photon (a photon at the foot of a sealed partition, seen from the other room).
bool photon_visible(vec3 from, Photon ph, Clearance photon_clearance, inout uint occluder, out bool proven) {
    vec3 lifted = photon_clearance.lifted;  // offset_ray(ph.position, ph.normal)
    float lift = dot(lifted - ph.position, ph.normal);
    vec3 to = mix(ph.position, lifted, 0.5);
    vec3 d = to - from;
    float dist2 = dot(d, d);
    // Both ends in the clear ball (around `lifted`, which `to` is half a lift from) and at
    // least 2τ above the photon's surface: the segment meets nothing (see the top).
    vec3 from_lifted = lifted - from;
    proven = params.prove_clear != 0u && dot(from_lifted, from_lifted) < photon_clearance.radius * photon_clearance.radius
        && 0.5 * lift < photon_clearance.radius && dot(from - ph.position, ph.normal) > 0.5 * lift;
    if (proven) {
        return true;
    }
    float dist = sqrt(dist2);
    if (!(dist > 0.0)) {
        return true;
    }
    return !traceOccludedCached(from, d / dist, 0.0, dist, occluder);
}

// Visible-disk normalisation (leakless). The kernel estimate divides the flux near x by the
// kernel's mass over a whole disk, which holds only where x's surface covers the disk and all
// of it can be seen from x. Where it does not (a 40 cm pier's face under a 40 cm radius, the
// foot of a wall, a corner), `splat` happens to make up the missing area with light from
// other surfaces (the pier's other faces, the room behind the wall), which the visibility test
// rightly removes: `leakless` came out darker than the reference there. With `visible_disk`,
// only photons on x's own surface count (normal within 60° of x's, and within DISK_SLOPE of
// its tangent plane as seen from x), and their sum is divided by the kernel's mass over the
// part of the disk where that surface exists and can be seen from x.
//
// That mass is estimated along DISK_DIRECTIONS rays from x, rotated at random per pixel and
// frame (accumulation averages them), each DISK_SLOPE above the plane (a concave surface
// rises above its tangent plane; a ray grazing it would find it at once). Each ray gives
// exactly the kernel mass its direction sees up to the first surface it meets; within that,
// DISK_DEPTHS points drawn from the kernel's radial mass check that the surface exists: over
// the sample's own triangle (no ray needed), or else a ray down from the point must meet a
// surface facing like x's within DISK_SLOPE below the plane.
#define DISK_DIRECTIONS 8u
#define DISK_DEPTHS 4u
const float DISK_SLOPE = 0.1763;            // tan 10°
const float DISK_MIN_NORMAL_COSINE = 0.5;   // 60°
// A floor so that one unlucky probe set cannot amplify a pixel's noise without bound (a
// room's corner is a quarter disk).
const float DISK_MIN_MASS = 0.2;

// The biweight kernel's mass within distance s·r of the centre: 1 − (1 − s²)³.
float biweight_mass(float s) {
    float u = 1.0 - s * s;
    return 1.0 - u * u * u;
}

// Whether a photon at `p` with normal `pn` lies on the surface of the sample at `x`.
bool on_own_surface(vec3 x, vec3 ng, vec3 p, vec3 pn) {
    vec3 d = p - x;
    return dot(pn, ng) >= DISK_MIN_NORMAL_COSINE && abs(dot(d, ng)) <= DISK_SLOPE * length(d);
}

// Whether `p`, projected along the triangle's normal, lies in the triangle.
bool over_triangle(uint triangle, vec3 p) {
    vec3 a = vertex_position(3u * triangle);
    vec3 b = vertex_position(3u * triangle + 1u);
    vec3 c = vertex_position(3u * triangle + 2u);
    vec3 n = cross(b - a, c - a);
    return dot(cross(b - a, p - a), n) >= 0.0 && dot(cross(c - b, p - b), n) >= 0.0 && dot(cross(a - c, p - c), n) >= 0.0;
}

// The share of the kernel's mass over the part of the disk around `from` (normal `ng`,
// radius r) where the surface exists and can be seen. `own` is the sample's triangle: a probe
// that lands over it (and it is opaque) is on the surface without a ray down, which spares
// most of those rays on the large triangles walls and floors are made of.
float visible_disk_mass(vec3 from, vec3 ng, uint own, float r, uvec2 pixel) {
    bool own_opaque = triangle_material(own).alpha_cutoff < 0.0;
    vec3 t, b;
    basis(ng, t, b);
    Rng rng = rng_seed(pixel, 0xd15cu, params.seed);
    float angle_phase = rng_next(rng);
    float stretch = sqrt(1.0 + DISK_SLOPE * DISK_SLOPE);  // ray length per unit of in-plane distance
    float mass = 0.0;
    for (uint k = 0u; k < DISK_DIRECTIONS; ++k) {
        float phi = 2.0 * PI * (float(k) + angle_phase) / float(DISK_DIRECTIONS);
        vec3 dir = (cos(phi) * t + sin(phi) * b + DISK_SLOPE * ng) / stretch;
        // What this direction sees: exactly, up to the first surface the ray meets.
        Hit hit = traceClosest(from, dir, 0.0, r * stretch);
        float reach = hit.triangle == NO_HIT ? r : min(hit.t / stretch, r);
        float seen = biweight_mass(reach / r);
        // Where the surface exists within that reach: probes drawn from the kernel's radial
        // mass 1 − (1 − s²)³ (uniform in it: s = sqrt(1 − (1 − u)^(1/3))), stratified.
        float phase = rng_next(rng);
        uint supported = 0u;
        for (uint j = 0u; j < DISK_DEPTHS; ++j) {
            float u = seen * (float(j) + phase) / float(DISK_DEPTHS);
            float rho = r * sqrt(max(0.0, 1.0 - pow(1.0 - u, 1.0 / 3.0)));
            vec3 q = from + (rho * stretch) * dir;
            if (own_opaque && over_triangle(own, q)) {
                supported += 1u;
                continue;
            }
            Hit down = traceClosest(q, -ng, 0.0, 2.0 * DISK_SLOPE * rho + 4.0 * lift_size(q));
            if (down.triangle != NO_HIT && abs(dot(triangle_geometric_normal(down.triangle), ng)) >= DISK_MIN_NORMAL_COSINE) {
                supported += 1u;
            }
        }
        mass += seen * float(supported) / float(DISK_DEPTHS);
    }
    return max(mass / float(DISK_DIRECTIONS), DISK_MIN_MASS);
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
    vec3 from = x;
    vec3 ng = n;
    float disk_mass = 1.0;
    if (params.visibility != 0u) {
        ng = triangle_geometric_normal(uint(position.w) - 1u);
        ng = dot(ng, n) < 0.0 ? -ng : ng;
        from = offset_ray(nudge_toward(x, params.eye), ng);
        if (params.visible_disk != 0u) {
            disk_mass = visible_disk_mass(from, ng, uint(position.w) - 1u, params.radius, uvec2(xy));
        }
    }
    float r = params.radius;
    i64vec3 kept = i64vec3(0);
    i64vec3 lost = i64vec3(0);
    uint candidates = 0u;
    uint accepted = 0u;
    uint occluded = 0u;
    uint proven = 0u;
    uint occluder = NO_HIT;  // the surface that blocked this sample's last blocked segment
    bool capped = false;
    for (uint l = 0u; l < params.level_count && !capped; ++l) {
        Level lv = levels.levels[l];
        uint node = lv.offset + s / lv.span;
        for (uint e = node_heads.heads[node]; e != END_OF_LIST; e = list_entries.entries[e].next) {
            uint index = list_entries.entries[e].photon;
            Photon ph = photons.photons[index];
            candidates += 1u;
            float d = distance(x, ph.position);
            if (d >= r || dot(n, -ph.direction) <= 0.0) {
                continue;
            }
            if (params.visible_disk != 0u && !on_own_surface(x, ng, ph.position, ph.normal)) {
                continue;
            }
            if (params.cap != 0u && accepted == params.cap) {
                capped = true;
                break;
            }
            accepted += 1u;
            i64vec3 contribution = i64vec3(ph.flux * (biweight(d, r) * params.fixed_scale));
            bool clear = true;
            if (params.visibility != 0u) {
                bool without_ray;
                clear = photon_visible(from, ph, clearance.items[index], occluder, without_ray);
                proven += without_ray ? 1u : 0u;
            }
            if (clear) {
                kept += contribution;
            } else {
                occluded += 1u;
                lost += contribution;
            }
        }
    }
    vec3 albedo_over_pi = imageLoad(gbuffer_albedo, xy).rgb / PI;
    imageStore(indirect_sum, xy, vec4(albedo_over_pi * vec3(kept) / (params.fixed_scale * disk_mass), 1.0));
    imageStore(leaked, xy, vec4(albedo_over_pi * vec3(lost) / params.fixed_scale, 1.0));
    float rays = params.visibility != 0u ? float(accepted - proven) : 0.0;
    imageStore(gather_counts, xy, vec4(float(candidates), rays, float(occluded), 0.0));
    atomicAdd(gather_counters.valid_samples, 1u);
    if (capped) {
        atomicAdd(gather_counters.capped_samples, 1u);
    }
    ADD64(gather_counters.candidates_lo, gather_counters.candidates_hi, candidates);
    ADD64(gather_counters.accepted_lo, gather_counters.accepted_hi, accepted);
    ADD64(gather_counters.occluded_lo, gather_counters.occluded_hi, occluded);
    ADD64(gather_counters.proven_lo, gather_counters.proven_hi, proven);
}
