// What the gather and visible_disk.comp agree on: which photons lie on a view sample's own
// surface, and that surface's normal at the sample.
#ifndef LEAKLESS_DISK_GLSL
#define LEAKLESS_DISK_GLSL

#include "disk_band.glsl"

const float DISK_MIN_NORMAL_COSINE = 0.5;   // 60°
const float SMOOTH_EDGE_COSINE = 0.866;     // 30°: convex_curvature

// The sample's geometric normal, turned to the side its shading normal `n` faces.
vec3 sample_geometric_normal(uint triangle, vec3 n) {
    vec3 ng = triangle_geometric_normal(triangle);
    return dot(ng, n) < 0.0 ? -ng : ng;
}

// How fast the sample's surface curves away below its tangent plane (1/R on a ball of radius
// R seen from outside; 0 on flat faces and on concave ones), read from the triangle's vertex
// normals: along an edge from p to q, (n_q − n_p)·(q − p)/|q − p|² is the normal curvature of
// a surface those normals belong to, and the largest over the three edges is the most convex
// direction. Normals are turned to the side `ng` faces, so a ball seen from inside is concave.
// Flat-shaded triangles (equal vertex normals) give exactly 0, so on them nothing below
// changes by a single bit.
float convex_curvature(uint triangle, vec3 ng) {
    float curvature = 0.0;
    for (uint k = 0u; k < 3u; ++k) {
        uint a = 3u * triangle + k;
        uint b = 3u * triangle + (k + 1u) % 3u;
        vec3 edge = vertex_position(b) - vertex_position(a);
        vec3 bend = vertex_normal(b) - vertex_normal(a);
        float side = dot(vertex_normal(a) + vertex_normal(b), ng) < 0.0 ? -1.0 : 1.0;
        float length2 = dot(edge, edge);
        // Normals more than 30° apart along one edge are a crease smoothed over (a box exported
        // with averaged corner normals), not a curve: read as one, its flat faces would count
        // a step below them, whose photons the segments cannot reach (visible_disk.comp).
        if (length2 > 0.0 && dot(vertex_normal(a), vertex_normal(b)) >= SMOOTH_EDGE_COSINE) {
            curvature = max(curvature, side * dot(bend, edge) / length2);
        }
    }
    return curvature;
}

// How far below the tangent plane the sample's own surface may lie at distance d when it is
// convex with curvature κ > 0: the polygon's edges drop at the angle between neighbouring facets
// (DISK_SLOPE allows 10°), and a sphere lies κd²/2 below it at chord d, taken twice for the
// facets inside it and for curvatures that vary, but no more than R/2, the depth where the
// normal test's 60° ends on a sphere. 0 on flat and concave surfaces, where a surface below the
// plane is another one (a step) whose photons the gather's segments cannot reach. The visible
// disk's probes look this far down and the gather counts photons this far down, lifting its
// segments (gather.comp) so that they pass over the facets between: the one counts the area
// whose photons the other can see (visible_disk.comp says why they must agree).
float convex_drop(float curvature, float d) {
    return curvature > 0.0 ? DISK_SLOPE * d + min(curvature * d * d, 0.5 / curvature) : 0.0;
}

// Whether a photon at `p` with normal `pn` lies on the surface of the sample at `x`: facing
// like it, and within DISK_SLOPE of its tangent plane as seen from x, or below it by no more
// than a convex surface of curvature `curvature` drops (convex_drop).
bool on_own_surface(vec3 x, vec3 ng, float curvature, vec3 p, vec3 pn) {
    vec3 d = p - x;
    float height = dot(d, ng);
    float band = DISK_SLOPE * length(d);
    return dot(pn, ng) >= DISK_MIN_NORMAL_COSINE && height <= band && -height <= max(band, convex_drop(curvature, length(d)));
}

#endif
