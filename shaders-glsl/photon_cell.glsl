// The cells the photon order groups photons by (crates/renderer/src/passes/photon_order.rs): a 32³ grid over
// the scene's bounds, numbered in Morton order so that consecutive cells are neighbours.
#ifndef LEAKLESS_PHOTON_CELL_GLSL
#define LEAKLESS_PHOTON_CELL_GLSL

#include "common.glsl"

// Mirrored in crates/renderer/src/passes/photon_order.rs (CELL_BITS).
#define PHOTON_CELL_BITS 5u
const uint PHOTON_CELL_SIDE = 1u << PHOTON_CELL_BITS;

#define PHOTON_ORDER_PARAMS_BLOCK layout(push_constant) uniform PhotonOrderParams { \
    vec3 bounds_min; \
    uint capacity;   /* photons the buffers hold */ \
    vec3 bounds_max; \
    uint pad0; \
} params

// The cell of a position: outside the bounds (an animated object that moved past them), the
// nearest cell, which only costs coherence.
uint photon_cell(vec3 p, vec3 lo, vec3 hi) {
    vec3 t = clamp((p - lo) / max(hi - lo, vec3(1e-30)), 0.0, 1.0);
    uvec3 c = min(uvec3(t * float(PHOTON_CELL_SIDE)), uvec3(PHOTON_CELL_SIDE - 1u));
    uint b = PHOTON_CELL_BITS;
    return (spread_cell_bits(c.x, b, 3u) << 2u) | (spread_cell_bits(c.y, b, 3u) << 1u) | spread_cell_bits(c.z, b, 3u);
}

#endif
