#version 460
// Photon order, step 1: each stored photon's cell (photon_cell.glsl), and how many lie in each.
// The counts become each cell's first slot by an exclusive scan (sort_scan.comp), and
// photon_order.comp then moves every photon into its cell's range. The cell is kept, not
// computed again there: another pipeline may round the division differently on a boundary,
// and a photon counted in one cell but placed in another would overrun that cell's range.
#include "common.glsl"
#include "photon.glsl"
#include "photon_cell.glsl"

layout(local_size_x = 64) in;

PHOTON_ORDER_PARAMS_BLOCK;
layout(set = 1, binding = 0, std430) readonly buffer Photons { Photon photons[]; } photons;
layout(set = 1, binding = 1, std430) readonly buffer PhotonCounters { uint stored; uint overflowed; uint rays; uint next_path; } photon_counters;
layout(set = 1, binding = 2, std430) buffer CellCounts { uint data[]; } cell_counts;
layout(set = 1, binding = 3, std430) writeonly buffer PhotonCellOf { uint data[]; } photon_cell_of;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= min(photon_counters.stored, params.capacity)) {
        return;
    }
    uint cell = photon_cell(photons.photons[i].position, params.bounds_min, params.bounds_max);
    photon_cell_of.data[i] = cell;
    atomicAdd(cell_counts.data[cell], 1u);
}
