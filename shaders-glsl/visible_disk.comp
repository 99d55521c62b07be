#version 460
// Visible disk (leakless): per view sample, the share of the gather kernel's mass over the part
// of its disk where the sample's own surface exists and can be seen from it. The gather
// divides the flux of the photons on that surface by it (gather.comp).
//
// Why: the kernel estimate divides the flux near x by the kernel's mass over a whole disk,
// which holds only where x's surface covers the disk and all of it can be seen from x. Where it
// does not (a 40 cm pier's face under a 46 cm radius, the foot of a wall, a corner), `splat`
// makes up the missing area with light from other surfaces (the pier's other faces, the room
// behind the wall), which the visibility test rightly removes: `leakless` came out darker than
// the reference there (6% over the atrium at the default radius, 12% at twice it).
//
// How: DISK_DIRECTIONS rays from x, rotated at random per pixel and frame (accumulation
// averages them), each DISK_SLOPE above the tangent plane (a concave surface rises above its
// tangent plane; a ray grazing it would find it at once). Each ray gives exactly the kernel
// mass its direction sees up to the first surface it meets; within that, DISK_DEPTHS points
// drawn from the kernel's radial mass check that the surface exists: over the sample's own
// face (its triangle, or that triangle's coplanar neighbour: no ray needed), or else a short ray
// down from the point must meet a surface facing like x's no deeper than a few lifts below the
// tangent plane (on a convex curved mesh as deep as it drops, below).
//
// Why not deeper: the gather's visibility segment from x to a photon on a surface below the plane
// beyond an edge of x's face dips through x's face or the solid under it, so the test drops every
// photon there, and counting that surface's mass divided the photons that remain by too much.
// The atrium's beam, 3 cm behind the face of the pier it meets, made the piers' inner faces 14%
// dark after 32 frames (1% above the reference with the probe stopping at the plane). A convex
// curved mesh is the exception: below the plane lies the sample's own surface, and the gather
// lifts its segments over the facets between (gather.comp), so the probes follow it down as far
// as it drops (convex_drop; 0 on flat faces), and this pass traces that lift (the image's .a).
// A tessellated ball: 0.51× → 0.92× the reference in single frames, 0.943× → 0.997× after 32
// (corner_bias.rs). The probes see from x and the segments from the lifted point, so near an
// occluder lower than the lift the two disagree a little.
#include "trace.glsl"
#include "common.glsl"
#include "gbuffer.glsl"
#include "disk.glsl"
#include "random.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

FRAME_BLOCK(0);
GBUFFER_BINDINGS(1)
layout(set = 0, binding = 4, rgba32f) uniform writeonly image2D disk_mass;
// Per triangle, its coplanar neighbour across edge k (vertices k, k + 1), or NO_NEIGHBOUR
// (Scene::coplanar_neighbours says which triangles are linked).
layout(set = 0, binding = 5, std430) readonly buffer CoplanarNeighbours { uint ids[]; } coplanar_neighbours;
layout(push_constant) uniform VisibleDiskParams {
    float radius;   // this frame's gather radius
    uint seed;      // this frame's seed (the rays' rotation)
    uint enabled;   // 0: every sample's mass is 1 (the whole disk)
    float partial_radius_exponent;  // γ: a partial disk grows (γ < 0) or shrinks (γ > 0) the radius
    float min_radius_share;         // s: it shrinks to no less than s·r
    uint walk_faces;                // 1: over_own_face may step to a coplanar neighbour
    float max_radius_share;         // g: it grows to no more than g·r
    uint pad1;
} params;

#define DISK_DIRECTIONS 4u
#define DISK_DEPTHS 4u
// A floor so that one unlucky set of rays cannot amplify a pixel's noise without bound (a
// room's corner is a quarter disk).
const float DISK_MIN_MASS = 0.2;

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
bool over_own_face(uint own, vec3 p) {
    uint edge = edge_beyond(own, p);
    if (edge == 3u) {
        return true;
    }
    if (params.walk_faces == 0u) {
        return false;
    }
    uint across = coplanar_neighbours.ids[3u * own + edge];
    return across != NO_NEIGHBOUR && edge_beyond(across, p) == 3u;
}

// The mass around `from` (normal `ng`, radius r) on `own`'s surface, seen from `from`.
// `rays_down` counts the rays down it traces (the disk-mass image's .b: tests compare it).
// On a convex curved surface (curvature > 0) it also traces the gather's lift: `lift` is how
// far the gather may move `from` along ng, κr² (at most r) or half the way to whatever stands
// in front of the surface closer than that. An untraced lift could carry the segments' start
// through a wall beside a ball, into the next room, and let that room's light in.
float visible_disk_mass(vec3 from, vec3 ng, float curvature, uint own, float r, inout Rng rng, inout uint rays_down, out float lift) {
    // A probe over the sample's own (opaque) face is on the surface without a ray down, which
    // spares most of those rays on the large triangles walls and floors are made of.
    bool own_opaque = triangle_material(own).alpha_cutoff < 0.0;
    vec3 t, b;
    basis(ng, t, b);
    float angle_phase = rng_next(rng);
    float stretch = sqrt(1.0 + DISK_SLOPE * DISK_SLOPE);  // ray length per unit of in-plane distance
    float mass = 0.0;
    // One loop over the rays, not a loop of directions each with its own loop of rays down: one
    // call site inlines the trace once (compiling faster), and a lane tracing a direction's ray
    // and one tracing a ray down share an iteration instead of waiting for each other.
    uint k = 0u;                     // the direction
    uint j = DISK_DEPTHS;            // its next probe; DISK_DEPTHS: its ray comes first
    vec3 dir = vec3(0.0);
    float seen = 0.0;
    float phase = 0.0;
    uint supported = 0u;
    float wanted = curvature > 0.0 ? min(curvature * r * r, r) : 0.0;
    lift = 0.0;
    bool lifting = false;  // the last ray: the lift's
    while (true) {
        if (k == DISK_DIRECTIONS) {
            if (lifting || !(wanted > 0.0)) {
                break;
            }
            lifting = true;
        }
        vec3 origin = from;
        vec3 towards;
        float length;
        if (lifting) {
            towards = ng;
            length = wanted;
        } else if (j == DISK_DEPTHS) {
            float phi = 2.0 * PI * (float(k) + angle_phase) / float(DISK_DIRECTIONS);
            dir = (cos(phi) * t + sin(phi) * b + DISK_SLOPE * ng) / stretch;
            towards = dir;
            length = r * stretch;
        } else {
            // The kernel's radial mass 1 − (1 − s²)³ is uniform in u: s = sqrt(1 − (1 − u)^(1/3)).
            float u = seen * (float(j) + phase) / float(DISK_DEPTHS);
            float rho = r * sqrt(max(0.0, 1.0 - pow(1.0 - u, 1.0 / 3.0)));
            origin = from + (rho * stretch) * dir;
            towards = -ng;
            // From DISK_SLOPE·rho above the plane down to it, and a few lifts below: a tolerance
            // for rounding on coplanar faces and for `from`'s own lift off the plane. A convex
            // curved surface is followed down as far as it drops (convex_drop): the gather lifts
            // its segments to see photons there.
            length = DISK_SLOPE * rho + 4.0 * lift_size(origin) + convex_drop(curvature, rho);
        }
        bool on_face = !lifting && j < DISK_DEPTHS && own_opaque && over_own_face(own, origin);
        Hit hit = Hit(length, NO_HIT, vec2(0.0));  // a probe on the face needs no ray
        if (!on_face) {
            hit = traceClosest(origin, towards, 0.0, length);
            rays_down += j < DISK_DEPTHS ? 1u : 0u;
        }
        if (lifting) {
            lift = hit.triangle == NO_HIT ? wanted : 0.5 * hit.t;
            break;
        }
        if (j == DISK_DEPTHS) {
            float reach = hit.triangle == NO_HIT ? r : min(hit.t / stretch, r);
            seen = biweight_mass(reach / r);
            phase = rng_next(rng);
            supported = 0u;
            j = 0u;
            continue;
        }
        if (on_face || (hit.triangle != NO_HIT && abs(dot(triangle_geometric_normal(hit.triangle), ng)) >= DISK_MIN_NORMAL_COSINE)) {
            supported += 1u;
        }
        j += 1u;
        if (j == DISK_DEPTHS) {
            mass += seen * float(supported) / float(DISK_DEPTHS);
            k += 1u;
        }
    }
    return mass / float(DISK_DIRECTIONS);
}

// Partial disks: the sample gathers within r·clamp(m^γ, s, g), m its visible share at r, and
// its mass is measured again at that radius.
//
// Why grow in a single frame (γ = −1, up to g = 1.5): a partial disk holds fewer photons, and
// dividing fewer by a smaller mass made one frame noisier at the edges than the whole disk, which
// darkens there instead (relMSE 11% worse in the Cornell box at 10k paths, 5% in the doorway).
// A disk grown as the share shrinks holds about as many photons as a whole one. Its centroid
// moves off the sample (a bias of first order in r, below), which a single frame's noise hides;
// the cap keeps the atrium at twice the default radius, where bias dominates, near the
// reference.
//
// Why shrink in an accumulation (γ > 0): over a whole disk the kernel's centroid is the sample,
// so the estimate's bias is of second order in r; over a part of it the centroid lies off the
// sample, inside the part, and the estimate is the irradiance there: a bias of first order in r
// (the floor beside a wall reads the floor further out, a lintel narrower than r reads along
// itself). Accumulating averages noise away but not that, and after a few seconds it was most of
// the atrium's error, on the lintels and piers. A smaller disk there moves the centroid in with
// it; its extra noise stays at the edges, and the radius elsewhere is untouched. The more partial
// the disk, the more it shrinks; the floor s (splatting::MIN_RADIUS_SHARE, ½) keeps a corner's
// quarter disk at half the radius, and the gather's fixed-point bound allows for it (gather.rs).
// γ ramps from 1/64 at batch 1 to 1 as batches add up (splatting::partial_radius_exponent).
//
// The hierarchy takes each sample's radius from .g (hierarchy_build.comp), so the splat lists a
// photon wherever a grown disk may reach it.

// The share of the radius a disk of visible share `m` gathers within.
float radius_share(float m) {
    float gamma = params.partial_radius_exponent;
    // m = 0 (no probe found the surface): the smallest disk when shrinking, the largest when
    // growing (pow(0, γ < 0) is undefined).
    float share = m > 0.0 ? pow(m, gamma) : (gamma > 0.0 ? 0.0 : params.max_radius_share);
    return clamp(share, params.min_radius_share, params.max_radius_share);
}

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (pixel.x >= int(frame.width) || pixel.y >= int(frame.height)) {
        return;
    }
    vec4 position = imageLoad(gbuffer_position, pixel);
    float mass = 1.0;
    float r = params.radius;
    uint rays_down = 0u;
    float lift = 0.0;
    if (params.enabled != 0u && position.w > 0.0) {
        uint triangle = uint(position.w) - 1u;
        vec3 ng = sample_geometric_normal(triangle, imageLoad(gbuffer_normal, pixel).xyz);
        vec3 from = offset_ray(nudge_toward(position.xyz, frame.camera_position.xyz), ng);
        float curvature = convex_curvature(triangle, ng);
        Rng rng = rng_seed(uvec2(pixel), 0xd15cu, params.seed);
        // A partial disk is measured a second time at its new radius. One call site in a
        // loop, not two calls: each call inlines the whole trace twice, and on lavapipe four
        // copies took 7.5 s to compile on first use (the app's first frame waited for it).
        for (uint measure = 0u; measure < 2u; ++measure) {
            mass = visible_disk_mass(from, ng, curvature, triangle, r, rng, rays_down, lift);
            if (measure == 1u || !(params.partial_radius_exponent != 0.0 && mass < 1.0)) {
                break;
            }
            r *= radius_share(max(mass, 0.0));
        }
        mass = max(mass, DISK_MIN_MASS);
    }
    // .a: the gather's lift at the final radius (the last measure's).
    imageStore(disk_mass, pixel, vec4(mass, r, float(rays_down), lift));
}
