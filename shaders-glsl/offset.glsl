// Ray origins off surfaces, scaled with the scene: the `trace_scale` block and offset_ray.
// Every tracing pass binds it (trace.glsl includes this file), and so does a pass that must
// reproduce the gather's segment endpoints exactly (photon_clearance.comp).
#ifndef LEAKLESS_OFFSET_GLSL
#define LEAKLESS_OFFSET_GLSL

#include "frame_set.glsl"

// The scene's size (its bounding radius), so that ray offsets scale with the scene: a scene
// scaled ×1000 traces the same rays.
layout(set = FRAME_SET, binding = BINDING_TRACE_SCALE) uniform TraceScale {
    float scene_scale;
    uint static_root;  // a scene of one static part: its root (trace_compute.glsl); else NO_HIT
    float pad1;
    float pad2;
    uvec2 bvh_nodes_address;      // bvh.glsl: where the compute BVH's nodes and triangles are
    uvec2 bvh_triangles_address;
    vec3 static_min;   // that part's box, the top level's one box (trace_compute.glsl)
    uint pad3;
    vec3 static_max;
    uint pad4;
} trace_scale;

// Moves a ray origin on a surface off it along the geometric normal `n` (pointing to the side
// the ray leaves on): a fixed number of float ULPs of the position, which scales with its
// magnitude, and near the world origin, where ULPs vanish, a fixed fraction of the scene's
// size (Wächter and Binder, "A Fast and Robust Method for Avoiding Self-Intersection", Ray
// Tracing Gems, 2019, with their constants made relative to the scene so that the offsets
// scale with it).
vec3 offset_ray(vec3 p, vec3 n) {
    float origin = trace_scale.scene_scale / 32.0;
    float float_scale = trace_scale.scene_scale / 65536.0;
    const float int_scale = 256.0;
    ivec3 of_i = ivec3(int_scale * n);
    vec3 p_i = vec3(intBitsToFloat(floatBitsToInt(p.x) + ((p.x < 0.0) ? -of_i.x : of_i.x)),
                    intBitsToFloat(floatBitsToInt(p.y) + ((p.y < 0.0) ? -of_i.y : of_i.y)),
                    intBitsToFloat(floatBitsToInt(p.z) + ((p.z < 0.0) ? -of_i.z : of_i.z)));
    return vec3(abs(p.x) < origin ? p.x + float_scale * n.x : p_i.x,
                abs(p.y) < origin ? p.y + float_scale * n.y : p_i.y,
                abs(p.z) < origin ? p.z + float_scale * n.z : p_i.z);
}

// How far `nudge_toward` moves a point: the size of offset_ray's lift at `p` (256 float ULPs
// of its largest coordinate, and near the origin a fixed fraction of the scene's size).
float lift_size(vec3 p) {
    float magnitude = max(max(abs(p.x), abs(p.y)), abs(p.z));
    return max(magnitude * (256.0 / 8388608.0), trace_scale.scene_scale / 65536.0);
}

// `p` moved toward `target` by lift_size(p), at most half-way. Two uses:
// * toward the eye, for a view sample before its rays leave. The raster (or any primary hit)
//   can land a rounding error inside a solid where two surfaces meet in a shared plane (a wall
//   box standing on a side wall: its face and the side wall meet along the wall's plane), and
//   lifting that point along its own normal keeps it inside, so every ray from it is blocked:
//   a lone black pixel. The segment from the eye to the sample is free by construction, so a
//   point on it a little toward the eye is outside.
// * toward its triangle's centroid, for a photon's hit point. A point on an edge that another
//   surface shares (a zero-thickness wall standing on a floor, sealed along that edge), or a
//   rounding error past it, is then strictly on its own side of that surface, by far more than
//   the rounding of a segment's crossing: a visibility segment to it from beyond the wall
//   crosses the wall, and the next bounce cannot start beyond it.
//   The reference path tracer does the same except within a lift of the triangle's boundary,
//   where it moves the vertex back along the ray it arrived on (reference.comp says why).
vec3 nudge_toward(vec3 p, vec3 target) {
    vec3 d = target - p;
    float len = length(d);
    if (!(len > 0.0)) {
        return p;
    }
    return p + d * (min(lift_size(p), 0.5 * len) / len);
}

// Where a view sample's visibility segments leave from: the sample `x` moved toward the eye
// (above), then lifted along its geometric normal `ng`. The gather and sample_clearance.comp
// must agree on it.
vec3 sample_segment_start(vec3 x, vec3 ng, vec3 eye) {
    return offset_ray(nudge_toward(x, eye), ng);
}

#endif
