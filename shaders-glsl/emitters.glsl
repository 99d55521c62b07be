// Emissive triangles as area lights (crates/renderer/src/emitters.rs): picking one by power, a point on it,
// what it emits, and the densities MIS needs. Needs scene.glsl included before it (the shadow
// rays are area_light.glsl's).
#ifndef LEAKLESS_EMITTERS_GLSL
#define LEAKLESS_EMITTERS_GLSL
#include "common.glsl"
#include "frame_set.glsl"

// Twin: `gpu_types::Emitter`.
struct Emitter {
    uint triangle;
    float cdf;          // Σ probability up to this emitter; the last is 1
    float probability;  // chance that `select_emitter` picks it
    uint pad0;
};

layout(set = FRAME_SET, binding = BINDING_EMITTERS, std430) readonly buffer Emitters { Emitter emitters[]; } emitters;

// The first emitter whose CDF exceeds u (u in [0, 1)).
uint select_emitter(float u, uint count) {
    uint lo = 0u;
    uint hi = count - 1u;
    while (lo < hi) {
        uint mid = (lo + hi) / 2u;
        if (u < emitters.emitters[mid].cdf) {
            hi = mid;
        } else {
            lo = mid + 1u;
        }
    }
    return lo;
}

// Barycentrics (ray-query convention) of a uniform point on a triangle from the unit square:
// the square folded onto the triangle along its diagonal (area-preserving, keeps strata).
vec2 uniform_triangle(vec2 u) {
    return u.x + u.y > 1.0 ? vec2(1.0 - u.x, 1.0 - u.y) : u;
}

// A point on an emissive triangle and what it emits.
struct EmitterPoint {
    vec3 position;
    vec3 normal;    // the front face's (counter-clockwise winding) unit normal
    vec2 uv;
    float area;     // the triangle's area as posed now
    Material material;
};

EmitterPoint emitter_point(uint triangle, vec2 u) {
    vec2 b = uniform_triangle(u);
    vec3 p0 = vertex_position(3u * triangle);
    vec3 c = cross(vertex_position(3u * triangle + 1u) - p0, vertex_position(3u * triangle + 2u) - p0);
    float len = length(c);
    return EmitterPoint(triangle_position(triangle, b), c / max(len, 1e-30), triangle_uv(triangle, b), 0.5 * len,
                        triangle_material(triangle));
}

// Radiance the point emits along unit `dir` (away from it); none where an alpha mask cuts the
// surface away (tracing never finds such points; sampling the triangle's area can).
vec3 emitted_toward(EmitterPoint e, vec3 dir) {
    if (e.material.alpha_cutoff >= 0.0 && material_albedo(e.material, e.uv).a < e.material.alpha_cutoff) {
        return vec3(0.0);
    }
    return material_emission(e.material, e.uv, dot(e.normal, dir) > 0.0);
}

// Emitted radiance of `triangle` at barycentrics `b`, seen along unit `dir` (toward the surface).
vec3 triangle_emission(uint triangle, vec2 b, vec3 dir) {
    Material m = triangle_material(triangle);
    if (m.emission == vec3(0.0)) {
        return vec3(0.0);
    }
    return material_emission(m, triangle_uv(triangle, b), dot(triangle_geometric_normal(triangle), dir) < 0.0);
}

// The chance that `select_emitter` picks `triangle` (0 for triangles that do not emit): the
// table is in triangle order, so a binary search finds it.
float emitter_probability(uint triangle, uint count) {
    uint lo = 0u;
    uint hi = count;
    while (lo < hi) {
        uint mid = (lo + hi) / 2u;
        if (emitters.emitters[mid].triangle < triangle) {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    return lo < count && emitters.emitters[lo].triangle == triangle ? emitters.emitters[lo].probability : 0.0;
}

// Solid-angle density with which next-event estimation (`probability` of picking the
// triangle, then a uniform point on it) samples the direction toward a point of a triangle of
// `area` seen at distance `dist` under cosine `cos_light` at the emitter.
float emitter_solid_angle_pdf(float probability, float area, float dist, float cos_light) {
    return cos_light > 0.0 && area > 0.0 ? probability * dist * dist / (area * cos_light) : 0.0;
}

float triangle_area(uint triangle) {
    vec3 p0 = vertex_position(3u * triangle);
    return 0.5 * length(cross(vertex_position(3u * triangle + 1u) - p0, vertex_position(3u * triangle + 2u) - p0));
}

#endif
