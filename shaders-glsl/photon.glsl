// A stored photon and the node lists the splat builds. Rust twins: `Photon` in
// crates/renderer/src/passes/photons.rs, `SplatRecord` in crates/renderer/src/passes/splat.rs.
#ifndef LEAKLESS_PHOTON_GLSL
#define LEAKLESS_PHOTON_GLSL

struct Photon {
    vec3 position;
    uint path;       // light path index (0..paths)
    vec3 normal;     // geometric normal, facing the incoming photon
    uint bounce;     // reflections before arriving: 1 = second hit (0 only with store_direct)
    vec3 direction;  // ω_in: the unit direction the photon was travelling
    uint light;      // index of the emitting light
    vec3 flux;       // RGB flux arriving (W)
    uint pad0;
};

// A photon's clearance (photon_clearance.comp): its lifted position, where the gather's
// visibility segments end, and the radius of the ball around it that holds no geometry but
// the photon's own plane.
struct Clearance {
    vec3 lifted;
    float radius;
};

// A photon's position alone (the splat copies it from the photon): the gather's distance test,
// which rejects most candidates, reads these 16 bytes and nothing else of a photon.
struct PhotonPosition {
    vec3 position;
    uint pad0;
};

// What the splat records for each list that takes a photon: the list's node and the photon.
// list_scatter.comp then writes every node's photons contiguously, in node order, so that the
// gather reads a list as one run of words instead of chasing links.
struct SplatRecord {
    uint node;
    uint photon;
};

// The biweight kernel normalised over the disk of radius r: ∫ K dA = 1.
float biweight(float d, float r) {
    float t = 1.0 - (d * d) / (r * r);
    return t <= 0.0 ? 0.0 : 3.0 / (PI * r * r) * t * t;
}

#endif
