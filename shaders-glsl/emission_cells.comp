#version 460
// Emission order, step 1: how many of the frame's paths start in each emission cell
// (emission_cell.glsl); a scan turns the counts into each cell's first slot.
#include "emission_cell.glsl"

layout(local_size_x = 64) in;

EMISSION_ORDER_PARAMS_BLOCK;
layout(set = 1, binding = 0, std430) buffer CellCounts { uint data[]; } cell_counts;

void main() {
    uint path = gl_GlobalInvocationID.x;
    if (path < params.paths) {
        atomicAdd(cell_counts.data[emission_cell(path, params.path_offset, params.seed)], 1u);
    }
}
