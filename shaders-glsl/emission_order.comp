#version 460
// Emission order, step 2: every path index goes to the next free slot of its cell's range, so
// photons.comp's neighbouring threads start neighbouring paths (emission_order.rs).
#include "emission_cell.glsl"

layout(local_size_x = 64) in;

EMISSION_ORDER_PARAMS_BLOCK;
layout(set = 1, binding = 0, std430) buffer CellStarts { uint data[]; } cell_starts;
layout(set = 1, binding = 1, std430) writeonly buffer PathOrder { uint paths[]; } path_order;

void main() {
    uint path = gl_GlobalInvocationID.x;
    if (path < params.paths) {
        // The same cell as emission_cells.comp's, bit for bit: integer work, and a scaling by a
        // power of two (emission_cell.glsl). The guard only keeps a mistake in bounds.
        uint slot = atomicAdd(cell_starts.data[emission_cell(path, params.path_offset, params.seed)], 1u);
        if (slot < params.paths) {
            path_order.paths[slot] = path;
        }
    }
}
