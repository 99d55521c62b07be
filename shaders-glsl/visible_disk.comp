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
    uint tile_offset;               // x | y << 16: the workgroups' tiles start this far up and left of pixel 0
    float rotation;                 // this frame's turn of the directions, in quarter turns [0, 1)
    float share_distance;           // neighbours closer than this share of r lend their directions
    uint pad1;
    uint pad2;
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

// Traces the ray in direction `phi` around `from` and its probes at radius `big_r`, and, with
// `lift_length` > 0 (a convex curved surface), the ray up along ng that bounds the gather's
// lift: `lift_hit` is where it met something (lift_length: nothing). `rays_down` counts the
// rays down it traces (the disk-mass image's .b: tests compare it).
DirectionSamples trace_direction(vec3 from, vec3 ng, float curvature, uint own, float big_r, float phi, float lift_length, inout Rng rng, inout uint rays_down, out float lift_hit) {
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
        bool on_face = probe && own_opaque && over_own_face(own, origin);
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

// Sharing: each sample traces one of the DISK_DIRECTIONS directions (pixel_direction), all of
// them a quarter turn apart and turned by one random angle per frame (params.rotation), and takes
// the others from the neighbours in its 3×3 block that lie on its surface (shares_surface), or
// its 5×5 block where the 3×3 lacks a direction. Its mass is the mean over the directions of
// their lenders' mean. A direction no neighbour lends (a sample alone on its surface: a baluster
// a pixel wide, a silhouette, neighbours far apart at a low resolution) the workgroup traces for
// it: fewer directions would leave its divisor noisier and one frame's 1/mass brighter (+28% at
// the Cornell box's edges with the directions present only). The lanes take such jobs in turn, so
// that the few samples alone on their surface do not keep their neighbours' lanes waiting.
//
// Why: on detailed geometry (the basilica's columns, balusters and pews) the probes seldom land
// on the sample's own triangle, so each direction costs up to five rays, and four directions a
// sample were half of the frame. Inside a surface a sample now traces one direction, and its mass
// averages up to 25 of them: less grain on narrow faces, where a noisy divisor made one frame look
// like sandpaper. One angle for the frame rather than one per pixel: four directions a quarter
// turn apart measure a straight edge through the sample exactly (a half disk is 0.5 every frame);
// independent angles made the Cornell box's edges +5.6% bright in single frames (+3.9% now).
// Each frame's tiles start elsewhere (params.tile_offset), so their edges leave no seam.
//
// One measurement serves both radii of a partial disk: the rays are drawn at the largest radius
// the frame may gather within (g·r when growing, r when shrinking), and direction_mass reads any
// radius up to it from them. Measuring again at the new radius had cost as much as the first
// measurement.
const uint TILE = 8u;
shared vec4 shared_plane[TILE * TILE];   // xyz: the sample's normal; w: 1 + its supported probes (0: none)
shared vec4 shared_origin[TILE * TILE];  // xyz: the sample's ray origin; w: its reach
shared vec4 shared_rho[TILE * TILE];     // its probes' distances
shared float shared_curvature[TILE * TILE];
shared uint shared_triangle[TILE * TILE];
shared float shared_radius[TILE * TILE];   // the radius the sample measures at
// The directions traced for samples none of whose neighbours traced them: at most three each.
const uint MOST_JOBS = (DISK_DIRECTIONS - 1u) * TILE * TILE;
shared uint shared_job_count;
shared uint shared_job[MOST_JOBS];             // the sample's slot | the direction << 8
shared vec2 shared_job_samples[MOST_JOBS];     // DirectionSamples: reach, supported (bits)
shared vec4 shared_job_rho[MOST_JOBS];

// The direction the sample at `pixel` traces: (x − y) mod 4, so that every 3×3 block, and every
// row or column of three pixels (a baluster or a rail a pixel wide), holds three or four
// directions (a pixel-parity pattern gave a column of pixels only two).
uint pixel_direction(ivec2 pixel) {
    return uint(pixel.x - pixel.y) & 3u;
}

// Whether the sample at `y` (normal `ny`) may lend its direction to the one at `x` (normal `nx`,
// frame radius `r`): facing alike, on x's tangent plane, and near enough (params.share_distance).
bool shares_surface(vec3 x, vec3 nx, float r, vec3 y, vec3 ny) {
    vec3 d = y - x;
    float distance = length(d);
    return dot(nx, ny) >= 0.9 && distance <= params.share_distance * r && abs(dot(d, nx)) <= DISK_SLOPE * distance + 4.0 * lift_size(x);
}

// Whether the sample `offset` pixels from the one in slot `local` of the tile (at `from`, normal
// `ng`) is on the same surface, and so lends it its direction; `outside`: it lies outside the tile.
bool lends(uvec2 local, ivec2 offset, vec3 from, vec3 ng, out bool outside) {
    ivec2 at = ivec2(local) + offset;
    outside = any(lessThan(at, ivec2(0))) || any(greaterThanEqual(at, ivec2(TILE)));
    if (outside) {
        return false;
    }
    uint other = uint(at.y) * TILE + uint(at.x);
    vec4 plane = shared_plane[other];
    return plane.w > 0.0 && (offset == ivec2(0) || shares_surface(from, ng, params.radius, shared_origin[other].xyz, plane.xyz));
}

// Bit (dy + LEND_WINDOW)·LEND_SIDE + dx + LEND_WINDOW of a lender mask: the neighbour at (dx, dy).
const int LEND_WINDOW = 2;
const int LEND_SIDE = 2 * LEND_WINDOW + 1;
const uint LEND_CENTRE = uint(LEND_WINDOW * LEND_SIDE + LEND_WINDOW);
// The 3×3 block's bits.
const uint LEND_3X3 = (7u << 6u) | (7u << 11u) | (7u << 16u);

// The neighbours within `window` pixels (at most LEND_WINDOW) of the sample in slot `local` of
// the tile (at `from`, normal `ng`) that lend it their directions: those on its surface whose
// mirror image about it lends too, unless the tile's edge hides that one. The lenders lie
// symmetric about the sample where the surface ends. A neighbour's disk is not the sample's;
// over a symmetric block the mass's change along the surface cancels to first order. At a
// crease or a silhouette all the neighbours lie on one side and read the mass further in,
// larger by its slope times their offset (the atrium's edges, accumulated, were 25% worse in
// relMSE). A tile's edge is not required to be symmetric: it moves every frame, and requiring
// it made a third of the samples trace more directions themselves. Read after the barrier that
// follows the shares' writes; computed once, since the directions lent and the mass both walk
// the same lenders.
uint lenders(uvec2 local, vec3 from, vec3 ng, int window) {
    uint on_surface = 0u, outside_tile = 0u;
    for (int dy = -window; dy <= window; ++dy) {
        for (int dx = -window; dx <= window; ++dx) {
            uint bit = 1u << uint((dy + LEND_WINDOW) * LEND_SIDE + dx + LEND_WINDOW);
            bool outside;
            on_surface |= lends(local, ivec2(dx, dy), from, ng, outside) ? bit : 0u;
            outside_tile |= outside ? bit : 0u;
        }
    }
    // The mirror of bit i is bit 2·LEND_CENTRE − i.
    uint both = 0u;
    for (uint i = 0u; i <= 2u * LEND_CENTRE; ++i) {
        uint mirror = 1u << (2u * LEND_CENTRE - i);
        if ((on_surface & (1u << i)) != 0u && ((on_surface | outside_tile) & mirror) != 0u) {
            both |= 1u << i;
        }
    }
    return both;
}

// The offset of lender bit `i`.
ivec2 lender_offset(uint i) {
    return ivec2(int(i) % LEND_SIDE, int(i) / LEND_SIDE) - LEND_WINDOW;
}

// Bit k set: the sample at `pixel` or one of its `mask` of lenders traced direction k.
uint lent_directions(ivec2 pixel, uint mask) {
    uint lent = 0u;
    for (uint rest = mask; rest != 0u; rest &= rest - 1u) {
        lent |= 1u << pixel_direction(pixel + lender_offset(uint(findLSB(rest))));
    }
    return lent;
}

// The sample's visible share of the kernel at radius `r`: per direction, the mean of what it and
// its `mask` of lenders measured at `big_r`, or, for the directions in `missing`, what the tile
// traced for it (jobs `first` on, in the order of their bits); then the mean over the
// directions.
float shared_mass(uvec2 local, ivec2 pixel, float big_r, float r, uint mask, uint missing, uint first) {
    float sum[DISK_DIRECTIONS] = float[](0.0, 0.0, 0.0, 0.0);
    uint count[DISK_DIRECTIONS] = uint[](0u, 0u, 0u, 0u);
    for (uint rest = mask; rest != 0u; rest &= rest - 1u) {
        ivec2 offset = lender_offset(uint(findLSB(rest)));
        uint other = uint(int(local.y) + offset.y) * TILE + uint(int(local.x) + offset.x);
        vec4 origin = shared_origin[other];
        DirectionSamples lent = DirectionSamples(origin.w, shared_rho[other], uint(shared_plane[other].w) - 1u);
        uint d = pixel_direction(pixel + offset);
        sum[d] += direction_mass(lent, big_r, r);
        count[d] += 1u;
    }
    float mass = 0.0;
    uint job = first;
    for (uint d = 0u; d < DISK_DIRECTIONS; ++d) {
        if ((missing & (1u << d)) != 0u) {
            DirectionSamples traced = DirectionSamples(shared_job_samples[job].x, shared_job_rho[job], floatBitsToUint(shared_job_samples[job].y));
            mass += direction_mass(traced, big_r, r);
            job += 1u;
        } else {
            mass += sum[d] / float(max(count[d], 1u));
        }
    }
    return mass / float(DISK_DIRECTIONS);
}

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
        from = offset_ray(nudge_toward(position.xyz, frame.camera_position.xyz), ng);
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
                DirectionSamples got = trace_direction(at, normal, bend, face, measured_at, phi, lift_length, rng, rays_down, hit);
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
                uint near = measuring ? lenders(local, from, ng, window == 0 ? 0 : LEND_WINDOW) : 0u;
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
