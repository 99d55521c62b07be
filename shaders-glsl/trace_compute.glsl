// The compute-shader trace backend (docs/architecture.md §3): a stack-based traversal of the binary BVH
// that crates/accel builds on the CPU. trace.glsl includes this file under TRACE_COMPUTE after
// defining Hit, NO_HIT and trace_alpha_pass.
//
// Bvh::traverse and intersect_triangle in crates/accel/src/bvh*.rs are this file's CPU twin,
// operation for operation (its single loop visits a ray's nodes in the order this file's nested
// loops do), and the tests there (brute force, watertightness) speak for it:
// change both together.
#ifndef LEAKLESS_TRACE_COMPUTE_GLSL
#define LEAKLESS_TRACE_COMPUTE_GLSL

#include "bvh.glsl"

// The traversal pushes at most one node per tree level, and no BVH is deeper than
// BVH_MAX_DEPTH = 64 (crates/accel: PLOC trees are 20-35 deep for 200k triangles, and a deeper
// one is rebuilt with binned SAH, which bounds the depth; a test checks the two constants
// agree), so this stack never overflows.
#define BVH_STACK_SIZE 64

// 1 + 2γ₃ (Ize, "Robust BVH Ray Traversal", 2013): scaling the far slab distance by it keeps
// the box test from culling a box the exact ray touches. The builder also pads every box by a
// few ulps of the scene's scale to cover the triangle test's own rounding.
const float BVH_ROBUST_FAR = 1.0000004;

// What the tests need of a ray, computed once.
struct BvhRay {
    vec3 origin;
    vec3 inv_dir;  // ±inf on an axis the ray does not move along
    uvec3 k;       // kx, ky, kz: kz is the axis of the largest |dir|
    vec3 shear;    // dir[kx]/dir[kz], dir[ky]/dir[kz], 1/dir[kz]
};

BvhRay bvh_ray(vec3 origin, vec3 dir) {
    vec3 a = abs(dir);
    // Ties pick the lowest axis, as on the CPU.
    uint kz = (a.x >= a.y && a.x >= a.z) ? 0u : (a.y >= a.z ? 1u : 2u);
    // Woop et al. swap kx and ky when dir[kz] < 0 to keep the winding. Surfaces are two-sided
    // and the swap only flips the signs of u, v, w and det together, so it is left out.
    uint kx = (kz + 1u) % 3u;
    uint ky = (kx + 1u) % 3u;
    BvhRay ray;
    ray.origin = origin;
    ray.inv_dir = 1.0 / dir;
    ray.k = uvec3(kx, ky, kz);
    ray.shear = vec3(dir[kx] / dir[kz], dir[ky] / dir[kz], 1.0 / dir[kz]);
    return ray;
}

// Whether the ray meets the box lo..hi within [tmin, tmax], and where it enters. Near and far planes
// are picked by the sign of 1/dir rather than with min/max: on an axis the ray does not move
// along that gives ±inf, or NaN for a ray exactly in a face plane, and the comparisons below
// are written so that NaN leaves the interval as it is, which is right for such a ray.
bool bvh_box(BvhRay ray, vec3 lo, vec3 hi, float tmin, float tmax, out float entry) {
    bvec3 neg = lessThan(ray.inv_dir, vec3(0.0));
    vec3 t_near = (mix(lo, hi, neg) - ray.origin) * ray.inv_dir;
    vec3 t_far = (mix(hi, lo, neg) - ray.origin) * ray.inv_dir * BVH_ROBUST_FAR;
    float near = tmin;
    float far = tmax;
    near = t_near.x > near ? t_near.x : near;
    near = t_near.y > near ? t_near.y : near;
    near = t_near.z > near ? t_near.z : near;
    far = t_far.x < far ? t_far.x : far;
    far = t_far.y < far ? t_far.y : far;
    far = t_far.z < far ? t_far.z : far;
    entry = near;
    return near <= far;
}

// Watertight ray/triangle test (Woop, Benthin and Wald, JCGT 2013): move the origin to the ray
// origin, permute so the ray's dominant axis is z, shear so the ray is the z axis, and take the
// 2D edge functions at the origin. Hits have t in (tmin, tmax); barycentrics (u, v) mean
// p = (1-u-v) v0 + u v1 + v v2, as GL_EXT_ray_query reports them.
//
// Watertight without the paper's double-precision fallback: a vertex shared by two triangles
// goes through the same operations to the same values, and a shared edge's function from the
// other side is the same products subtracted the other way round, exactly the negation. So a
// ray through a shared edge or vertex sees matching zeros, and since zero counts as inside, a
// triangle on one side always reports it. `precise` (which covers every operation feeding the
// variable) forbids the fused multiply-adds that would break that symmetry.
bool bvh_triangle(BvhRay ray, BvhTriangle tri, float tmin, float tmax, out float t, out vec2 barycentrics) {
    vec3 a = bvh_vertex(tri.v0) - ray.origin;
    vec3 b = bvh_vertex(tri.v1) - ray.origin;
    vec3 c = bvh_vertex(tri.v2) - ray.origin;
    float ax = a[ray.k.x] - ray.shear.x * a[ray.k.z];
    float ay = a[ray.k.y] - ray.shear.y * a[ray.k.z];
    float bx = b[ray.k.x] - ray.shear.x * b[ray.k.z];
    float by = b[ray.k.y] - ray.shear.y * b[ray.k.z];
    float cx = c[ray.k.x] - ray.shear.x * c[ray.k.z];
    float cy = c[ray.k.y] - ray.shear.y * c[ray.k.z];
    // Twice the signed areas of the sub-triangles the ray splits the projected triangle into.
    precise float u = cx * by - cy * bx;
    precise float v = ax * cy - ay * cx;
    precise float w = bx * ay - by * ax;
    // Mixed signs: the ray passes outside. Zeros count as inside (see above).
    if ((u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0)) {
        return false;
    }
    float det = u + v + w;
    if (det == 0.0) {
        return false;  // degenerate, or the ray lies in the triangle's plane
    }
    float sz = ray.shear.z;
    float t_scaled = u * (sz * a[ray.k.z]) + v * (sz * b[ray.k.z]) + w * (sz * c[ray.k.z]);
    float inv_det = 1.0 / det;
    t = t_scaled * inv_det;
    barycentrics = vec2(v, w) * inv_det;
    return t > tmin && t < tmax;
}

// Which children of an interior node (references c0, c1; h0/h1: their boxes are hit, d0/d1:
// where the ray enters them) to visit: `next` now (NO_HIT: neither, pop the stack) and `far`
// later (NO_HIT: none). Near child first: its hits shrink the ray and may cull the far one.
void bvh_children(bool h0, bool h1, float d0, float d1, uint c0, uint c1, out uint next, out uint far) {
    far = NO_HIT;
    next = NO_HIT;
    if (h0 && h1) {
        bool near0 = d0 <= d1;
        next = near0 ? c0 : c1;
        far = near0 ? c1 : c0;
    } else if (h0 || h1) {
        next = h0 ? c0 : c1;
    }
}

// A plane that the caller's ray lies wholly above (TRACE_PLANE_CULL, defined by a module before
// it includes trace.glsl: the gather, whose visibility segments run a lift above the surface
// their photon lies on): a box wholly below it, dot(p, xyz) < w for each of its points, holds
// no triangle the ray can meet, and is not entered. Exact: the ray and the box are on the two
// sides of one plane. Only where the ray is in world space (the top level, and a part that is
// not moved); w = -inf sets it off. The CPU twin has no such plane: nothing compares the
// gather's rays with it, and the images are the traversal's without the plane bit for bit.
#ifdef TRACE_PLANE_CULL
vec4 trace_cull_plane = vec4(0.0, 0.0, 0.0, -3.0e38);
bool trace_cull_world = true;  // the ray being walked is in world space
bool bvh_box_below(vec3 lo, vec3 hi) {
    vec3 n = trace_cull_plane.xyz;
    return trace_cull_world && dot(mix(lo, hi, greaterThan(n, vec3(0.0))), n) < trace_cull_plane.w;
}
#endif

// One traversal step at interior node `n`: its children to visit now and later (above).
void bvh_step(BvhRay ray, BvhNode n, float tmin, float tmax, out uint next, out uint far) {
    float d0, d1;
    bool h0 = bvh_box(ray, n.min0, n.max0, tmin, tmax, d0);
    bool h1 = bvh_box(ray, n.min1, n.max1, tmin, tmax, d1);
#ifdef TRACE_PLANE_CULL
    h0 = h0 && !bvh_box_below(n.min0, n.max0);
    h1 = h1 && !bvh_box_below(n.min1, n.max1);
#endif
    bvh_children(h0, h1, d0, d1, n.child0, n.child1, next, far);
}

// A world ray in part `part`'s space: the static part's is the world ray itself; an
// instance's origin and direction go through the inverse of its transform, which keeps the ray
// parameter t, so hits in different parts compare.
//
// The record is read field by field, its map only for an instance: read whole, its 64 bytes
// would be loaded for every ray (the map's loads are not moved into the branch that uses
// them), though a static scene's one part needs 4 of them.
BvhRay bvh_part_ray(uint part, BvhRay world, vec3 origin, vec3 dir) {
    if (trace_scale.static_root != NO_HIT || bvh_instances.items[part].identity != 0u) {
        return world;
    }
    vec4 m0 = bvh_instances.items[part].local_from_world0;
    vec4 m1 = bvh_instances.items[part].local_from_world1;
    vec4 m2 = bvh_instances.items[part].local_from_world2;
    vec4 o = vec4(origin, 1.0);
    vec3 local_origin = vec3(dot(m0, o), dot(m1, o), dot(m2, o));
    vec3 local_dir = vec3(dot(m0.xyz, dir), dot(m1.xyz, dir), dot(m2.xyz, dir));
    return bvh_ray(local_origin, local_dir);
}

// The traversal's work, counted where TRACE_COUNT_WORK is on (bench rays' counting pass,
// raycast.comp): the bottom-level nodes it processes and the triangles it tests, as
// Bvh::traverse counts them on the CPU. Off, its default, in every other pipeline: the counts
// compile away. naga parses no specialization constant outside an array size: the reflection
// twin has it off.
#ifdef LEAKLESS_REFLECTION
#define TRACE_COUNT_WORK false
#else
layout(constant_id = 10) const bool TRACE_COUNT_WORK = false;
#endif
uint trace_nodes_visited = 0u;
uint trace_triangles_tested = 0u;

// The bottom level of one part (root node `root`), `ray` in its space: the closest hit with t in
// (tmin, hit.t) replaces `hit`, and `slot` becomes its index in bvh_triangles. With any_hit,
// returns true at the first accepted hit.
//
// The walk starts at `root`, or (NO_HIT) at those of a tile's `entries` whose boxes the ray
// meets (segment_entries.comp: the nodes under which lies every triangle a short segment can
// meet, each as its parent · 2 + which child), tested as the steps above them would have. The
// stack has room for them beside one node a level. The CPU twin walks from the root only: only
// the gather's segments start at entries, and its images are those of the walk from the root
// bit for bit (the identity hashes).
bool trace_bvh_walk(BvhRay ray, uint root, uvec4 entries, uint count, float tmin, bool any_hit, inout Hit hit,
                    inout uint slot) {
    uint stack[BVH_STACK_SIZE + 4];
    uint sp = 0u;
    for (uint i = count; i > 0u; --i) {
        // Only the entry's own child is read: a select between the node's two children would
        // load both (on a CPU driver a load is paid per lane and word; docs/results.md, "Rays").
        uint at = entries[i - 1u];
        uint parent = at >> 1u;
        vec3 lo, hi;
        uint child;
        if ((at & 1u) != 0u) {
            lo = BVH_NODE(parent).min1;
            hi = BVH_NODE(parent).max1;
            child = BVH_NODE(parent).child1;
        } else {
            lo = BVH_NODE(parent).min0;
            hi = BVH_NODE(parent).max0;
            child = BVH_NODE(parent).child0;
        }
        float d;
        bool h = bvh_box(ray, lo, hi, tmin, hit.t, d);
#ifdef TRACE_PLANE_CULL
        h = h && !bvh_box_below(lo, hi);
#endif
        if (h) {
            stack[sp] = child;
            sp++;
        }
    }
    uint node = root;  // a child reference
    if (node == NO_HIT && sp > 0u) {
        sp--;
        node = stack[sp];
    }
    // While-while (Aila and Laine, 2009): each invocation descends through interior nodes until
    // it holds a leaf, and only then tests triangles. Lanes that run together (a SIMD group on
    // a CPU driver, a subgroup on a GPU) then test their leaves' triangles in one pass instead
    // of one lane's leaf per iteration of a single loop. The order in which one ray visits
    // nodes is the if-if loop's, so hits and counts are unchanged.
    while (node != NO_HIT) {
        while (!bvh_is_leaf(node)) {
            if (TRACE_COUNT_WORK) {
                trace_nodes_visited++;
            }
            uint next, far;
            // hit.t shrinks as hits are found, culling everything behind the closest one.
            bvh_step(ray, BVH_NODE(node), tmin, hit.t, next, far);
            if (far != NO_HIT && sp < uint(BVH_STACK_SIZE + 4)) {  // always room (see BVH_STACK_SIZE)
                stack[sp] = far;
                sp++;
            }
            if (next == NO_HIT) {
                if (sp == 0u) {
                    return false;
                }
                sp--;
                next = stack[sp];
            }
            node = next;
        }
        if (TRACE_COUNT_WORK) {
            trace_nodes_visited++;
        }
        uint first = bvh_leaf_first(node);
        uint end = first + bvh_leaf_count(node);
        for (uint i = first; i < end; i++) {
            if (TRACE_COUNT_WORK) {
                trace_triangles_tested++;
            }
            BvhTriangle tri = BVH_TRIANGLE(i);
            float t;
            vec2 barycentrics;
            if (bvh_triangle(ray, tri, tmin, hit.t, t, barycentrics) && trace_alpha_pass(tri.triangle, barycentrics)) {
                hit.t = t;
                hit.triangle = tri.triangle;
                hit.barycentrics = barycentrics;
                slot = i;
                if (any_hit) {
                    return true;
                }
            }
        }
        node = NO_HIT;
        if (sp > 0u) {
            sp--;
            node = stack[sp];
        }
    }
    return false;
}

bool trace_bvh_part(BvhRay ray, uint root, float tmin, bool any_hit, inout Hit hit, inout uint slot) {
    return trace_bvh_walk(ray, root, uvec4(NO_HIT), 0u, tmin, any_hit, hit, slot);
}

// The closest hit with t in (tmin, tmax), or with any_hit the first accepted one (occlusion).
// Every candidate goes through trace_alpha_pass before it counts. On a miss, triangle is
// NO_HIT and t is tmax. `slot` is the hit's index in bvh_triangles and the part it belongs to
// (for trace_bvh_occluded_cached). The top level is walked like a bottom level, near child
// first; its leaves are parts.
Hit trace_bvh_slot(vec3 origin, vec3 dir, float tmin, float tmax, bool any_hit, out uvec2 slot) {
    slot = uvec2(NO_HIT);
    Hit hit;
    hit.t = tmax;
    hit.triangle = NO_HIT;
    hit.barycentrics = vec2(0.0);
    BvhRay ray = bvh_ray(origin, dir);
    uint stack[BVH_TOP_STACK_SIZE];
    uint sp = 0u;
    uint node = 0u;  // a child reference: the root
    if (trace_scale.static_root != NO_HIT) {
        // A scene of one static part: its top level is a root whose one child is the part's
        // leaf, so its one step is this box test, and the ray goes on to the leaf without
        // reading the top level or the part's record, which are bound, not read through
        // addresses (a CPU driver loads each a lane at a time).
        float entry;
        if (!bvh_box(ray, trace_scale.static_min, trace_scale.static_max, tmin, hit.t, entry)) {
            return hit;
        }
        node = BVH_LEAF;  // part 0's leaf
    }
    while (true) {
        if (!bvh_is_leaf(node)) {
            uint next, far;
            bvh_step(ray, bvh_top.nodes[node], tmin, hit.t, next, far);
            if (far != NO_HIT && sp < uint(BVH_TOP_STACK_SIZE)) {  // always room (BVH_TOP_STACK_SIZE)
                stack[sp] = far;
                sp++;
            }
            if (next != NO_HIT) {
                node = next;
                continue;
            }
        } else {
            uint part = bvh_leaf_first(node);  // a top-level leaf holds one part
            uint root = trace_scale.static_root;
            if (root == NO_HIT) {
                root = bvh_instances.items[part].root;
            }
            uint closest = slot.x;
#ifdef TRACE_PLANE_CULL
            trace_cull_world = trace_scale.static_root != NO_HIT || bvh_instances.items[part].identity != 0u;
#endif
            bool done = trace_bvh_part(bvh_part_ray(part, ray, origin, dir), root, tmin, any_hit, hit, closest);
#ifdef TRACE_PLANE_CULL
            trace_cull_world = true;
#endif
            if (closest != slot.x) {
                slot = uvec2(closest, part);
            }
            if (done) {
                return hit;
            }
        }
        if (sp == 0u) {
            break;
        }
        sp--;
        node = stack[sp];
    }
    return hit;
}

Hit trace_bvh(vec3 origin, vec3 dir, float tmin, float tmax, bool any_hit) {
    uvec2 slot;
    return trace_bvh_slot(origin, dir, tmin, tmax, any_hit, slot);
}

// Occlusion, trying first the triangle that blocked this invocation's last blocked ray
// (`cached_slot`: its index in bvh_triangles and its part; NO_HIT for none). Rays from one view sample to the photons around it are
// mostly blocked by the same wall, and one triangle test is far cheaper than a traversal.
// Exact: a triangle the test reports is one the traversal would reach too (its boxes are
// padded and tested robustly, above; the ray is moved into the triangle's part as the
// traversal moves it), so the answer is the traversal's.
bool trace_bvh_cached_blocks(vec3 origin, vec3 dir, float tmin, float tmax, uvec2 cached_slot) {
    if (cached_slot.x != NO_HIT) {
        BvhTriangle tri = BVH_TRIANGLE(cached_slot.x);
        BvhRay ray = bvh_part_ray(cached_slot.y, bvh_ray(origin, dir), origin, dir);
        float t;
        vec2 barycentrics;
        if (bvh_triangle(ray, tri, tmin, tmax, t, barycentrics)
            && trace_alpha_pass(tri.triangle, barycentrics)) {
            return true;
        }
    }
    return false;
}

bool trace_bvh_occluded_cached(vec3 origin, vec3 dir, float tmin, float tmax, inout uvec2 cached_slot) {
    if (trace_bvh_cached_blocks(origin, dir, tmin, tmax, cached_slot)) {
        return true;
    }
    uvec2 slot;
    bool occluded = trace_bvh_slot(origin, dir, tmin, tmax, true, slot).triangle != NO_HIT;
    cached_slot = occluded ? slot : cached_slot;
    return occluded;
}

// The same in a scene of one static part, the walk starting at `count` entries that hold every
// triangle the ray can meet (segment_entries.comp: the caller checks that its segment lies in
// their region). Exact as above: the triangles the walk from the root could report are under
// the entries, and the answer is the same.
bool trace_bvh_occluded_cached_from(vec3 origin, vec3 dir, float tmin, float tmax, uvec4 entries, uint count,
                                    inout uvec2 cached_slot) {
    if (trace_bvh_cached_blocks(origin, dir, tmin, tmax, cached_slot)) {
        return true;
    }
    Hit hit;
    hit.t = tmax;
    hit.triangle = NO_HIT;
    hit.barycentrics = vec2(0.0);
    uint closest = NO_HIT;
    bool occluded = trace_bvh_walk(bvh_ray(origin, dir), NO_HIT, entries, count, tmin, true, hit, closest);
    cached_slot = occluded ? uvec2(closest, 0u) : cached_slot;
    return occluded;
}

#endif
