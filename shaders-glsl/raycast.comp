#version 460
// Traces a list of rays through the trace interface: closest hits or occlusion. Used to
// compare backends ray by ray and to measure rays per second.
#include "trace.glsl"

layout(local_size_x = 64) in;

struct Ray {
    vec3 origin;
    float tmin;
    vec3 dir;
    float tmax;
};

struct RayHit {
    float t;
    uint triangle;  // NO_HIT on a miss; for occlusion rays 0 = occluded, NO_HIT = clear
    vec2 barycentrics;
};

layout(set = 1, binding = 0, std430) readonly buffer Rays { Ray rays[]; } rays;
layout(set = 1, binding = 1, std430) writeonly buffer RayHits { RayHit hits[]; } ray_hits;
// Per ray, the compute traversal's work (nodes processed, triangles tested) where the pipeline
// counts it (TRACE_COUNT_WORK, trace_compute.glsl); untouched otherwise and on ray queries.
struct RayWork {
    uint nodes;
    uint triangles;
};
layout(set = 1, binding = 2, std430) writeonly buffer RayWorks { RayWork work[]; } ray_work;
layout(push_constant) uniform RaycastParams {
    uint ray_count;
    uint occlusion;  // 1: traceOccluded, 0: traceClosest
    uint pad0;
    uint pad1;
} params;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= params.ray_count) {
        return;
    }
    Ray r = rays.rays[i];
    RayHit out_hit;
    if (params.occlusion != 0u) {
        bool occluded = traceOccluded(r.origin, r.dir, r.tmin, r.tmax);
        out_hit.t = 0.0;
        out_hit.triangle = occluded ? 0u : NO_HIT;
        out_hit.barycentrics = vec2(0.0);
    } else {
        Hit h = traceClosest(r.origin, r.dir, r.tmin, r.tmax);
        out_hit.t = h.t;
        out_hit.triangle = h.triangle;
        out_hit.barycentrics = h.barycentrics;
    }
    ray_hits.hits[i] = out_hit;
#if defined(TRACE_COMPUTE)
    if (TRACE_COUNT_WORK) {
        ray_work.work[i] = RayWork(trace_nodes_visited, trace_triangles_tested);
    }
#endif
}
