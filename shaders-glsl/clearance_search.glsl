// The clearance search shared by photon_clearance.comp and sample_clearance.comp: the radius
// of the ball around a point that holds no triangle except those lying wholly on or under a
// plane just above the surface the point was lifted from. The gather proves a visibility
// segment clear without a ray where the segment stays inside such balls and above their planes
// (gather.comp).
#ifndef LEAKLESS_CLEARANCE_SEARCH_GLSL
#define LEAKLESS_CLEARANCE_SEARCH_GLSL

#include "bvh.glsl"

// The plane dot(v − point, normal) = tau: triangles with all three vertices on or under it
// (the surface itself, anything coplanar, everything behind it) do not bound the ball.
struct ClearancePlane {
    vec3 point;
    vec3 normal;
    float tau;
};

#define STACK_SIZE 64

// Squared distance from q to the box lo..hi (0 inside).
float box_distance2(vec3 q, vec3 lo, vec3 hi) {
    vec3 d = max(max(lo - q, q - hi), vec3(0.0));
    return dot(d, d);
}

// Squared distance from q to triangle abc (Ericson, Real-Time Collision Detection, 5.1.5).
float triangle_distance2(vec3 q, vec3 a, vec3 b, vec3 c) {
    vec3 ab = b - a;
    vec3 ac = c - a;
    vec3 ap = q - a;
    float d1 = dot(ab, ap);
    float d2 = dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) return dot(ap, ap);
    vec3 bp = q - b;
    float d3 = dot(ab, bp);
    float d4 = dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) return dot(bp, bp);
    float vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        vec3 e = ap - (d1 / (d1 - d3)) * ab;
        return dot(e, e);
    }
    vec3 cp = q - c;
    float d5 = dot(ab, cp);
    float d6 = dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) return dot(cp, cp);
    float vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        vec3 e = ap - (d2 / (d2 - d6)) * ac;
        return dot(e, e);
    }
    float va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
        vec3 e = bp - ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
        return dot(e, e);
    }
    float denom = 1.0 / (va + vb + vc);
    vec3 e = ap - ab * (vb * denom) - ac * (vc * denom);
    return dot(e, e);
}

// Whether v lies on or under the plane τ above the surface.
bool below(vec3 v, ClearancePlane plane) {
    return dot(v - plane.point, plane.normal) <= plane.tau;
}

// Whether the whole box lo..hi lies on or under that plane (its highest corner does).
bool box_below(vec3 lo, vec3 hi, ClearancePlane plane) {
    vec3 center = 0.5 * (lo + hi);
    vec3 half_extent = 0.5 * (hi - lo);
    return dot(center - plane.point, plane.normal) + dot(half_extent, abs(plane.normal)) <= 0.5 * plane.tau;
}

// The squared distance to a child's box where the search enters it, or -1 where it need not: the
// box is no nearer than the best so far, or lies wholly under the plane. Boxes are compared with
// a little slack, so that rounding never culls a closer triangle.
float enter_distance2(vec3 q, vec3 lo, vec3 hi, ClearancePlane plane, float best2) {
    float d2 = box_distance2(q, lo, hi);
    return d2 * 0.999 < best2 && !box_below(lo, hi, plane) ? d2 : -1.0;
}

// One step of a search at interior node `n`: the child to enter now (`next`, BVH_NO_CHILD: none) and
// the one to enter later (`far`), nearer first, with their boxes' squared distances.
void search_step(vec3 q, BvhNode n, ClearancePlane plane, float best2, out uint next, out float next_d2, out uint far, out float far_d2) {
    float d0 = enter_distance2(q, n.min0, n.max0, plane, best2);
    float d1 = enter_distance2(q, n.min1, n.max1, plane, best2);
    // Nearer child first: what it finds may cull the other.
    bool near0 = d1 < 0.0 || (d0 >= 0.0 && d0 <= d1);
    next = near0 ? n.child0 : n.child1;
    next_d2 = near0 ? d0 : d1;
    far = near0 ? n.child1 : n.child0;
    far_d2 = near0 ? d1 : d0;
    next = next_d2 < 0.0 ? BVH_NO_CHILD : next;
    far = far_d2 < 0.0 ? BVH_NO_CHILD : far;
}

// The nearest triangle of the static part (bottom level from `root`, world space) not wholly
// under the plane, within sqrt(best2).
float static_distance2(vec3 q, ClearancePlane plane, uint root, float best2) {
    uint stack[STACK_SIZE];
    float stack_d2[STACK_SIZE];
    uint sp = 0u;
    uint node = root;  // a child reference: the root is interior
    while (true) {
        if (!bvh_is_leaf(node)) {
            uint next, far;
            float next_d2, far_d2;
            search_step(q, BVH_NODE(node), plane, best2, next, next_d2, far, far_d2);
            if (far != BVH_NO_CHILD && sp < uint(STACK_SIZE)) {  // the tree is at most BVH_MAX_DEPTH deep
                stack[sp] = far;
                stack_d2[sp] = far_d2;
                sp++;
            }
            if (next != BVH_NO_CHILD) {
                node = next;
                continue;
            }
        } else {
            uint first = bvh_leaf_first(node);
            for (uint t = first; t < first + bvh_leaf_count(node); t++) {
                BvhTriangle tri = BVH_TRIANGLE(t);
                vec3 v0 = bvh_vertex(tri.v0), v1 = bvh_vertex(tri.v1), v2 = bvh_vertex(tri.v2);
                if (below(v0, plane) && below(v1, plane) && below(v2, plane)) {
                    continue;
                }
                best2 = min(best2, triangle_distance2(q, v0, v1, v2));
            }
        }
        // A child put aside is entered only if it is still nearer than the best found since.
        node = BVH_NO_CHILD;
        while (sp > 0u && node == BVH_NO_CHILD) {
            sp--;
            node = stack_d2[sp] * 0.999 < best2 ? stack[sp] : BVH_NO_CHILD;
        }
        if (node == BVH_NO_CHILD) {
            break;
        }
    }
    return best2;
}

// The clearance radius of `q` against `plane`, at most `max_radius`, made smaller by a margin
// that covers float rounding, so it never exceeds the true clearance.
float clearance_radius(vec3 q, ClearancePlane plane, float max_radius) {
    float best2 = max_radius * max_radius;
    // The top level: the static part is searched triangle by triangle; an animated instance
    // (a door leaf) counts as its whole world box, which is conservative (the ball only
    // shrinks) and keeps mesh-space distances, which a scaled instance would distort, out of it.
    uint stack[BVH_TOP_STACK_SIZE];
    float stack_d2[BVH_TOP_STACK_SIZE];
    uint sp = 0u;
    uint node = 0u;  // a child reference: the root
    float node_d2 = 0.0;  // its box's squared distance (a leaf's: its part's world box)
    while (true) {
        if (!bvh_is_leaf(node)) {
            uint next, far;
            float next_d2, far_d2;
            search_step(q, bvh_top.nodes[node], plane, best2, next, next_d2, far, far_d2);
            if (far != BVH_NO_CHILD && sp < uint(BVH_TOP_STACK_SIZE)) {  // the top level is at most BVH_TOP_MAX_DEPTH deep
                stack[sp] = far;
                stack_d2[sp] = far_d2;
                sp++;
            }
            if (next != BVH_NO_CHILD) {
                node = next;
                node_d2 = next_d2;
                continue;
            }
        } else {
            uint part = bvh_leaf_first(node);  // a top-level leaf holds one part
            // Two fields of the record, not its 64 bytes (see bvh_part_ray).
            if (bvh_instances.items[part].identity != 0u) {
                best2 = static_distance2(q, plane, bvh_instances.items[part].root, best2);
            } else {
                best2 = min(best2, node_d2);
            }
        }
        node = BVH_NO_CHILD;
        while (sp > 0u && node == BVH_NO_CHILD) {
            sp--;
            node = stack_d2[sp] * 0.999 < best2 ? stack[sp] : BVH_NO_CHILD;
            node_d2 = stack_d2[sp];
        }
        if (node == BVH_NO_CHILD) {
            break;
        }
    }
    // Rounding of the distance: relative to it, and in ULPs of the coordinates involved.
    float magnitude = max(max(abs(q.x), abs(q.y)), max(abs(q.z), trace_scale.scene_scale / 32.0));
    return max(sqrt(best2) * (1.0 - 1.0 / 1024.0) - magnitude * (64.0 / 8388608.0), 0.0);
}

#endif
