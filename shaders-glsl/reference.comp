#version 460
// Reference path tracer of the same light transport as the splatting methods: Lambertian
// surfaces, punctual lights and emissive triangles, next-event estimation at every path
// vertex (for emitters one sample by power, weighted by multiple importance sampling against
// the next bounce's cosine sample, which counts the emitters it hits: Veach's power
// heuristic). It estimates the indirect radiance leaving each view sample of the G-buffer (the
// direct part comes from the direct pass) and adds `sample_count` samples to a running sum.
#include "trace.glsl"
#include "common.glsl"
#include "gbuffer.glsl"
#include "light.glsl"
#include "random.glsl"
#include "emitters.glsl"
#include "lowdiscrepancy.glsl"
#include "area_light.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

FRAME_BLOCK(0);
layout(set = 1, binding = 1, std430) readonly buffer Lights { Light lights[]; } lights;
GBUFFER_BINDINGS(2)
layout(set = 1, binding = 5, rgba32f) uniform image2D accumulated;
layout(push_constant) uniform ReferenceParams {
    uint first_sample;   // index of this dispatch's first sample in the sequence
    uint sample_count;   // samples this dispatch adds
    uint max_bounces;    // indirect bounces after the view sample
    uint seed;
    uint roulette_start; // bounces before Russian roulette may end a path
    uint restart;        // 1: start the sum over (else add to it)
    uint pad1;
    uint pad2;
} params;

// Orients the geometric normal of `triangle` to the side of `n`.
vec3 oriented_geometric_normal(uint triangle, vec3 n) {
    vec3 ng = triangle_geometric_normal(triangle);
    return dot(ng, n) < 0.0 ? -ng : ng;
}

vec3 direct_at(vec3 p, vec3 n, vec3 ng) {
    vec3 e = vec3(0.0);
    for (uint i = 0u; i < frame.light_count; ++i) {
        e += visible_irradiance(lights.lights[i], p, n, ng);
    }
    return e;
}

// Veach's power heuristic: the weight of a sample drawn with density `a` where another
// strategy would have drawn it with density `b`.
float power_heuristic(float a, float b) {
    return a * a / max(a * a + b * b, 1e-30);
}

// Irradiance at `p` from one emitter sample (by power, uniform on the triangle) with its shadow
// ray; `mis`: weighted against the cosine sample of the next bounce, which will also count it.
vec3 emitter_sample(vec3 p, vec3 n, vec3 ng, bool mis, inout Rng rng) {
    if (frame.emitter_count == 0u) {
        return vec3(0.0);
    }
    Emitter em = emitters.emitters[select_emitter(rng_next(rng), frame.emitter_count)];
    float u0 = rng_next(rng);
    EmitterPoint e = emitter_point(em.triangle, vec2(u0, rng_next(rng)));
    vec3 l;
    float dist;
    vec3 irr = unshadowed_irradiance(e, p, n, ng, l, dist);
    if (irr == vec3(0.0)) {
        return irr;
    }
    if (!emitter_visible(p, ng, e.position)) {
        return vec3(0.0);
    }
    float weight = 1.0;
    if (mis) {
        float pdf_light = emitter_solid_angle_pdf(em.probability, e.area, dist, abs(dot(e.normal, l)));
        weight = power_heuristic(pdf_light, dot(n, l) / PI);
    }
    return irr * (weight * e.area / em.probability);
}

// Whether the point at barycentrics `b` lies within `d` of the triangle's boundary: its distance
// to the edge opposite vertex k is w_k times that vertex's altitude, 2·area / |edge k|.
bool near_boundary(uint triangle, vec2 b, float d) {
    vec3 p0 = vertex_position(3u * triangle);
    vec3 p1 = vertex_position(3u * triangle + 1u);
    vec3 p2 = vertex_position(3u * triangle + 2u);
    float area2 = length(cross(p1 - p0, p2 - p0));
    vec3 edges = vec3(length(p2 - p1), length(p0 - p2), length(p1 - p0));
    return any(lessThan(bary_weights(b) * area2, d * edges));
}

// One path from the view sample: returns its estimate of the indirect radiance.
vec3 indirect_sample(vec3 p, vec3 n, vec3 ng, vec3 albedo, inout Rng rng) {
    vec3 radiance = vec3(0.0);
    vec3 throughput = albedo;  // ρ/π · L cos / (cos/π): the cosine pdf cancels all but ρ
    for (uint bounce = 1u; bounce <= params.max_bounces; ++bounce) {
        vec3 dir = sample_cosine(n, rng_next(rng), rng_next(rng));
        if (dot(dir, ng) <= 0.0) {
            break;  // below the actual surface: the shading normal lied; no light this way
        }
        vec3 from = offset_ray(p, ng);
        Hit hit = traceClosest(from, dir, 0.0, 1e30);
        if (hit.triangle == NO_HIT) {
            break;
        }
        // Emission that this cosine sample finds, from the second bounce on (light the first
        // bounce finds is direct light), weighted against the emitter sample at `p`.
        if (bounce >= 2u && frame.emitter_count > 0u) {
            vec3 le = triangle_emission(hit.triangle, hit.barycentrics, dir);
            if (le != vec3(0.0)) {
                float probability = emitter_probability(hit.triangle, frame.emitter_count);
                vec3 x_hit = triangle_position(hit.triangle, hit.barycentrics);
                float cos_light = abs(dot(triangle_geometric_normal(hit.triangle), dir));
                float pdf_light = emitter_solid_angle_pdf(probability, triangle_area(hit.triangle), distance(from, x_hit), cos_light);
                radiance += throughput * le * power_heuristic(dot(n, dir) / PI, pdf_light);
            }
        }
        // Into its triangle by a lift, toward the centroid, as photons are stored
        // (nudge_toward), so that a hit on an edge that a sealed wall shares does not send the
        // path on from beyond the wall. Except within a lift of the triangle's boundary: a ray
        // from room A that meets the seam where a zero-thickness wall stands on the floor may be
        // reported on room B's floor triangle, whose centroid lies beyond the wall, and the path
        // went on from room B (one sample in 1.7 million on stress/partition-0mm.gltf, seed 1).
        // There the vertex moves back along the ray it arrived on, as view samples move toward
        // the eye: that segment is free, so the point is on the side the path came from. Not
        // where a lift is as large as the triangle (positions a million metres out, 1/16 m
        // apart, lift 30 m): the move back would carry the vertex halfway to the last one, off
        // every surface, while the move toward the centroid stays on the triangle.
        vec3 x = triangle_position(hit.triangle, hit.barycentrics);
        vec3 middle = triangle_position(hit.triangle, vec2(1.0 / 3.0));
        float lift = lift_size(x);
        vec3 y = near_boundary(hit.triangle, hit.barycentrics, lift) && lift < 0.5 * distance(x, middle)
            ? nudge_toward(x, from)
            : nudge_toward(x, middle);
        vec3 ny = triangle_shading_normal(hit.triangle, hit.barycentrics);
        if (dot(ny, dir) > 0.0) {
            ny = -ny;  // two-sided: face the incoming ray
        }
        vec3 ngy = oriented_geometric_normal(hit.triangle, ny);
        vec3 rho = material_albedo(triangle_material(hit.triangle), triangle_uv(hit.triangle, hit.barycentrics)).rgb;
        // The emitter sample is weighted against the next bounce's unless this vertex is the last.
        vec3 e = direct_at(y, ny, ngy) + emitter_sample(y, ny, ngy, bounce < params.max_bounces, rng);
        radiance += throughput * rho / PI * e;
        throughput *= rho;
        if (bounce >= params.roulette_start) {
            float survive = clamp(max(throughput.r, max(throughput.g, throughput.b)), 0.05, 1.0);
            if (rng_next(rng) >= survive) {
                break;
            }
            throughput /= survive;
        }
        p = y;
        n = ny;
        ng = ngy;
    }
    return radiance;
}

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (pixel.x >= int(frame.width) || pixel.y >= int(frame.height)) {
        return;
    }
    vec3 sum = params.restart != 0u ? vec3(0.0) : imageLoad(accumulated, pixel).rgb;
    vec4 position = imageLoad(gbuffer_position, pixel);
    if (position.w > 0.0) {
        uint triangle = uint(position.w) - 1u;
        vec3 n = imageLoad(gbuffer_normal, pixel).xyz;
        vec3 ng = oriented_geometric_normal(triangle, n);
        vec3 albedo = imageLoad(gbuffer_albedo, pixel).rgb;
        vec3 origin = nudge_toward(position.xyz, frame.camera_position.xyz);
        for (uint s = 0u; s < params.sample_count; ++s) {
            Rng rng = rng_seed(uvec2(pixel), params.first_sample + s, params.seed);
            sum += indirect_sample(origin, n, ng, albedo, rng);
        }
    }
    imageStore(accumulated, pixel, vec4(sum, float(params.first_sample + params.sample_count)));
}
