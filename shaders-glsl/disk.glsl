// What the gather and visible_disk.comp agree on: which photons lie on a view sample's own
// surface, and that surface's normal at the sample.
#ifndef LEAKLESS_DISK_GLSL
#define LEAKLESS_DISK_GLSL

const float DISK_SLOPE = 0.1763;            // tan 10°: the band around the tangent plane
const float DISK_MIN_NORMAL_COSINE = 0.5;   // 60°

// The sample's geometric normal, turned to the side its shading normal `n` faces.
vec3 sample_geometric_normal(uint triangle, vec3 n) {
    vec3 ng = triangle_geometric_normal(triangle);
    return dot(ng, n) < 0.0 ? -ng : ng;
}

// Whether a photon at `p` with normal `pn` lies on the surface of the sample at `x`: facing
// like it, and within DISK_SLOPE of its tangent plane as seen from x.
bool on_own_surface(vec3 x, vec3 ng, vec3 p, vec3 pn) {
    vec3 d = p - x;
    return dot(pn, ng) >= DISK_MIN_NORMAL_COSINE && abs(dot(d, ng)) <= DISK_SLOPE * length(d);
}

#endif
