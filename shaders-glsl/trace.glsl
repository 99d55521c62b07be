// The one trace interface of leakless (docs/architecture.md §3): traceClosest and traceOccluded, on
// GL_EXT_ray_query against a TLAS (TRACE_RAYQUERY) or on a stack-based traversal of a BVH in
// storage buffers (TRACE_COMPUTE). crates/renderer/build.rs compiles every shader including this file in both
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

#include "offset.glsl"

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

// One instance per part of the scene (the static triangles; each animated instance), its custom
// index the part's first scene triangle: custom index + primitive index names the triangle in
// the scene's list, as the compute backend's hits do.
layout(set = FRAME_SET, binding = BINDING_TLAS) uniform accelerationStructureEXT tlas;

Hit trace_backend(vec3 origin, vec3 dir, float tmin, float tmax, bool any_hit) {
    rayQueryEXT q;
    uint flags = any_hit ? gl_RayFlagsTerminateOnFirstHitEXT : gl_RayFlagsNoneEXT;
    rayQueryInitializeEXT(q, tlas, flags, 0xffu, origin, tmin, dir, tmax);
    while (rayQueryProceedEXT(q)) {
        // Only non-opaque (alpha-masked) geometry reaches here.
        if (rayQueryGetIntersectionTypeEXT(q, false) == gl_RayQueryCandidateIntersectionTriangleEXT) {
            uint triangle = uint(rayQueryGetIntersectionInstanceCustomIndexEXT(q, false))
                + uint(rayQueryGetIntersectionPrimitiveIndexEXT(q, false));
            if (trace_alpha_pass(triangle, rayQueryGetIntersectionBarycentricsEXT(q, false))) {
                rayQueryConfirmIntersectionEXT(q);
            }
        }
    }
    Hit hit;
    if (rayQueryGetIntersectionTypeEXT(q, true) == gl_RayQueryCommittedIntersectionTriangleEXT) {
        hit.t = rayQueryGetIntersectionTEXT(q, true);
        hit.triangle = uint(rayQueryGetIntersectionInstanceCustomIndexEXT(q, true))
            + uint(rayQueryGetIntersectionPrimitiveIndexEXT(q, true));
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
#error "trace.glsl needs TRACE_RAYQUERY or TRACE_COMPUTE (crates/renderer/build.rs defines one)"
#endif

Hit traceClosest(vec3 origin, vec3 dir, float tmin, float tmax) {
    return trace_backend(origin, dir, tmin, tmax, false);
}

bool traceOccluded(vec3 origin, vec3 dir, float tmin, float tmax) {
    return trace_backend(origin, dir, tmin, tmax, true).triangle != NO_HIT;
}

// traceOccluded for many rays of one invocation that tend to be blocked by the same surface:
// `cache` (start it at uvec2(NO_HIT)) carries what the last blocked ray learnt. The answer is always
// traceOccluded's; only the compute backend uses the cache (trace_bvh_occluded_cached), since
// a ray query cannot be asked about one triangle.
bool traceOccludedCached(vec3 origin, vec3 dir, float tmin, float tmax, inout uvec2 cache) {
#if defined(TRACE_COMPUTE)
    return trace_bvh_occluded_cached(origin, dir, tmin, tmax, cache);
#else
    return traceOccluded(origin, dir, tmin, tmax);
#endif
}

#endif
