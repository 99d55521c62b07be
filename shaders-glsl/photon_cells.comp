#version 460
// Photon order, step 1: how many stored photons lie in each cell (photon_cell.glsl). The
// counts become each cell's first slot by an exclusive scan (sort_scan.comp), and
// photon_order.comp then moves every photon into its cell's range.
#include "common.glsl"
#include "photon.glsl"
#include "photon_cell.glsl"

layout(local_size_x = 64) in;

PHOTON_ORDER_PARAMS_BLOCK;
layout(set = 0, binding = 0, std430) readonly buffer Photons { Photon photons[]; } photons;
layout(set = 0, binding = 1, std430) readonly buffer PhotonCounters { uint stored; uint overflowed; uint rays; uint next_path; } photon_counters;
layout(set = 0, binding = 2, std430) buffer CellCounts { uint data[]; } cell_counts;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= min(photon_counters.stored, params.capacity)) {
        return;
    }
    atomicAdd(cell_counts.data[photon_cell(photons.photons[i].position, params.bounds_min, params.bounds_max)], 1u);
}
