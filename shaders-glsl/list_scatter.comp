#version 460
// List scatter: writes each splat record's photon into its node's range of the node lists.
// `node_ends` holds the exclusive prefix sum of the nodes' counts (the first slot of each
// node's range) and each record takes the next slot of its node's with an atomic, so once
// every record is placed a node's entry holds the end of its range: node n's photons are
// list_photons[ends[n − 1] .. ends[n]) (from 0 for node 0), contiguous and in node order.
// Within a range, photons stand in the order the atomics gave, as the linked lists' did; the
// gather's fixed-point sums do not depend on it.
//
// The records are walked in a grid-stride loop: a frame may hold more than
// maxComputeWorkGroupCount × 64 of them, and the indirect dispatch (photon_dispatch.comp
// over the splat counters) asks for at most that many workgroups.
#include "common.glsl"
#include "photon.glsl"

layout(local_size_x = 64) in;

layout(set = 1, binding = 0, std430) readonly buffer SplatCounters {
    uint entries_used;
    uint entries_dropped;
    uint nodes_visited;
    uint photons_listed;
} splat_counters;
layout(set = 1, binding = 1, std430) readonly buffer SplatRecords { SplatRecord records[]; } splat_records;
layout(set = 1, binding = 2, std430) buffer NodeEnds { uint ends[]; } node_ends;
layout(set = 1, binding = 3, std430) writeonly buffer ListPhotons { uint photons[]; } list_photons;
layout(push_constant) uniform ListScatterParams {
    uint capacity;  // records the buffers hold: entries_used counts the ones beyond it too
    uint pad0;
    uint pad1;
    uint pad2;
} params;

void main() {
    uint count = min(splat_counters.entries_used, params.capacity);
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    for (uint i = gl_GlobalInvocationID.x; i < count; i += stride) {
        SplatRecord record = splat_records.records[i];
        list_photons.photons[atomicAdd(node_ends.ends[record.node], 1u)] = record.photon;
    }
}
