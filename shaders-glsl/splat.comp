#version 460
// Splat: one thread per photon walks the view-sample hierarchy from the root. A node is
// culled when the photon's sphere misses its bounds or its normal cone faces away from the
// photon. The sphere's radius is the frame's largest gather radius, and where a single frame
// grows partial disks (visible_disk.comp), the node's own largest radius once the frame's
// has not culled it: read only then, since on lavapipe every word a node test loads costs. With trivial accept, a node inside the sphere whose cone faces the photon takes the
// photon onto its list and the walk stops there (the gather still evaluates it per sample);
// otherwise the walk descends and a leaf takes the photon onto its list. Each photon's
// `photon_listed` flag says whether any list took it: only those reach the gather, so only
// their clearance is needed (photon_clearance.comp).
//
// A list taking a photon is recorded (node, photon) and counted on its node; the counts'
// prefix sum gives each node its range and list_scatter.comp fills the ranges, so a list is
// contiguous for the gather. A record that does not fit the capacity is dropped before its
// node counts it, so every range is filled. The photon's position is copied to a compact
// array beside: the distance test that rejects most of the gather's candidates reads 16 bytes
// of it, not a 64-byte photon.
//
// With SPLAT_LANES > 1 (the device tuning's), a cluster of that many aligned lanes of a
// subgroup walks each photon's hierarchy together, each lane testing one child of the node
// being expanded: children are consecutive, so the cluster reads them in one contiguous load,
// and a frame of few photons (a budgeted frame on a GPU traces a few thousand paths) keeps
// SPLAT_LANES times as many threads busy. The walk tests the same nodes, takes the same
// (node, photon) records and counts the same visits; only the records' order differs, which
// the list scatter's atomics already leave open.
#include "common.glsl"
#include "hierarchy.glsl"
#include "photon.glsl"
#include "counters.glsl"
#include "device_address.glsl"

layout(local_size_x = 64) in;

layout(set = 1, binding = 0, std430) readonly buffer Photons { Photon photons[]; } photons;
layout(set = 1, binding = 1, std430) readonly buffer PhotonCounters { uint stored; uint overflowed; uint rays; uint next_path; } photon_counters;
layout(set = 1, binding = 2, std430) readonly buffer Levels { Level levels[]; } levels;
layout(set = 1, binding = 3, std430) readonly buffer Nodes { Node nodes[]; } nodes;
layout(set = 1, binding = 4, std430) buffer NodeCounts { uint counts[]; } node_counts;
layout(set = 1, binding = 5, std430) writeonly buffer SplatRecords { SplatRecord records[]; } splat_records;
layout(set = 1, binding = 6, std430) buffer SplatCounters {
    uint entries_used;      // list entries recorded (and attempted beyond capacity)
    uint entries_dropped;   // entries that did not fit: their contributions are lost
    uint nodes_visited;     // node tests made by all photons
    uint photons_listed;    // photons some list took
} splat_counters;
layout(set = 1, binding = 7, std430) writeonly buffer PhotonListed { uint listed[]; } photon_listed;
layout(set = 1, binding = 8, std430) writeonly buffer PhotonPositions { PhotonPosition positions[]; } photon_positions;
layout(set = 1, binding = 9, std430) readonly buffer SamplePositions { SamplePosition positions[]; } sample_positions;
layout(push_constant) uniform SplatParams {
    float radius;           // the largest radius any sample gathers within
    uint trivial_accept;
    uint root;
    uint capacity;          // entries the record and list buffers hold
    uint photon_capacity;   // photons the photon buffer holds
    uint node_radius;       // 1: samples' radii differ upward; test each node's radius_max
    uvec2 nodes_address;    // `nodes`, read through its address (device_address.rs says why)
} params;

#ifdef LEAKLESS_REFLECTION
#define NODE(I) nodes.nodes[I]
#else
ARRAY_AT(NodesAt, Node, 16);
#define NODE(I) NodesAt(params.nodes_address).values[I]
#endif

// Deep enough for levels·(B−1)+1 pending nodes; the Rust side checks the hierarchy fits.
#define SPLAT_STACK 192

// The lanes that walk one photon (see above). naga parses no subgroup operation
// (counters.glsl): the reflection twin walks a photon a thread.
#ifdef LEAKLESS_REFLECTION
#define LEAF_SAMPLES true
#define SPLAT_LANES 1u
#define CLUSTER_LANE 0u
#define CLUSTER_BASE 0u
#define subgroupShuffle(X, K) (X)
#define subgroupMax(X) (X)
#define SUBGROUP_CLUSTERS 1u
#define FIRST_CLUSTER 0u
#define SUBGROUP_CLUSTER 0u
#define CLUSTER_COUNT (gl_NumWorkGroups.x * gl_WorkGroupSize.x)
#else
#extension GL_KHR_shader_subgroup_shuffle : require
layout(constant_id = 12) const uint SPLAT_LANES = 1u;
layout(constant_id = 13) const bool LEAF_SAMPLES = false;
#define CLUSTER_LANE (gl_SubgroupInvocationID & (SPLAT_LANES - 1u))
#define CLUSTER_BASE (gl_SubgroupInvocationID & ~(SPLAT_LANES - 1u))
#define SUBGROUP_CLUSTERS (gl_SubgroupSize / SPLAT_LANES)
// The subgroup's first cluster among all the dispatch's (by subgroup, not by invocation index,
// whose mapping to subgroups Vulkan leaves open), and this lane's cluster within its subgroup.
#define FIRST_CLUSTER ((gl_WorkGroupID.x * gl_NumSubgroups + gl_SubgroupID) * SUBGROUP_CLUSTERS)
#define SUBGROUP_CLUSTER (gl_SubgroupInvocationID / SPLAT_LANES)
#define CLUSTER_COUNT (gl_NumWorkGroups.x * gl_NumSubgroups * SUBGROUP_CLUSTERS)
#endif

// A pending node of the shared walk: its level above its index, so that the cluster can take
// the deepest (bits 27 and up: the Rust side holds nodes below 2^27 and levels below 32).
#define PENDING_LEVEL_SHIFT 27u
#define PENDING_NODE_MASK ((1u << PENDING_LEVEL_SHIFT) - 1u)

#include "cluster.glsl"

// The angle between the node's cone axis and the direction toward the photon's source side.
float cone_gap(Node node, vec3 toward_light) {
    return acos(clamp(dot(node.cone_axis, toward_light), -1.0, 1.0));
}

void append(uint node, uint photon) {
    uint slot;
    RESERVE_ONE(splat_counters.entries_used, slot);
    if (slot >= params.capacity) {
        atomicAdd(splat_counters.entries_dropped, 1u);
        return;
    }
    splat_records.records[slot] = SplatRecord(node, photon);
    atomicAdd(node_counts.counts[node], 1u);
}


// Whether some sample of `leaf` stands within r of the photon at p: the distance the gather
// tests, from the same G-buffer position (copied by the hierarchy's build), so that no photon
// a sample gathers is left out.
bool near_a_sample(Node leaf, vec3 p, float r) {
    for (uint s = leaf.first_child; s < leaf.first_child + leaf.child_count; ++s) {
        SamplePosition x = sample_positions.positions[s];
        if (x.valid != 0u && distance(x.position, p) < r) {
            return true;
        }
    }
    return false;
}

const uint CULL = 0u;     // the photon reaches no sample of the node
const uint TAKE = 1u;     // the node's list takes the photon
const uint DESCEND = 2u;  // the node's children decide

uint classify(uint index, Node node, Photon ph, float r, vec3 toward_light) {
    if (node.valid_samples == 0u) {
        return CULL;
    }
    // Sphere against box: the squared distance from the photon to the box.
    vec3 nearest = clamp(ph.position, node.bounds_min, node.bounds_max);
    vec3 to_near = ph.position - nearest;
    if (dot(to_near, to_near) >= r * r) {
        return CULL;
    }
    if (params.node_radius != 0u) {
        r = NODE(index).radius_max;
        if (dot(to_near, to_near) >= r * r) {
            return CULL;
        }
    }
    // Every normal of the node within cone_angle of the axis: the gather's facing test
    // dot(n, −ω_in) > 0 fails for all of them when the cone lies beyond 90°.
    float gap = cone_gap(node, toward_light);
    if (gap - node.cone_angle >= 0.5 * PI) {
        return CULL;
    }
    if (params.trivial_accept != 0u) {
        vec3 far = max(abs(ph.position - node.bounds_min), abs(ph.position - node.bounds_max));
        bool enveloped = dot(far, far) < r * r;
        bool facing = gap + node.cone_angle < 0.5 * PI;
        if (enveloped && facing) {
            return TAKE;
        }
    }
    if (node.level != 0u) {
        return DESCEND;
    }
    // A leaf's box bounds its samples however far apart they stand: where the Morton order
    // jumps, a leaf's 8 consecutive samples can lie across the scene, and its box then meets
    // a large share of all photons (40% of them in the atrium), every one a candidate of each
    // of its samples, which a GPU's gather waits for. With LEAF_SAMPLES (the device tuning's),
    // where the box is wider than the radius, the leaf takes only the photons some sample of
    // it can gather; the same work then runs across the photons instead of in a few samples.
    vec3 extent = node.bounds_max - node.bounds_min;
    if (LEAF_SAMPLES && dot(extent, extent) > r * r && !near_a_sample(node, ph.position, r)) {
        return CULL;
    }
    return TAKE;
}

// A photon a cluster (SPLAT_LANES > 1): the cluster expands its deepest pending node, each lane
// testing the children first_child + lane, + lane + SPLAT_LANES, ..., and keeping on a stack of
// its own the ones to descend. Expanding the deepest first, as the thread's stack does, leaves
// at most ⌈B / SPLAT_LANES⌉ nodes of each level on a lane's stack: within SPLAT_STACK wherever
// the thread's walk fits. Clusters loop over the photons (the dispatch may hold fewer than a
// cluster each), and a subgroup loops while any of its clusters has a photon or a node left,
// so that the shuffles stay in its uniform control flow.
void splat_shared() {
    uint stored = min(photon_counters.stored, params.photon_capacity);
    uint lane = CLUSTER_LANE;
    uint clusters = CLUSTER_COUNT;
    uint visited = 0u;
    uint listed_count = 0u;
    for (uint photon_index = FIRST_CLUSTER + SUBGROUP_CLUSTER; subgroupMax(uint(photon_index < stored)) != 0u;
         photon_index += clusters) {
        bool has_photon = photon_index < stored;
        Photon ph = photons.photons[has_photon ? photon_index : 0u];
        float r = params.radius;
        vec3 toward_light = -ph.direction;
        uint stack[SPLAT_STACK];
        uint top = 0u;
        bool listed = false;
        if (has_photon && lane == 0u) {
            photon_positions.positions[photon_index] = PhotonPosition(ph.position, 0u);
            visited += 1u;
            Node root = NODE(params.root);
            uint k = classify(params.root, root, ph, r, toward_light);
            if (k == TAKE) {
                append(params.root, photon_index);
                listed = true;
            } else if (k == DESCEND) {
                stack[top++] = (root.level << PENDING_LEVEL_SHIFT) | params.root;
            }
        }
        while (true) {
            uint key = top > 0u ? ((stack[top - 1u] >> PENDING_LEVEL_SHIFT) << 8u) | lane : 0xffffffffu;
            key = cluster_min(key, SPLAT_LANES);
            if (subgroupMax(uint(key != 0xffffffffu)) == 0u) {
                break;
            }
            bool pending = key != 0xffffffffu;
            uint from = pending ? key & 0xffu : lane;
            uint node = 0u;
            if (pending && from == lane) {
                node = stack[--top] & PENDING_NODE_MASK;
            }
            node = subgroupShuffle(node, CLUSTER_BASE + from);
            if (pending) {
                Node parent = NODE(node);
                uint below = (parent.level - 1u) << PENDING_LEVEL_SHIFT;
                for (uint c = parent.first_child + lane; c < parent.first_child + parent.child_count; c += SPLAT_LANES) {
                    visited += 1u;
                    uint k = classify(c, NODE(c), ph, r, toward_light);
                    if (k == TAKE) {
                        append(c, photon_index);
                        listed = true;
                    } else if (k == DESCEND && top < SPLAT_STACK) {
                        stack[top++] = below | c;
                    }
                }
            }
        }
        // Whether any lane's list took the photon.
        uint any = 1u - cluster_min(listed ? 0u : 1u, SPLAT_LANES);
        if (has_photon && lane == 0u) {
            photon_listed.listed[photon_index] = any;
            listed_count += any;
        }
    }
    ADD_COUNT(splat_counters.nodes_visited, visited);
    ADD_COUNT(splat_counters.photons_listed, listed_count);
}

void main() {
    if (SPLAT_LANES > 1u) {
        splat_shared();
        return;
    }
    uint photon_index = gl_GlobalInvocationID.x;
    if (photon_index >= min(photon_counters.stored, params.photon_capacity)) {
        return;
    }
    Photon ph = photons.photons[photon_index];
    photon_positions.positions[photon_index] = PhotonPosition(ph.position, 0u);
    float r = params.radius;
    vec3 toward_light = -ph.direction;
    // The stack holds nodes already found to need descending: a node is tested before it is
    // pushed, so culled nodes cost no stack traffic.
    uint stack[SPLAT_STACK];
    uint top = 0u;
    uint visited = 1u;
    uint root = classify(params.root, NODE(params.root), ph, r, toward_light);
    bool listed = root == TAKE;
    if (root == TAKE) {
        append(params.root, photon_index);
    } else if (root == DESCEND) {
        stack[top++] = params.root;
    }
    while (top > 0u) {
        Node node = NODE(stack[--top]);
        for (uint c = node.first_child; c < node.first_child + node.child_count; ++c) {
            visited += 1u;
            uint k = classify(c, NODE(c), ph, r, toward_light);
            if (k == TAKE) {
                append(c, photon_index);
                listed = true;
            } else if (k == DESCEND && top < SPLAT_STACK) {
                stack[top++] = c;
            }
        }
    }
    ADD_COUNT(splat_counters.nodes_visited, visited);
    photon_listed.listed[photon_index] = listed ? 1u : 0u;
    ADD_COUNT(splat_counters.photons_listed, listed ? 1u : 0u);
}
