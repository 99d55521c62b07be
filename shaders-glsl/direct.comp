#version 460
// Direct light: radiance reflected toward the camera by a Lambertian surface, L = ρ/π · E,
// from every punctual light it sees (one shadow ray per light, exact) and from the emissive
// triangles (resampled next-event estimation, area_light.glsl: an estimate per frame that an
// accumulation averages), plus the radiance the surface itself emits toward the camera.
#include "trace.glsl"
#include "common.glsl"
#include "gbuffer.glsl"
#include "light.glsl"
#include "emitters.glsl"
#include "lowdiscrepancy.glsl"
#include "random.glsl"
#include "area_light.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

FRAME_BLOCK(0);
layout(set = 1, binding = 1, std430) readonly buffer Lights { Light lights[]; } lights;
GBUFFER_BINDINGS(2)
layout(set = 1, binding = 5, rgba32f) uniform writeonly image2D direct;
layout(push_constant) uniform DirectParams {
    uint first_sample; // the frame's first emitter sample: an accumulation continues one sequence
    uint samples;      // shadow rays to emitters per pixel
    uint candidates;   // emitter points resampled per shadow ray
    uint seed;
} params;

// Barycentrics (ray-query convention) of `p` on the plane of `triangle`.
vec2 barycentrics_of(uint triangle, vec3 p) {
    vec3 p0 = vertex_position(3u * triangle);
    vec3 e1 = vertex_position(3u * triangle + 1u) - p0;
    vec3 e2 = vertex_position(3u * triangle + 2u) - p0;
    vec3 d = p - p0;
    float d11 = dot(e1, e1), d12 = dot(e1, e2), d22 = dot(e2, e2);
    float d1 = dot(d, e1), d2 = dot(d, e2);
    float det = d11 * d22 - d12 * d12;
    return det != 0.0 ? vec2(d22 * d1 - d12 * d2, d11 * d2 - d12 * d1) / det : vec2(1.0 / 3.0);
}

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (pixel.x >= int(frame.width) || pixel.y >= int(frame.height)) {
        return;
    }
    vec4 position = imageLoad(gbuffer_position, pixel);
    vec3 radiance = vec3(0.0);
    if (position.w > 0.0) {
        uint triangle = uint(position.w) - 1u;
        vec3 n = imageLoad(gbuffer_normal, pixel).xyz;
        vec3 ng = triangle_geometric_normal(triangle);
        if (dot(ng, n) < 0.0) {
            ng = -ng;
        }
        vec3 albedo = imageLoad(gbuffer_albedo, pixel).rgb;
        vec3 origin = nudge_toward(position.xyz, frame.camera_position.xyz);
        vec3 e = vec3(0.0);
        for (uint i = 0u; i < frame.light_count; ++i) {
            e += visible_irradiance(lights.lights[i], origin, n, ng);
        }
        if (frame.emitter_count > 0u && params.samples > 0u) {
            uint pixel_seed = ld_hash_combine(params.seed, uint(pixel.y) * frame.width + uint(pixel.x));
            Rng rng = rng_seed(uvec2(pixel), params.first_sample, params.seed ^ 0x9e3779b9u);
            e += area_light_irradiance(origin, n, ng, frame.emitter_count, params.first_sample, params.samples,
                                       params.candidates, pixel_seed, rng);
        }
        radiance = albedo / PI * e;
        vec3 toward_surface = position.xyz - frame.camera_position.xyz;
        radiance += triangle_emission(triangle, barycentrics_of(triangle, position.xyz), toward_surface);
    }
    imageStore(direct, pixel, vec4(radiance, 1.0));
}
