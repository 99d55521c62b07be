// The cells the photon order groups photons by (src/passes/photon_order.rs): a 32³ grid over
// the scene's bounds, numbered in Morton order so that consecutive cells are neighbours.
#ifndef LEAKLESS_PHOTON_CELL_GLSL
#define LEAKLESS_PHOTON_CELL_GLSL

// Mirrored in src/passes/photon_order.rs (CELL_BITS).
#define PHOTON_CELL_BITS 5u
const uint PHOTON_CELL_SIDE = 1u << PHOTON_CELL_BITS;

#define PHOTON_ORDER_PARAMS_BLOCK layout(push_constant) uniform PhotonOrderParams { \
    vec3 bounds_min; \
    uint capacity;   /* photons the buffers hold */ \
    vec3 bounds_max; \
    uint pad0; \
} params

// Bit i of v moved to bit 3i.
uint spread_cell_bits(uint v) {
    uint spread = 0u;
    for (uint i = 0u; i < PHOTON_CELL_BITS; ++i) {
        spread |= ((v >> i) & 1u) << (3u * i);
    }
    return spread;
}

// The cell of a position: outside the bounds (an animated object that moved past them), the
// nearest cell, which only costs coherence.
uint photon_cell(vec3 p, vec3 lo, vec3 hi) {
    vec3 t = clamp((p - lo) / max(hi - lo, vec3(1e-30)), 0.0, 1.0);
    uvec3 c = min(uvec3(t * float(PHOTON_CELL_SIDE)), uvec3(PHOTON_CELL_SIDE - 1u));
    return (spread_cell_bits(c.x) << 2u) | (spread_cell_bits(c.y) << 1u) | spread_cell_bits(c.z);
}

#endif
