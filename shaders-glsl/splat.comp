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
    return node.level == 0u ? TAKE : DESCEND;
}

void main() {
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
