// Sharing a tile's directions (visible_disk.comp): which neighbours of a sample lie on its
// surface and lend it the direction they traced, and the mass from theirs and its own. Included
// after disk_probe.glsl.

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
// on the sample's own triangle, so each direction costs up to five rays, and four directions for
// every sample would cost half of the frame. Inside a surface a sample traces one direction, and
// its mass averages up to 25 of them: less grain on narrow faces, where a noisy divisor makes one
// frame look like sandpaper. One angle for the frame rather than one per pixel: four directions a
// quarter turn apart measure a straight edge through the sample exactly (a half disk is 0.5 every
// frame), where independent angles leave single frames' edges brighter.
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

// Whether the sample at `y` (normal `ny`) may lend its direction to the one at `x` (normal `nx`):
// facing alike, on x's tangent plane, and no further than `reach` (params.share_distance of the
// frame's radius).
bool shares_surface(vec3 x, vec3 nx, float reach, vec3 y, vec3 ny) {
    vec3 d = y - x;
    float distance = length(d);
    return dot(nx, ny) >= 0.9 && distance <= reach && abs(dot(d, nx)) <= DISK_SLOPE * distance + 4.0 * lift_size(x);
}

// Whether the sample `offset` pixels from the one in slot `local` of the tile (at `from`, normal
// `ng`) is on the same surface within `reach` (shares_surface), and so lends it its direction;
// `outside`: it lies outside the tile.
bool lends(uvec2 local, ivec2 offset, vec3 from, vec3 ng, float reach, out bool outside) {
    ivec2 at = ivec2(local) + offset;
    outside = any(lessThan(at, ivec2(0))) || any(greaterThanEqual(at, ivec2(TILE)));
    if (outside) {
        return false;
    }
    uint other = uint(at.y) * TILE + uint(at.x);
    vec4 plane = shared_plane[other];
    return plane.w > 0.0 && (offset == ivec2(0) || shares_surface(from, ng, reach, shared_origin[other].xyz, plane.xyz));
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
uint lenders(uvec2 local, vec3 from, vec3 ng, float reach, int window) {
    uint on_surface = 0u, outside_tile = 0u;
    for (int dy = -window; dy <= window; ++dy) {
        for (int dx = -window; dx <= window; ++dx) {
            uint bit = 1u << uint((dy + LEND_WINDOW) * LEND_SIDE + dx + LEND_WINDOW);
            bool outside;
            on_surface |= lends(local, ivec2(dx, dy), from, ng, reach, outside) ? bit : 0u;
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
