// The cells the emission order groups light paths by (crates/renderer/src/passes/emission_order.rs): a 256×256
// grid over the emission sample's square (dimensions 0 and 1 of the path's low-discrepancy
// emission sample: where on a directional light's disk, or which direction from a point or
// spot light), numbered in Morton order so that consecutive cells are neighbours.
#ifndef LEAKLESS_EMISSION_CELL_GLSL
#define LEAKLESS_EMISSION_CELL_GLSL

#include "common.glsl"
#include "lowdiscrepancy.glsl"

// Mirrored in crates/renderer/src/passes/emission_order.rs (CELL_BITS).
#define EMISSION_CELL_BITS 8u

#define EMISSION_ORDER_PARAMS_BLOCK layout(push_constant) uniform EmissionOrderParams { \
    uint paths; \
    uint path_offset; /* index of path 0 in the sequence (photons.comp) */ \
    uint seed; \
    uint pad0; \
} params

// The cell of path `path`: photons.comp's `emit` draws the same sample (GROUP_EMISSION = 0).
uint emission_cell(uint path, uint path_offset, uint seed) {
    vec2 u = ld_sample3(path + path_offset, 0u, seed).xy;
    uint side = 1u << EMISSION_CELL_BITS;
    uvec2 c = min(uvec2(u * float(side)), uvec2(side - 1u));
    return (spread_cell_bits(c.x, EMISSION_CELL_BITS, 2u) << 1u) | spread_cell_bits(c.y, EMISSION_CELL_BITS, 2u);
}

#endif
