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
// How: DISK_DIRECTIONS rays from x (most of them traced by its neighbours: sharing, below),
// turned by a random angle per frame (accumulation averages them), each DISK_SLOPE above the
// tangent plane (a concave surface rises above its tangent plane; a ray grazing it would find it
// at once). Each ray gives exactly the kernel mass its direction sees up to the first surface it
// meets; within that, DISK_DEPTHS points drawn from the kernel's radial mass check that the
// surface exists: over the sample's own face (its triangle, or that triangle's coplanar
// neighbour: no ray needed), or else a short ray down from the point must meet a surface facing
// like x's no deeper than a few lifts below the tangent plane (on a convex curved mesh as deep
// as it drops, below).
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

layout(local_size_x = 8, local_size_y = 8) in;  // TILE × TILE (visible_disk.rs: TILE)

FRAME_BLOCK(0);
GBUFFER_BINDINGS(1)
layout(set = 1, binding = 4, rgba32f) uniform writeonly image2D disk_mass;
// Per triangle, its coplanar neighbour across edge k (vertices k, k + 1), or NO_NEIGHBOUR
// (Scene::coplanar_neighbours says which triangles are linked).
layout(set = 1, binding = 5, std430) readonly buffer CoplanarNeighbours { uint ids[]; } coplanar_neighbours;
layout(push_constant) uniform VisibleDiskParams {
    float radius;   // this frame's gather radius
    uint seed;      // this frame's seed (the rays' rotation)
    uint enabled;   // 0: every sample's mass is 1 (the whole disk)
    float partial_radius_exponent;  // γ: a partial disk grows (γ < 0) or shrinks (γ > 0) the radius
    float min_radius_share;         // s: it shrinks to no less than s·r
    uint walk_faces;                // 1: over_own_face may step to a coplanar neighbour
    float max_radius_share;         // g: it grows to no more than g·r
    uint tile_offset;               // x | y << 16: the workgroups' tiles start this far up and left of pixel 0
    float rotation;                 // this frame's turn of the directions, in quarter turns [0, 1)
    float share_distance;           // neighbours closer than this share of r lend their directions
    uint pad1;
    uint pad2;
} params;

#define DISK_DIRECTIONS 4u
// A floor so that one unlucky set of rays cannot amplify a pixel's noise without bound (a
// room's corner is a quarter disk).
const float DISK_MIN_MASS = 0.2;

#include "disk_probe.glsl"

// Partial disks: the sample gathers within r·clamp(m^γ, s, g), m its visible share at r, and
// its mass is read again at that radius (from the same rays: direction_mass).
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

#include "disk_share.glsl"

void main() {
    uvec2 local = gl_LocalInvocationID.xy;
    uint slot = local.y * TILE + local.x;
    ivec2 tile_offset = ivec2(params.tile_offset & 0xffffu, params.tile_offset >> 16u);
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy) - tile_offset;
    bool inside = all(greaterThanEqual(pixel, ivec2(0))) && pixel.x < int(frame.width) && pixel.y < int(frame.height);
    vec4 position = inside ? imageLoad(gbuffer_position, pixel) : vec4(0.0);
    // Every invocation, inside the image or not, reaches the barriers below.
    bool valid = inside && params.enabled != 0u && position.w > 0.0;
    float r = params.radius;
    uint rays_down = 0u;
    float lift = 0.0;
    float mass = 1.0;
    vec3 ng = vec3(0.0);
    vec3 from = vec3(0.0);
    float curvature = 0.0;
    uint triangle = valid ? uint(position.w) - 1u : 0u;
    if (valid) {
        ng = sample_geometric_normal(triangle, imageLoad(gbuffer_normal, pixel).xyz);
        from = sample_segment_start(position.xyz, ng, frame.camera_position.xyz);
        curvature = convex_curvature(triangle, ng);
    }
    uint own = pixel_direction(pixel);
    float lift_hit = 0.0;
    // A single frame measures once, at the largest radius its partial disks may grow to, and
    // reads both radii from those rays. An accumulation's shrunk disk is measured again, with
    // rays of its own, at its new radius: read from the rays that chose the radius, its mass
    // would be correlated with that choice (a disk whose probes happened to miss the surface
    // would both shrink and count less), a bias that accumulating keeps.
    uint measures = params.partial_radius_exponent > 0.0 ? 2u : 1u;
    float big_r = params.partial_radius_exponent < 0.0 ? params.max_radius_share * r : r;
    bool measuring = valid;
    for (uint measure = 0u; measure < measures; ++measure) {
        if (slot == 0u) {
            shared_job_count = 0u;
        }
        uint missing = 0u;  // the directions no neighbour lent: the tile traces them for the sample
        uint first = 0u;    // their first job
        uint mask = 0u;     // the sample's lenders (`lenders`)
        // The neighbours within this many pixels lend their directions; none to a second
        // measurement, whose neighbours measured at radii of their own.
        int window = measure == 0u ? 1 : 0;
        // Step 0: each sample traces its own direction (and, first, the lift) and shares it.
        // Step 1: the tile's samples share out the directions none of its neighbours lent some
        // sample (jobs), so that the few samples alone on their surface do not keep their
        // neighbours' lanes waiting. One call site: each call inlines the whole trace, and on
        // lavapipe four copies took 7.5 s to compile on first use (the app's first frame waited).
        for (uint step = 0u; step < 2u; ++step) {
            uint jobs = step == 0u ? (measuring ? 1u : 0u) : shared_job_count;
            for (uint job = step == 0u ? 0u : slot; job < jobs; job += TILE * TILE) {
                // Whose direction, which, and from where.
                uint owner = step == 0u ? slot : shared_job[job] & 0xffu;
                uint d = step == 0u ? own : shared_job[job] >> 8u;
                vec3 at = step == 0u ? from : shared_origin[owner].xyz;
                vec3 normal = step == 0u ? ng : shared_plane[owner].xyz;
                float bend = step == 0u ? curvature : shared_curvature[owner];
                uint face = step == 0u ? triangle : shared_triangle[owner];
                float measured_at = step == 0u ? big_r : shared_radius[owner];
                // The lift wanted at the largest radius: the final one's is no longer.
                float lift_length = step == 0u && measure == 0u && bend > 0.0 ? min(bend * big_r * big_r, big_r) : 0.0;
                float phi = 2.0 * PI * (float(d) + params.rotation) / float(DISK_DIRECTIONS);
                float hit = 0.0;
                // The random numbers are the owner's and its direction's, not the lane's: which
                // lane takes a job depends on the order of the atomics, and the image must not.
                ivec2 owner_pixel = ivec2(gl_WorkGroupID.xy * TILE + uvec2(owner % TILE, owner / TILE)) - tile_offset;
                Rng rng = rng_seed(uvec2(max(owner_pixel, ivec2(0))), 0xd15cu + d + 4u * measure, params.seed);
                DirectionSamples got = trace_direction(at, normal, bend, face, params.walk_faces != 0u, measured_at, phi, lift_length, rng, rays_down, hit);
                if (step == 0u) {
                    lift_hit = measure == 0u ? hit : lift_hit;
                    shared_origin[slot] = vec4(from, got.reach);
                    shared_rho[slot] = got.rho;
                    shared_plane[slot].w = float(got.supported + 1u);
                } else {
                    shared_job_samples[job] = vec2(got.reach, uintBitsToFloat(got.supported));
                    shared_job_rho[job] = got.rho;
                }
            }
            if (step == 0u) {
                if (!measuring) {
                    shared_plane[slot].w = 0.0;
                }
                shared_plane[slot].xyz = ng;
                shared_curvature[slot] = curvature;
                shared_triangle[slot] = triangle;
                shared_radius[slot] = big_r;
                barrier();
                // The 3×3 block, or where it lacks a direction, the 5×5 one: a rail a pixel wide
                // holds all four directions within five pixels along it.
                uint near = measuring ? lenders(local, from, ng, params.share_distance * params.radius, window == 0 ? 0 : LEND_WINDOW) : 0u;
                mask = window == 1 ? near & LEND_3X3 : near;
                uint lent = measuring ? lent_directions(pixel, mask) : 0xfu;
                if (lent != 0xfu && window == 1) {
                    window = 2;
                    mask = near;
                    lent = lent_directions(pixel, mask);
                }
                missing = ~lent & 0xfu;
                if (missing != 0u) {
                    first = atomicAdd(shared_job_count, uint(bitCount(missing)));
                    uint job = first;
                    for (uint d = 0u; d < DISK_DIRECTIONS; ++d) {
                        if ((missing & (1u << d)) != 0u) {
                            shared_job[job] = slot | (d << 8u);
                            job += 1u;
                        }
                    }
                }
            }
            barrier();
        }
        if (measuring) {
            mass = shared_mass(local, pixel, big_r, r, mask, missing, first);
            if (measure == 0u && params.partial_radius_exponent != 0.0 && mass < 1.0) {
                r *= radius_share(max(mass, 0.0));
                if (measures == 1u) {
                    mass = shared_mass(local, pixel, big_r, r, mask, missing, first);
                }
            } else {
                measuring = false;  // nothing to measure again
            }
        }
        // Every read of this measurement's shares before the next one writes its own.
        barrier();
        big_r = r;
    }
    if (valid) {
        // The gather's lift at the final radius: as far as κr² (at most r), or half the way to
        // whatever stands in front of the surface closer than that. An untraced lift could carry
        // the segments' start through a wall beside a ball, into the next room.
        float wanted = curvature > 0.0 ? min(curvature * r * r, r) : 0.0;
        lift = lift_hit < wanted ? 0.5 * lift_hit : wanted;
        mass = max(mass, DISK_MIN_MASS);
    }
    if (inside) {
        imageStore(disk_mass, pixel, vec4(mass, r, float(rays_down), lift));
    }
}
