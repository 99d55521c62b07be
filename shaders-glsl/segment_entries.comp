#version 460
// Segment entries: for each tile of view samples, the BVH nodes where the traversals of its
// visibility segments start. A segment is short (at most the gather's largest radius) and
// stays near its tile, so a traversal from the root spends much of its steps descending to
// that neighbourhood, the same steps for every segment of the tile. Here they are taken once:
// from the root, a node whose one child's box meets the tile's region is replaced by that
// child, one whose two children both do by both while there is room for ENTRIES nodes, and
// one whose box misses it is dropped. Every triangle whose box meets the region is then under
// one of the entries (a triangle's box is inside every ancestor's), so a segment that lies in
// the region meets exactly the triangles that a walk from the root would find
// (trace_compute.glsl, trace_bvh_occluded_cached_from). The gather checks that each segment
// lies in the region, and walks from the root where one does not.
//
// Only in a scene of one static part (trace_scale.static_root): elsewhere every part has its
// own space, and the entries' count is 0 with the region empty, which the gather reads as
// "from the root".
#include "common.glsl"
#include "scene.glsl"
#include "gbuffer.glsl"
#include "bvh.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

GBUFFER_BINDINGS(0)
// Per tile: the region's corners (.xyz), the entries' count in the low corner's .w, and the
// entries, each as its parent node · 2 + which of its children (BVH_NO_CHILD past the count).
layout(set = 1, binding = 3, rgba32f) uniform writeonly image2D segment_region_lo;
layout(set = 1, binding = 4, rgba32f) uniform writeonly image2D segment_region_hi;
layout(set = 1, binding = 5, rgba32ui) uniform writeonly uimage2D segment_entries;
layout(push_constant) uniform SegmentEntriesParams {
    float max_radius;  // no segment of the gather is longer than this
    uint tile;         // a tile × tile block of pixels shares its entries
    uint pad0;
    uint pad1;
} params;

const uint ENTRIES = 4u;
const uint NO_PARENT = 0xffffffffu;

bool boxes_meet(vec3 lo, vec3 hi, vec3 region_lo, vec3 region_hi) {
    return all(lessThanEqual(lo, region_hi)) && all(lessThanEqual(region_lo, hi));
}

void write_none(ivec2 t) {
    imageStore(segment_region_lo, t, vec4(0.0));
    imageStore(segment_region_hi, t, vec4(-1.0, -1.0, -1.0, 0.0));  // empty: no segment is in it
    imageStore(segment_entries, t, uvec4(BVH_NO_CHILD));
}

void main() {
    ivec2 t = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(t, imageSize(segment_entries)))) {
        return;
    }
    if (trace_scale.static_root == BVH_NO_CHILD) {
        write_none(t);
        return;
    }
    // The tile's samples' box, grown by the longest segment: a segment leaves from a point a
    // few lifts from its sample and ends within the radius and a lift of it.
    ivec2 size = imageSize(gbuffer_position);
    ivec2 first = t * int(params.tile);
    vec3 lo = vec3(3.0e38);
    vec3 hi = vec3(-3.0e38);
    for (int y = 0; y < int(params.tile); ++y) {
        for (int x = 0; x < int(params.tile); ++x) {
            ivec2 xy = first + ivec2(x, y);
            if (all(lessThan(xy, size))) {
                vec4 p = imageLoad(gbuffer_position, xy);
                if (p.w != 0.0) {
                    lo = min(lo, p.xyz);
                    hi = max(hi, p.xyz);
                }
            }
        }
    }
    if (any(greaterThan(lo, hi))) {
        write_none(t);
        return;
    }
    float grow = 1.05 * params.max_radius;
    vec3 region_lo = lo - grow;
    vec3 region_hi = hi + grow;
    // The cut takes every node that comes within a margin of the region: far more than the
    // rounding of a traversal's ray and box tests (a few float ULPs of the coordinates).
    float magnitude = max(max(max(abs(region_lo.x), abs(region_lo.y)), abs(region_lo.z)),
                          max(max(abs(region_hi.x), abs(region_hi.y)), abs(region_hi.z)));
    float margin = magnitude * (1.0 / 4096.0) + 0.001 * params.max_radius;
    vec3 cut_lo = region_lo - margin;
    vec3 cut_hi = region_hi + margin;
    // The cut holds child references and, for the traversal to test their boxes as a walk
    // from the root would, where each box is: parent · 2 + which child.
    uint cut[ENTRIES];
    uint at[ENTRIES];
    cut[0] = trace_scale.static_root;
    at[0] = NO_PARENT;
    uint count = 1u;
    // Each pass over the cut refines what it can; a refinement loads one node. At most 64 are
    // made, which bounds the pass's work: a cut left higher in the tree is as exact, and its
    // walks only take more steps.
    uint refinements = 0u;
    bool refined = true;
    while (refined && refinements < 64u) {
        refined = false;
        uint i = 0u;
        while (i < count && refinements < 64u) {
            uint node = cut[i];
            if (bvh_is_leaf(node)) {
                i++;
                continue;
            }
            BvhNode n = BVH_NODE(node);
            bool h0 = n.child0 != BVH_NO_CHILD && boxes_meet(n.min0, n.max0, cut_lo, cut_hi);
            bool h1 = n.child1 != BVH_NO_CHILD && boxes_meet(n.min1, n.max1, cut_lo, cut_hi);
            if (h0 && h1) {
                if (count == ENTRIES) {
                    i++;
                    continue;
                }
                cut[i] = n.child0;
                at[i] = node * 2u;
                cut[count] = n.child1;
                at[count] = node * 2u + 1u;
                count++;
            } else if (h0 || h1) {
                cut[i] = h0 ? n.child0 : n.child1;
                at[i] = node * 2u + (h0 ? 0u : 1u);
            } else {
                count--;  // nothing under it meets the region
                cut[i] = cut[count];
                at[i] = at[count];
            }
            refined = true;
            refinements++;
        }
    }
    // A cut that is still the root saves nothing: the walk from the root is the same.
    if (count == 1u && at[0] == NO_PARENT) {
        write_none(t);
        return;
    }
    uvec4 entries = uvec4(BVH_NO_CHILD);
    for (uint i = 0u; i < count; ++i) {
        entries[i] = at[i];
    }
    imageStore(segment_region_lo, t, vec4(region_lo, float(count)));
    imageStore(segment_region_hi, t, vec4(region_hi, 0.0));
    imageStore(segment_entries, t, entries);
}
