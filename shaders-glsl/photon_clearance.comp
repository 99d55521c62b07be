#version 460
// Photon clearance: for each stored photon, the ball around its lifted position (where the
// gather's visibility segments end) that holds no geometry the gather's segments could meet.
// The gather uses it to prove a segment clear without tracing it (see gather.comp): a segment
// inside the ball that stays above a plane just over the photon's surface meets no triangle
// lying wholly on or under that plane.
//
// The plane is dot(v − p, n) = τ, with p the photon, n its geometric normal (facing where it
// came from) and τ a quarter of the lift of p above its surface. Triangles with all three
// vertices on or under it (the photon's own surface, anything coplanar, and everything behind
// it, such as the far face of a floor slab) are left out; the radius is the distance to the
// nearest other triangle, at most `max_radius`, made smaller by a margin that covers float
// rounding, so it never exceeds the true clearance.
//
// With `only_listed`, photons no node list took (out of view, or facing away from every
// sample: about a third of the atrium's) get radius 0 without a search: the gather never
// reads them, and the search is a BVH walk per photon.
#include "common.glsl"
#include "photon.glsl"
#include "clearance_search.glsl"

layout(local_size_x = 64) in;

layout(set = 1, binding = 0, std430) readonly buffer Photons { Photon photons[]; } photons;
layout(set = 1, binding = 1, std430) readonly buffer PhotonCounters { uint stored; uint overflowed; uint rays; uint next_path; } photon_counters;
layout(set = 1, binding = 2, std430) writeonly buffer Clearances { Clearance items[]; } clearance;
layout(set = 1, binding = 3, std430) readonly buffer PhotonListed { uint listed[]; } photon_listed;
layout(push_constant) uniform ClearanceParams {
    float max_radius;    // no segment of the gather is longer than this
    uint capacity;       // photons the buffers hold
    uint only_listed;    // 1: search only for photons with photon_listed set (splat.comp)
    uint pad1;
} params;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= min(photon_counters.stored, params.capacity)) {
        return;
    }
    Photon ph = photons.photons[i];
    vec3 q = offset_ray(ph.position, ph.normal);
    if (params.only_listed != 0u && photon_listed.listed[i] == 0u) {
        clearance.items[i] = Clearance(q, 0.0);  // proves nothing, and nothing asks
        return;
    }
    ClearancePlane plane = ClearancePlane(ph.position, ph.normal, 0.25 * dot(q - ph.position, ph.normal));
    clearance.items[i] = Clearance(q, clearance_radius(q, plane, params.max_radius));
}
