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
// With `visible_disk` (leakless), only photons on the sample's own surface count, and their sum
// is divided by the kernel's mass over the part of the disk that surface covers and is seen
// (visible_disk.comp says why).
//
// Most segments need no ray (`prove_clear`): photon_clearance.comp gives each photon a ball
// around its lifted position that holds no triangle except those lying wholly on or under the
// plane τ (a quarter of the photon's lift) above the photon's surface, and
// sample_clearance.comp gives each sample the same ball around the point its segments leave
// from. A segment from the sample that stays in the sample's ball (which is convex) up to a
// point above the sample's plane, and from there on in the photon's ball and more than 2τ
// above the photon's surface, meets no triangle, so tracing it would find nothing. The images
// are bit-identical either way (tests/suite/visibility.rs checks it on every leak scene and
// both backends).
//
// Sums are kept in 64-bit fixed point: the list scatter places photons with atomics, so a
// list's order changes from run to run, and only an order-independent sum makes a frame
// bit-identical for a fixed seed.
// Visibility segments run above their photon's plane: the traversal skips boxes below it.
#define TRACE_PLANE_CULL
#include "trace.glsl"
#include "common.glsl"
#include "gbuffer.glsl"
#include "hierarchy.glsl"
#include "photon.glsl"
#include "disk.glsl"
#include "counters.glsl"
#include "device_address.glsl"

// One thread per view sample; the device tuning sets the workgroup size.
layout(local_size_x = 64) in;
layout(local_size_x_id = 0) in;

GBUFFER_BINDINGS(0)
layout(set = 1, binding = 3, std430) readonly buffer SortedKeys { uint keys[]; } sorted_keys;
layout(set = 1, binding = 4, std430) readonly buffer SortedSamples { uint pixels[]; } sorted_samples;
layout(set = 1, binding = 5, std430) readonly buffer Levels { Level levels[]; } levels;
layout(set = 1, binding = 6, std430) readonly buffer Photons { Photon photons[]; } photons;
// Node n's photons are list_photons[ends[n − 1] .. ends[n]) (from 0 for n = 0; list_scatter.comp).
layout(set = 1, binding = 7, std430) readonly buffer NodeEnds { uint ends[]; } node_ends;
layout(set = 1, binding = 8, std430) readonly buffer ListPhotons { uint photons[]; } list_photons;
layout(set = 1, binding = 9, std430) buffer GatherCounters {
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
    uint ray_nodes_lo;    // the visibility rays' traversal work, where TRACE_COUNT_WORK counts it
    uint ray_nodes_hi;
    uint ray_triangles_lo;
    uint ray_triangles_hi;
    uint candidates_most;  // the most photons one sample examined: a GPU waits for its longest
    uint pad1;
} gather_counters;
layout(set = 1, binding = 10, rgba32f) uniform writeonly image2D indirect_sum;
layout(set = 1, binding = 11, rgba32f) uniform writeonly image2D leaked;
// Per pixel: photons examined, visibility rays traced, blocked rays (the heat-map layers).
layout(set = 1, binding = 13, rgba32f) uniform writeonly image2D gather_counts;
layout(push_constant) uniform GatherParams {
    float radius;
    float fixed_scale;  // fixed-point units per W/m²; chosen so no sum can overflow
    uint level_count;
    uint sample_count;
    vec3 eye;           // the camera's position (segments leave from a point nudged toward it)
    uint prove_clear;   // 1: skip the rays photon_clearance.comp proves clear
    uint image_width;
    uint cap;           // 0: no cap; else gather at most this many photons per sample
    uvec2 list_photons_address;  // the buffers below, read through their addresses
    uvec2 positions_address;     // (crates/renderer/src/device_address.rs says why)
    uvec2 photons_address;
    uvec2 clearance_address;
    uint sample_clearance_tile;  // pixels a side of sample_clearance's and segment_entries' tiles
    uint segment_entries;        // 1: segment_entries.comp wrote the tiles' entries (compute backend)
} params;
// Per photon (photon_clearance.comp): its lifted position and its clearance radius.
layout(set = 1, binding = 14, std430) readonly buffer Clearances { Clearance items[]; } clearance;
// Per pixel (visible_disk.comp): the kernel's mass over the part of the disk where the sample's
// own surface exists and is seen; 1 when `visible_disk` is off.
layout(set = 1, binding = 15, rgba32f) uniform readonly image2D disk_mass;
// Per photon, its position alone (splat.comp copies it): what the distance test reads.
layout(set = 1, binding = 12, std430) readonly buffer PhotonPositions { PhotonPosition positions[]; } photon_positions;
// Per tile of pixels (sample_clearance.comp): a clear ball, its centre in .xyz and radius in
// .w, and its plane: the normal, and the height a segment must stay above in .w.
layout(set = 1, binding = 16, rgba32f) uniform readonly image2D sample_clearance;
layout(set = 1, binding = 17, rgba32f) uniform readonly image2D sample_clearance_plane;
// Per tile (segment_entries.comp): a region, the count of its entries (in the low corner's .w),
// and the BVH nodes a traversal of a segment inside it starts from.
layout(set = 1, binding = 18, rgba32f) uniform readonly image2D segment_region_lo;
layout(set = 1, binding = 19, rgba32f) uniform readonly image2D segment_region_hi;
layout(set = 1, binding = 20, rgba32ui) uniform readonly uimage2D segment_entries;

// The traversal's work counts (trace_compute.glsl) exist in every variant, so that one
// specialization serves both backends: ray queries count nothing.
#if !defined(TRACE_COMPUTE)
#ifdef LEAKLESS_REFLECTION
#define TRACE_COUNT_WORK false
#else
layout(constant_id = 10) const bool TRACE_COUNT_WORK = false;
#endif
uint trace_nodes_visited = 0u;
uint trace_triangles_tested = 0u;
#endif

#ifdef LEAKLESS_REFLECTION
#define LIST_PHOTON(I) list_photons.photons[I]
#define PHOTON_POSITION(I) photon_positions.positions[I]
#define PHOTON(I) photons.photons[I]
#define CLEARANCE(I) clearance.items[I]
#else
ARRAY_AT(ListPhotonsAt, uint, 4);
ARRAY_AT(PhotonPositionsAt, PhotonPosition, 16);
ARRAY_AT(PhotonsAt, Photon, 16);
ARRAY_AT(ClearancesAt, Clearance, 16);
#define LIST_PHOTON(I) ListPhotonsAt(params.list_photons_address).values[I]
#define PHOTON_POSITION(I) PhotonPositionsAt(params.positions_address).values[I]
#define PHOTON(I) PhotonsAt(params.photons_address).values[I]
#define CLEARANCE(I) ClearancesAt(params.clearance_address).values[I]
#endif

// Visibility segments run from the lifted sample `from` to a point straight above the photon,
// at half its lift: on the photon's side of its own surface (a segment arriving from behind a
// zero-thickness wall still crosses it), and on the photon's side of everything else too.
// Ending it short of the photon along the segment instead would carry the end across a wall
// standing within that distance of the photon (a photon at the foot of a sealed partition,
// seen from the other room).
vec3 segment_end(Photon ph, Clearance photon_clearance) {
    return mix(ph.position, photon_clearance.lifted, 0.5);  // lifted = offset_ray(position, normal)
}

// The sample's side of a proof: how far along a segment from `from` a clear ball reaches (0: not
// at all), and its plane: a segment inside the ball is clear where dot(v, normal) > height.
struct SampleBall {
    float reach;
    vec3 normal;
    float height;
};

// Whether the two balls prove the segment clear without a ray (see the top): it leaves the
// sample's ball at `exit` (its end, if it never does), above the sample's plane, and from there
// runs inside the photon's ball (around `lifted`, which the end is half a lift from) and at
// least 2τ above the photon's surface. Without the sample's ball, `exit` is `from`.
bool proven_clear(vec3 from, Photon ph, Clearance photon_clearance, SampleBall ball) {
    if (params.prove_clear == 0u) {
        return false;
    }
    vec3 d = segment_end(ph, photon_clearance) - from;
    float len = sqrt(dot(d, d));
    float t = len > ball.reach ? ball.reach / len : 1.0;
    vec3 exit = from + d * t;
    if (t > 0.0 && !(dot(exit, ball.normal) > ball.height)) {
        exit = from;  // it may dip toward the sample's plane: the photon's ball alone
        t = 0.0;
    }
    if (t == 1.0) {
        return true;
    }
    vec3 lifted = photon_clearance.lifted;
    float lift = dot(lifted - ph.position, ph.normal);
    vec3 exit_lifted = lifted - exit;
    return dot(exit_lifted, exit_lifted) < photon_clearance.radius * photon_clearance.radius
        && 0.5 * lift < photon_clearance.radius && dot(from - ph.position, ph.normal) > 0.5 * lift;
}

// Whether a ray along the segment meets nothing. Both ends stand above the photon's plane
// (the end by half its lift, `from` where the sample is on the photon's side of it): the
// traversal passes over every box below the plane half-way up to the lower end, such as the
// floor the segment grazes, whose leaves it would otherwise enter all along (trace_compute.glsl).
// Half the height keeps the plane clear of both by far more than the rounding of the heights
// and of a box's corner against it: the lift is 256 float ULPs of the position, the rounding a
// few.
bool segment_clear(vec3 from, ivec2 tile, Photon ph, Clearance photon_clearance, inout uvec2 occluder) {
    vec3 end = segment_end(ph, photon_clearance);
    vec3 d = end - from;
    float dist = sqrt(dot(d, d));
    if (!(dist > 0.0)) {
        return true;
    }
#ifdef TRACE_COMPUTE
    float low = min(dot(end - ph.position, ph.normal), dot(from - ph.position, ph.normal));
    float magnitude = max(max(max(abs(from.x), abs(from.y)), abs(from.z)),
                          max(max(abs(ph.position.x), abs(ph.position.y)), abs(ph.position.z)));
    bool above = low > magnitude * (32.0 / 8388608.0);  // 32 ULPs of the largest coordinate
    trace_cull_plane = above ? vec4(ph.normal, dot(ph.position, ph.normal) + 0.5 * low) : vec4(0.0, 0.0, 0.0, -3.0e38);
    // A segment in its tile's region walks from the tile's entries, past the steps from the
    // root down to them that every segment of the tile shares (segment_entries.comp).
    if (params.segment_entries != 0u) {
        vec4 lo = imageLoad(segment_region_lo, tile);
        vec3 hi = imageLoad(segment_region_hi, tile).xyz;
        if (all(greaterThanEqual(min(from, end), lo.xyz)) && all(lessThanEqual(max(from, end), hi))) {
            uvec4 entries = imageLoad(segment_entries, tile);
            return !trace_bvh_occluded_cached_from(from, d / dist, 0.0, dist, entries, uint(lo.w), occluder);
        }
    }
#endif
    return !traceOccludedCached(from, d / dist, 0.0, dist, occluder);
}

// int64(v), truncated as a conversion truncates, for 0 <= v < 2^63, without a conversion
// instruction: LLVM 15 turns a vector of float-to-integer conversions (saturating, as
// lavapipe emits them) into one scalar conversion a lane, and those were a third of the
// splat's gather on lavapipe. v is cut into three integers below 2^21, each exact in a float,
// and each read from the bits of 2^23 + it (a float of exponent 23 holds an integer below
// 2^23 in its mantissa).
int64_t fixed_point(float v) {
    float top = floor(v * (1.0 / 4398046511104.0));           // v / 2^42
    float rest = v - top * 4398046511104.0;                   // exact: below 2^42, 23 bits
    float mid = floor(rest * (1.0 / 2097152.0));              // rest / 2^21
    float low = floor(rest - mid * 2097152.0);                // exact before the floor
    ivec3 parts = floatBitsToInt(vec3(top, mid, low) + 8388608.0) - 0x4B000000;
    return (int64_t(parts.x) << 42) + (int64_t(parts.y) << 21) + int64_t(parts.z);
}

i64vec3 contribution_of(Photon ph, float d, float r) {
    vec3 v = ph.flux * (biweight(d, r) * params.fixed_scale);
    return i64vec3(fixed_point(v.x), fixed_point(v.y), fixed_point(v.z));
}

// The subgroup's walk (see main): a specialization constant the device tuning sets where the
// device has subgroup arithmetic in compute shaders; without it every lane walks alone, and
// these are the lane's own values (WALK_READ(X, K) of lane K's X). naga parses no subgroup
// operation (counters.glsl).
#ifdef LEAKLESS_REFLECTION
#define SHARED_WALK false
#define subgroupMin(X) (X)
#define subgroupMax(X) (X)
#define WALK_LANE 0u
#define WALK_WIDTH 1u
#define WALK_READ(X, K) (X)
#define subgroupExclusiveAdd(X) 0u
#define subgroupBarrier()
#define subgroupMemoryBarrierShared()
#define WALK_CLUSTERED false
#define WALK_CLUSTER 1u
#define SUBGROUP_WIDTH 1u
#define SUBGROUP_LANE 0u
#define SUBGROUP_READ(X, K) (X)
#else
#extension GL_KHR_shader_subgroup_shuffle : require
layout(constant_id = 3) const bool SHARED_WALK = false;
// Where a subgroup spans several leaves (a GPU's 32 lanes, leaves of 8), its lanes walk in
// clusters of WALK_CLUSTER aligned lanes, a leaf's samples each, every cluster its own lists
// side by side; 0: the whole subgroup is one cluster (a subgroup no wider than a leaf). The
// clusters' reductions and shuffles stay within the cluster, in the subgroup's uniform control
// flow: a cluster that has nothing to do this round takes part with values nobody uses.
layout(constant_id = 11) const uint WALK_CLUSTER = 0u;
#define WALK_CLUSTERED (SHARED_WALK && WALK_CLUSTER != 0u)
#define WALK_WIDTH (WALK_CLUSTERED ? WALK_CLUSTER : SUBGROUP_WIDTH)
#define WALK_LANE (WALK_CLUSTERED ? gl_SubgroupInvocationID & (WALK_CLUSTER - 1u) : SUBGROUP_LANE)
#define WALK_READ(X, K) (WALK_CLUSTERED ? subgroupShuffle(X, (gl_SubgroupInvocationID & ~(WALK_CLUSTER - 1u)) + (K)) : SUBGROUP_READ(X, K))
// The subgroup's, for the walk's loop and the pooled trace.
#define SUBGROUP_WIDTH (SHARED_WALK ? gl_SubgroupSize : 1u)
#define SUBGROUP_LANE (SHARED_WALK ? gl_SubgroupInvocationID : 0u)
#define SUBGROUP_READ(X, K) (SHARED_WALK ? subgroupShuffle(X, K) : (X))
#endif
#define SUBGROUP_ANY(X) (SHARED_WALK ? subgroupMax(uint(X)) != 0u : (X))
// Whether any cluster of the subgroup has X, X the same across each cluster: without clusters,
// X itself (a reduction costs lavapipe more than the branch on it).
#define CLUSTERS_ANY(X) (WALK_CLUSTERED ? SUBGROUP_ANY(X) : (X))
#define WALK_MIN(X) (WALK_CLUSTERED ? cluster_min(X, WALK_CLUSTER) : SHARED_WALK ? subgroupMin(X) : (X))
#define WALK_ANY(X) (WALK_CLUSTERED ? cluster_min(uint(!(X)), WALK_CLUSTER) == 0u : SUBGROUP_ANY(X))

#include "cluster.glsl"

// Segments the clearance cannot prove wait in a queue and are traced together once it is full
// and after the walk. Traced where they arise, a SIMD group's lanes (the samples of one leaf,
// walking the same lists) waited for whichever lane had a ray at that photon: with a tenth of
// the segments unproven, more than half the steps of an 8-lane group traced a ray for one or
// two lanes. Queued, the lanes trace their own segments side by side. RAY_QUEUE entries a lane
// (the device tuning's).
//
// With SHARED_WALK the queues live in shared memory (RAY_POOL words: RAY_QUEUE for each thread
// of the workgroup) and a subgroup traces them as one pool, each lane an equal share of all
// its lanes' segments: a lane's own queue holds what its sample's edges and walls left
// unproven, and lanes that trace their own wait for the longest of them. Without it (the lanes walk
// apart, so they reach the trace at different times) each lane keeps its queue in its own
// local memory and traces it alone: 4 bytes an entry, cheap on a CPU, scarce on a GPU.
#ifdef LEAKLESS_REFLECTION
const uint RAY_QUEUE = 64u;  // naga sizes no array by a specialization constant
const uint RAY_POOL = 1u;
#define POOL_LANE 0u
#define POOL_WAIT false
#else
layout(constant_id = 2) const uint RAY_QUEUE = 64u;
layout(constant_id = 6) const uint RAY_POOL = 1u;
// The thread's place in the workgroup by its subgroup (the tuning makes the workgroup a whole
// number of subgroups), so that a lane finds the queue of lane k of its subgroup at POOL_LANE
// − own lane + k.
#define POOL_LANE (gl_SubgroupID * gl_SubgroupSize + gl_SubgroupInvocationID)
// Whether the subgroup's lanes wait for each other between writing and reading the pool: on a
// GPU a subgroup's lanes need not run in step. The device tuning leaves the wait out on a CPU
// driver, whose subgroup is one SIMD vector of lanes that cannot be out of step, and where
// lavapipe makes a subgroup's execution barrier the workgroup's: subgroups that trace their
// pools different numbers of times then lost samples (tuning.rs).
layout(constant_id = 7) const bool POOL_WAIT = true;
#endif
#define POOL_BARRIER() \
    subgroupMemoryBarrierShared(); \
    if (POOL_WAIT) { \
        subgroupBarrier(); \
    }

// The estimator, fixed per pipeline (gather.rs makes one per method) rather than pushed: code a
// method never runs is then compiled out, not stepped over with every lane masked off, which is
// what a CPU driver's SIMD lanes do with a branch (the splat's gather took 1.3x as long with the
// visibility code in it on lavapipe), and which costs a GPU registers. The reflection twin,
// whose expressions of specialization constants naga does not parse, takes every path.
#ifdef LEAKLESS_REFLECTION
#define VISIBILITY true
#define VISIBLE_DISK true
#else
layout(constant_id = 4) const bool VISIBILITY = false;    // a visibility segment to every photon
layout(constant_id = 5) const bool VISIBLE_DISK = false;  // own-surface photons over disk_mass
#endif
uint queue[RAY_QUEUE];     // photons whose segments wait for a ray (the lane's own)
shared uint pool[RAY_POOL];  // the same, every thread's, RAY_QUEUE apart (SHARED_WALK)
// A pooled entry's top bit: its segment is blocked (photon indices stay below 2^26, since a
// photon buffer is at most maxStorageBufferRange, 2^32 bytes, of 64-byte photons).
const uint POOL_BLOCKED = 0x80000000u;

void queue_push(inout uint queued, uint index) {
    if (SHARED_WALK) {
        pool[POOL_LANE * RAY_QUEUE + queued] = index;
    } else {
        queue[queued] = index;
    }
    queued += 1u;
}

// The queued photon's contribution to the kept or the lost sum.
void count_queued(uint index, bool clear, vec3 x, float r, inout i64vec3 kept, inout i64vec3 lost,
                  inout uint occluded) {
    Photon ph = PHOTON(index);
    i64vec3 contribution = contribution_of(ph, distance(x, ph.position), r);
    if (clear) {
        kept += contribution;
    } else {
        occluded += 1u;
        lost += contribution;
    }
}

// Traces the segments of this lane's queue, or (SHARED_WALK) of its subgroup's queues together,
// and counts each photon for its own sample. In uniform control flow when pooled.
void trace_queued(uint count, vec3 x, vec3 from, ivec2 tile, float r, inout i64vec3 kept,
                  inout i64vec3 lost, inout uint occluded, inout uvec2 occluder) {
    if (!SHARED_WALK) {
        for (uint i = 0u; i < count; ++i) {
            uint index = queue[i];
            count_queued(index, segment_clear(from, tile, PHOTON(index), CLEARANCE(index), occluder), x, r,
                         kept, lost, occluded);
        }
        return;
    }
    // The subgroup's segments in lane order, lane k's from `start` of lane k; in round i the
    // lanes trace segments i·W to i·W + W − 1, mostly consecutive segments of one sample: rays
    // from one point to nearby photons, which walk much the same nodes side by side.
    uint start = subgroupExclusiveAdd(count);
    uint total = subgroupAdd(count);
    if (total == 0u) {
        return;
    }
    uint per = (total + SUBGROUP_WIDTH - 1u) / SUBGROUP_WIDTH;
    uint lanes_base = POOL_LANE - SUBGROUP_LANE;
    POOL_BARRIER();  // every lane's queue is written
    for (uint i = 0u; i < per; ++i) {
        uint j = i * SUBGROUP_WIDTH + SUBGROUP_LANE;
        uint owner = 0u;  // the lane whose queue holds segment j: the last whose run starts at or before it
        for (uint k = 1u; k < SUBGROUP_WIDTH; ++k) {
            owner += j >= SUBGROUP_READ(start, k) ? 1u : 0u;
        }
        vec3 owner_from = SUBGROUP_READ(from, owner);
        ivec2 owner_tile = SUBGROUP_READ(tile, owner);
        uint owner_start = SUBGROUP_READ(start, owner);
        if (j < total) {
            uint slot = (lanes_base + owner) * RAY_QUEUE + (j - owner_start);
            uint index = pool[slot];
            if (!segment_clear(owner_from, owner_tile, PHOTON(index), CLEARANCE(index), occluder)) {
                pool[slot] = index | POOL_BLOCKED;
            }
        }
    }
    POOL_BARRIER();  // every segment is traced
    for (uint i = 0u; i < count; ++i) {
        uint entry = pool[POOL_LANE * RAY_QUEUE + i];
        count_queued(entry & ~POOL_BLOCKED, (entry & POOL_BLOCKED) == 0u, x, r, kept, lost, occluded);
    }
    // A lane writes only its own queue until the next pooled trace's first barrier, and reads
    // only its own here: no third barrier.
}

void main() {
    uint s = gl_GlobalInvocationID.x;
    // A lane without a surface to gather for still takes part in its subgroup's walk (it reads
    // list entries for the others) and stops at the end.
    bool in_range = s < params.sample_count;
    uint pixel = in_range ? sorted_samples.pixels[s] : 0u;
    ivec2 xy = ivec2(pixel % params.image_width, pixel / params.image_width);
    bool valid = in_range && sorted_keys.keys[s] != INVALID_SAMPLE_KEY;
    vec4 position = imageLoad(gbuffer_position, xy);
    vec3 x = position.xyz;
    vec3 n = imageLoad(gbuffer_normal, xy).xyz;
    vec4 disk = VISIBLE_DISK ? imageLoad(disk_mass, xy) : vec4(1.0, params.radius, 0.0, 0.0);
    float r = disk.y;
    vec3 from = x;
    vec3 ng = n;
    float curvature = 0.0;
    if (valid && VISIBILITY) {
        uint triangle = uint(position.w) - 1u;
        ng = sample_geometric_normal(triangle, n);
        from = sample_segment_start(x, ng, params.eye);
        if (VISIBLE_DISK) {
            curvature = convex_curvature(triangle, ng);
            // On a convex curved mesh a straight segment to a photon on a neighbouring facet is
            // a chord through the solid. Lifted by κr² it passes over the facets between: a
            // sphere point at angle θ is seen from outside its face from R(1/cos θ − 1) above
            // the sample, and κr² = 2R(1 − cos θ) at chord r covers that up to θ = 60°, beyond
            // which the normal test drops the photons anyway. visible_disk.comp traced the lift
            // (.a) and stopped it short of anything in front of the surface. 0 on flat faces.
            if (disk.w > 0.0) {
                from += disk.w * ng;
            }
        }
    }
    // A ball proves as much for any start inside it and above its plane, so the samples of a
    // tile share the ball of its middle sample (sample_clearance.comp), and each takes its own
    // tile's or a neighbour's, whichever reaches farthest: its radius less how far the start
    // stands from its centre, with a margin for rounding (the segment up to there is inside).
    SampleBall ball = SampleBall(0.0, ng, 0.0);
    if (valid && VISIBILITY && params.prove_clear != 0u) {
        ivec2 tile = xy / int(params.sample_clearance_tile);
        ivec2 tiles = imageSize(sample_clearance);
        for (int dy = -1; dy <= 1; ++dy) {
            for (int dx = -1; dx <= 1; ++dx) {
                ivec2 t = clamp(tile + ivec2(dx, dy), ivec2(0), tiles - 1);
                vec4 sample_ball = imageLoad(sample_clearance, t);
                vec4 plane = imageLoad(sample_clearance_plane, t);
                float reach = dot(from, plane.xyz) > plane.w ? 0.999 * sample_ball.w - distance(from, sample_ball.xyz) : 0.0;
                if (reach > ball.reach) {
                    ball = SampleBall(reach, plane.xyz, plane.w);
                }
            }
        }
    }
    i64vec3 kept = i64vec3(0);
    i64vec3 lost = i64vec3(0);
    uint candidates = 0u;
    uint accepted = 0u;
    uint occluded = 0u;
    uint proven = 0u;
    uvec2 occluder = uvec2(NO_HIT);  // the surface that blocked this sample's last blocked segment
    uint queued = 0u;
    bool capped = false;
    bool done = !valid;  // capped, or nothing to gather
    // The lists of the leaf and its ancestors, walked as one sequence of (level, node, entry)
    // that stops whenever a queue is full, so the traversal has a single call site (inlined
    // twice, it made the pass slower than tracing where segments arise). A list is a run of
    // photon indices: the next entry's address does not wait on this one's load.
    //
    // With SHARED_WALK the lanes of a cluster (the subgroup, or WALK_CLUSTER lanes of it) walk
    // together: each round takes the lowest node any lane of the cluster still has to walk at
    // this level, and the list is read a cluster's width at a time, each lane reading one entry
    // and its photon (one coalesced read on a GPU; on a CPU driver, where a load whose address
    // differs between lanes costs a branch per lane, a chunk is read once instead of once per
    // lane), which every lane then takes in turn from the lane that read it (a shuffle: one
    // permute on lavapipe). The lanes of that node test them. The samples of a leaf are
    // consecutive, so a cluster no wider than the leaf walks one list a level; a wider one
    // walks its leaves in turn. Without it each lane walks its own lists, an entry at a time.
    // Either way each lane tests the same photons in the same order, and a chunk is taken only
    // while every lane's queue has room for all of it (the subgroup traces its queues as one).
    uint level = 0u;
    uint e = 0u;
    uint end = 0u;
    uint my_node = 0u;
    bool to_walk = false;  // this lane's node at this level is not walked yet
    bool mine = false;     // the list walked is this lane's
    bool walked = false;          // every lane of the subgroup has walked all its lists
    bool cluster_walked = false;  // this lane's cluster has
    while (true) {
        while (true) {
            // A cluster at the end of a list takes its next node, or its next level, in a round
            // of its own: every lane (the clusters walking on too) runs the round's reductions,
            // so that they stay in the subgroup's uniform control flow.
            bool at_end = e == end && !cluster_walked;
            if (CLUSTERS_ANY(at_end)) {
                bool to_walk_here = WALK_ANY(to_walk);
                bool live = WALK_ANY(!done);
                if (at_end && !to_walk_here) {
                    if (level == params.level_count || !live) {
                        cluster_walked = true;
                    } else {
                        Level lv = levels.levels[level++];
                        my_node = lv.offset + s / lv.span;
                        to_walk = !done;
                    }
                }
                uint node = WALK_MIN(to_walk ? my_node : 0xffffffffu);
                if (at_end && !cluster_walked) {
                    mine = to_walk && my_node == node;
                    to_walk = to_walk && !mine;
                    e = node == 0u ? 0u : node_ends.ends[node - 1u];
                    end = node_ends.ends[node];
                }
                if (!CLUSTERS_ANY(!cluster_walked)) {
                    walked = true;
                    break;
                }
                continue;
            }
            uint count = min(min(end - e, WALK_WIDTH), RAY_QUEUE);  // 0 where the cluster is done
            if (SUBGROUP_ANY(queued + count > RAY_QUEUE)) {
                break;
            }
            // Lane k reads entry e + k of the list and what is tested of its photon; the lanes
            // then take each entry from the lane that read it (WALK_READ), in list order. Walking
            // alone, a lane reads its entry's position, and the rest only within the radius.
            uint lane_photon = 0u;
            vec3 lane_position = vec3(0.0);
            Photon lane_ph;
            Clearance lane_clearance;
            if (WALK_LANE < count) {
                lane_photon = LIST_PHOTON(e + WALK_LANE);
                lane_position = PHOTON_POSITION(lane_photon).position;
                if (SHARED_WALK) {
                    lane_ph = PHOTON(lane_photon);
                    if (VISIBILITY) {
                        lane_clearance = CLEARANCE(lane_photon);
                    }
                }
            }
            e += count;
            // Clusters read chunks of different lengths: each round shuffles in every cluster.
            uint rounds = WALK_CLUSTERED ? subgroupMax(count) : count;
            for (uint k = 0u; k < rounds; ++k) {
                uint index = WALK_READ(lane_photon, k);
                Photon ph;
                ph.position = WALK_READ(lane_position, k);
                Clearance photon_clearance;
                if (SHARED_WALK) {  // in uniform control flow: every lane's values are there to read
                    ph.normal = WALK_READ(lane_ph.normal, k);
                    ph.direction = WALK_READ(lane_ph.direction, k);
                    ph.flux = WALK_READ(lane_ph.flux, k);
                    if (VISIBILITY) {
                        photon_clearance.lifted = WALK_READ(lane_clearance.lifted, k);
                        photon_clearance.radius = WALK_READ(lane_clearance.radius, k);
                    }
                }
                if (mine && !done && (!WALK_CLUSTERED || k < count)) {
                    candidates += 1u;
                    // Most candidates fail on distance alone: read the rest of the photon after it.
                    float d = distance(x, ph.position);
                    if (d < r) {
                        if (!SHARED_WALK) {
                            ph = PHOTON(index);
                        }
                        if (dot(n, -ph.direction) > 0.0
                            && (!VISIBLE_DISK || on_own_surface(x, ng, curvature, ph.position, ph.normal))) {
                            if (params.cap != 0u && accepted == params.cap) {
                                capped = true;
                                done = true;
                            } else {
                                accepted += 1u;
                                if (VISIBILITY && !SHARED_WALK) {
                                    photon_clearance = CLEARANCE(index);
                                }
                                if (VISIBILITY && !proven_clear(from, ph, photon_clearance, ball)) {
                                    queue_push(queued, index);
                                } else {
                                    proven += VISIBILITY ? 1u : 0u;
                                    kept += contribution_of(ph, d, r);
                                }
                            }
                        }
                    }
                }
            }
        }
        trace_queued(queued, x, from, xy / int(params.sample_clearance_tile), r, kept, lost, occluded, occluder);
        queued = 0u;
        if (walked) {
            break;
        }
    }
    // Every lane counts what it traced, for its own sample or (pooled) for another's.
    if (TRACE_COUNT_WORK) {
        ADD64(gather_counters.ray_nodes_lo, gather_counters.ray_nodes_hi, trace_nodes_visited);
        ADD64(gather_counters.ray_triangles_lo, gather_counters.ray_triangles_hi, trace_triangles_tested);
    }
    if (!in_range) {
        return;
    }
    if (!valid) {
        imageStore(indirect_sum, xy, vec4(0.0, 0.0, 0.0, 1.0));
        imageStore(leaked, xy, vec4(0.0));
        imageStore(gather_counts, xy, vec4(0.0));
        return;
    }
    vec3 albedo_over_pi = imageLoad(gbuffer_albedo, xy).rgb / PI;
    float mass = disk.x;
    // .a carries the mass on: accumulation divides summed flux by summed mass (accumulate.comp).
    imageStore(indirect_sum, xy, vec4(albedo_over_pi * vec3(kept) / (params.fixed_scale * mass), mass));
    imageStore(leaked, xy, vec4(albedo_over_pi * vec3(lost) / params.fixed_scale, 1.0));
    float rays = VISIBILITY ? float(accepted - proven) : 0.0;
    imageStore(gather_counts, xy, vec4(float(candidates), rays, float(occluded), 0.0));
    ADD_COUNT(gather_counters.valid_samples, 1u);
    ADD_COUNT(gather_counters.capped_samples, capped ? 1u : 0u);
    ADD64(gather_counters.candidates_lo, gather_counters.candidates_hi, candidates);
    ADD64(gather_counters.accepted_lo, gather_counters.accepted_hi, accepted);
    ADD64(gather_counters.occluded_lo, gather_counters.occluded_hi, occluded);
    ADD64(gather_counters.proven_lo, gather_counters.proven_hi, proven);
    MAX_COUNT(gather_counters.candidates_most, candidates);
}
