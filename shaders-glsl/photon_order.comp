#version 460
// Photon order, step 2: every stored photon is copied to the next free slot of its cell's
// range (`cell_starts`: each cell's first slot, from the scan of photon_cells.comp's counts).
// Neighbouring photons then sit in neighbouring slots, so the threads of one SIMD group in the
// splat and the clearance walk the same nodes instead of diverging (photon_order.rs). Within
// a cell the order follows the atomics; nothing downstream depends on it (the gather's sums
// are order-independent).
#include "common.glsl"
#include "photon.glsl"
#include "photon_cell.glsl"

layout(local_size_x = 64) in;

PHOTON_ORDER_PARAMS_BLOCK;
layout(set = 1, binding = 0, std430) readonly buffer Photons { Photon photons[]; } photons;
layout(set = 1, binding = 1, std430) readonly buffer PhotonCounters { uint stored; uint overflowed; uint rays; uint next_path; } photon_counters;
layout(set = 1, binding = 2, std430) buffer CellStarts { uint data[]; } cell_starts;
layout(set = 1, binding = 3, std430) writeonly buffer OrderedPhotons { Photon photons[]; } ordered_photons;
layout(set = 1, binding = 4, std430) readonly buffer PhotonCellOf { uint data[]; } photon_cell_of;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= min(photon_counters.stored, params.capacity)) {
        return;
    }
    uint slot = atomicAdd(cell_starts.data[photon_cell_of.data[i]], 1u);
    if (slot < params.capacity) {  // always, as the counts and the cells are the same
        ordered_photons.photons[slot] = photons.photons[i];
    }
}
