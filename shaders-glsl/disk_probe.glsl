// One direction's measurement of a view sample's visible disk (visible_disk.comp says what the
// disk is and why): the ray along the direction, its probes down to the sample's surface, the
// gather's lift, and the share of the kernel's mass the direction sees. The includer declares
// the scene's bindings (trace.glsl, disk.glsl) and `coplanar_neighbours` (per triangle, its
// coplanar neighbour across each edge).

#define DISK_DEPTHS 4u
// The biweight kernel's mass within distance s·r of the centre: 1 − (1 − s²)³.
float biweight_mass(float s) {
    float u = 1.0 - s * s;
    return 1.0 - u * u * u;
}

const uint NO_NEIGHBOUR = 0xffffffffu;

// The edge k of the triangle (vertices k, k + 1) that `p`, projected along the triangle's
// normal, lies beyond; 3 when it lies in the triangle (edges included).
uint edge_beyond(uint triangle, vec3 p) {
    vec3 a = vertex_position(3u * triangle);
    vec3 b = vertex_position(3u * triangle + 1u);
    vec3 c = vertex_position(3u * triangle + 2u);
    vec3 n = cross(b - a, c - a);
    if (dot(cross(b - a, p - a), n) < 0.0) {
        return 0u;
    }
    if (dot(cross(c - b, p - b), n) < 0.0) {
        return 1u;
    }
    if (dot(cross(a - c, p - c), n) < 0.0) {
        return 2u;
    }
    return 3u;
}

// Whether `p` lies over the flat face `own` (opaque) belongs to: over `own`, or over its
// coplanar opaque neighbour across the edge p lies beyond (a face is often a quad, and a disk
// on it crosses the diagonal). The surface exists there without a ray. False only means "not
// found this way": the caller traces a ray down. One step, not a walk: in the scenes measured
// every link is a quad's diagonal, and a loop cost more on lavapipe than the rays it saved.
// `walk`: false stays on `own` (the step is a tuning: VisibleDiskParams::walk_faces).
bool over_own_face(uint own, vec3 p, bool walk) {
    uint edge = edge_beyond(own, p);
    if (edge == 3u) {
        return true;
    }
    if (!walk) {
        return false;
    }
    uint across = coplanar_neighbours.ids[3u * own + edge];
    return across != NO_NEIGHBOUR && edge_beyond(across, p) == 3u;
}

// One direction's measurement of the disk around `from` (normal `ng`) at radius R: how far in
// the plane the direction sees (`reach`, at most R), and DISK_DEPTHS probes drawn from the
// kernel's radial mass within that reach, at distances `rho`, bit j of `supported` set where
// probe j found the sample's own surface. `direction_mass` reads the direction's share of the
// mass at any radius up to R from it.
struct DirectionSamples {
    float reach;
    vec4 rho;
    uint supported;
};

// Where facets are small (the basilica's columns and balusters) most probes land off the
// sample's face and its coplanar neighbour and trace a ray down: about 35–40 ms of the pass's
// 83–93 ms there at 320×240 on lavapipe (`render --stats`; 48–52 ms in a build skipping them).
// Measured and not kept: two probes a direction instead of four (76–81 ms: a tenth saved for a
// support count of half the samples), and a probe resolved from the G-buffer's triangle where its
// foot lands, tracing only where that fails (101–104 ms: on a column the camera's line of sight
// through the foot meets another facet than the probe's ray down, so most probes still traced).
//
// Traces the ray in direction `phi` around `from` and its probes at radius `big_r`, and, with
// `lift_length` > 0 (a convex curved surface), the ray up along ng that bounds the gather's
// lift: `lift_hit` is where it met something (lift_length: nothing). `rays_down` counts the
// rays down it traces (the disk-mass image's .b: tests compare it).
DirectionSamples trace_direction(vec3 from, vec3 ng, float curvature, uint own, bool walk_faces, float big_r, float phi, float lift_length, inout Rng rng, inout uint rays_down, out float lift_hit) {
    // A probe over the sample's own (opaque) face is on the surface without a ray down, which
    // spares most of those rays on the large triangles walls and floors are made of.
    bool own_opaque = triangle_material(own).alpha_cutoff < 0.0;
    vec3 t, b;
    basis(ng, t, b);
    float stretch = sqrt(1.0 + DISK_SLOPE * DISK_SLOPE);  // ray length per unit of in-plane distance
    vec3 dir = (cos(phi) * t + sin(phi) * b + DISK_SLOPE * ng) / stretch;
    DirectionSamples samples = DirectionSamples(big_r, vec4(0.0), 0u);
    float seen = 1.0;
    float phase = rng_next(rng);
    lift_hit = lift_length;
    // One loop over the rays (the direction's, its probes', the lift's), one call site: it
    // inlines the trace once (compiling faster), and lanes tracing different kinds of ray share
    // an iteration instead of waiting for each other. j = 0: the direction's ray; 1 … DISK_DEPTHS:
    // its probes; DISK_DEPTHS + 1: the lift.
    for (uint j = 0u; j <= DISK_DEPTHS + 1u; ++j) {
        bool lifting = j == DISK_DEPTHS + 1u;
        if (lifting && !(lift_length > 0.0)) {
            break;
        }
        vec3 origin = from;
        vec3 towards;
        float length;
        float rho = 0.0;
        if (lifting) {
            towards = ng;
            length = lift_length;
        } else if (j == 0u) {
            towards = dir;
            length = big_r * stretch;
        } else {
            // The kernel's radial mass 1 − (1 − s²)³ is uniform in u: s = sqrt(1 − (1 − u)^(1/3)).
            float u = seen * (float(j - 1u) + phase) / float(DISK_DEPTHS);
            rho = big_r * sqrt(max(0.0, 1.0 - pow(1.0 - u, 1.0 / 3.0)));
            origin = from + (rho * stretch) * dir;
            towards = -ng;
            // From DISK_SLOPE·rho above the plane down to it, and a few lifts below: a tolerance
            // for rounding on coplanar faces and for `from`'s own lift off the plane. A convex
            // curved surface is followed down as far as it drops (convex_drop): the gather lifts
            // its segments to see photons there.
            length = DISK_SLOPE * rho + 4.0 * lift_size(origin) + convex_drop(curvature, rho);
        }
        bool probe = j >= 1u && j <= DISK_DEPTHS;
        bool on_face = probe && own_opaque && over_own_face(own, origin, walk_faces);
        Hit hit = Hit(length, NO_HIT, vec2(0.0));  // a probe on the face needs no ray
        if (!on_face) {
            hit = traceClosest(origin, towards, 0.0, length);
            rays_down += probe ? 1u : 0u;
        }
        if (lifting) {
            lift_hit = hit.triangle == NO_HIT ? lift_length : hit.t;
        } else if (j == 0u) {
            samples.reach = hit.triangle == NO_HIT ? big_r : min(hit.t / stretch, big_r);
            seen = biweight_mass(samples.reach / big_r);
        } else {
            samples.rho[j - 1u] = rho;
            if (on_face || (hit.triangle != NO_HIT && abs(dot(triangle_geometric_normal(hit.triangle), ng)) >= DISK_MIN_NORMAL_COSINE)) {
                samples.supported |= 1u << (j - 1u);
            }
        }
    }
    return samples;
}

// The share of the kernel's mass at radius `r` (≤ `big_r`, the radius the samples were drawn
// at) that one direction sees on the sample's surface: the mass up to the reach, exactly, less
// the part of it the probes found unsupported. The probes were drawn from the kernel at big_r
// within the reach, with density w_R(ρ)/seen_R; weighted by the kernels' radial densities'
// ratio w_r/w_R = (R²/r²)·((1 − ρ²/r²) / (1 − ρ²/R²))², each stands for the kernel at r, so the
// estimate is unbiased at any r ≤ R, exactly the count of supported probes at r = R, and exactly
// the seen mass where every probe found the surface. It may come out below 0 for one direction;
// the mean over directions is floored by the caller.
float direction_mass(DirectionSamples samples, float big_r, float r) {
    float seen = biweight_mass(min(samples.reach, r) / r);
    float seen_at_big_r = biweight_mass(samples.reach / big_r);
    float unsupported = 0.0;
    for (uint j = 0u; j < DISK_DEPTHS; ++j) {
        float rho = samples.rho[j];
        if ((samples.supported & (1u << j)) == 0u && rho < r) {
            float w = (1.0 - rho * rho / (r * r)) / (1.0 - rho * rho / (big_r * big_r));
            unsupported += (big_r * big_r) / (r * r) * w * w;
        }
    }
    return seen - seen_at_big_r * unsupported / float(DISK_DEPTHS);
}
