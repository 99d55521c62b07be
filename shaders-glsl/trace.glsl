// The one trace interface of leakless (docs/architecture.md §3): traceClosest and traceOccluded, on
// GL_EXT_ray_query against a TLAS (TRACE_RAYQUERY) or on a stack-based traversal of a BVH in
// storage buffers (TRACE_COMPUTE). build.rs compiles every shader including this file in both
// variants. Include it first, right after #version: it may enable an extension.
#ifndef LEAKLESS_TRACE_GLSL
#define LEAKLESS_TRACE_GLSL

#if defined(TRACE_RAYQUERY)
#extension GL_EXT_ray_query : require
#endif

#include "scene.glsl"

struct Hit {
    float t;
    uint triangle;      // original scene triangle index, NO_HIT on a miss
    vec2 barycentrics;  // p = (1-u-v) v0 + u v1 + v v2
};
const uint NO_HIT = 0xffffffffu;

#define TRACE_BINDING 16

// The scene's size (its bounding radius), so that ray offsets scale with the scene: a scene
// scaled ×1000 traces the same rays. Bound by every tracing pass on both backends.
layout(set = 0, binding = TRACE_BINDING + 3) uniform TraceScale {
    float scene_scale;
    float pad0;
    float pad1;
    float pad2;
} trace_scale;

// False when an alpha-masked material cuts the surface away at this point: such candidates
// neither occlude nor count as hits, on both backends.
bool trace_alpha_pass(uint triangle, vec2 barycentrics) {
    Material m = triangle_material(triangle);
    if (m.alpha_cutoff < 0.0) {
        return true;
    }
    return material_albedo(m, triangle_uv(triangle, barycentrics)).a >= m.alpha_cutoff;
}

#if defined(TRACE_RAYQUERY)

layout(set = 0, binding = TRACE_BINDING) uniform accelerationStructureEXT tlas;

Hit trace_backend(vec3 origin, vec3 dir, float tmin, float tmax, bool any_hit) {
    rayQueryEXT q;
    uint flags = any_hit ? gl_RayFlagsTerminateOnFirstHitEXT : gl_RayFlagsNoneEXT;
    rayQueryInitializeEXT(q, tlas, flags, 0xffu, origin, tmin, dir, tmax);
    while (rayQueryProceedEXT(q)) {
        // Only non-opaque (alpha-masked) geometry reaches here.
        if (rayQueryGetIntersectionTypeEXT(q, false) == gl_RayQueryCandidateIntersectionTriangleEXT) {
            uint triangle = uint(rayQueryGetIntersectionPrimitiveIndexEXT(q, false));
            if (trace_alpha_pass(triangle, rayQueryGetIntersectionBarycentricsEXT(q, false))) {
                rayQueryConfirmIntersectionEXT(q);
            }
        }
    }
    Hit hit;
    if (rayQueryGetIntersectionTypeEXT(q, true) == gl_RayQueryCommittedIntersectionTriangleEXT) {
        hit.t = rayQueryGetIntersectionTEXT(q, true);
        hit.triangle = uint(rayQueryGetIntersectionPrimitiveIndexEXT(q, true));
        hit.barycentrics = rayQueryGetIntersectionBarycentricsEXT(q, true);
    } else {
        hit.t = tmax;
        hit.triangle = NO_HIT;
        hit.barycentrics = vec2(0.0);
    }
    return hit;
}

#elif defined(TRACE_COMPUTE)

#include "trace_compute.glsl"

Hit trace_backend(vec3 origin, vec3 dir, float tmin, float tmax, bool any_hit) {
    return trace_bvh(origin, dir, tmin, tmax, any_hit);
}

#else
#error "trace.glsl needs TRACE_RAYQUERY or TRACE_COMPUTE (build.rs defines one)"
#endif

Hit traceClosest(vec3 origin, vec3 dir, float tmin, float tmax) {
    return trace_backend(origin, dir, tmin, tmax, false);
}

bool traceOccluded(vec3 origin, vec3 dir, float tmin, float tmax) {
    return trace_backend(origin, dir, tmin, tmax, true).triangle != NO_HIT;
}

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

#endif
