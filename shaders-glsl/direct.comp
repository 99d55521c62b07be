#version 460
// Direct light: radiance reflected toward the camera by a Lambertian surface from every
// punctual light, L = ρ/π · Σ E_light. Unshadowed until the trace interface exists.
#include "common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

FRAME_BLOCK(0);
layout(set = 0, binding = 1, std430) readonly buffer Lights { Light lights[]; } lights;
layout(set = 0, binding = 2, rgba32f) uniform readonly image2D gbuffer_position;
layout(set = 0, binding = 3, rgba32f) uniform readonly image2D gbuffer_normal;
layout(set = 0, binding = 4, rgba32f) uniform readonly image2D gbuffer_albedo;
layout(set = 0, binding = 5, rgba32f) uniform writeonly image2D direct;

// Irradiance at `p` (normal `n`) from one light.
vec3 irradiance(Light light, vec3 p, vec3 n) {
    if (light.kind == LIGHT_DIRECTIONAL) {
        return light.intensity * max(dot(n, -light.direction), 0.0);
    }
    vec3 d = light.position - p;
    float dist2 = dot(d, d);
    vec3 l = d * inversesqrt(dist2);
    float falloff = 1.0;
    if (light.kind == LIGHT_SPOT) {
        // glTF's recommended smooth falloff between the outer and inner cone.
        float cos_angle = dot(-l, light.direction);
        float t = clamp((cos_angle - light.cos_outer) / max(light.cos_inner - light.cos_outer, 1e-4), 0.0, 1.0);
        falloff = t * t;
    }
    return light.intensity * (falloff * max(dot(n, l), 0.0) / dist2);
}

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (pixel.x >= int(frame.width) || pixel.y >= int(frame.height)) {
        return;
    }
    vec4 position = imageLoad(gbuffer_position, pixel);
    vec3 radiance = vec3(0.0);
    if (position.w > 0.0) {
        vec3 n = imageLoad(gbuffer_normal, pixel).xyz;
        vec3 albedo = imageLoad(gbuffer_albedo, pixel).rgb;
        vec3 e = vec3(0.0);
        for (uint i = 0u; i < frame.light_count; ++i) {
            e += irradiance(lights.lights[i], position.xyz, n);
        }
        radiance = albedo / PI * e;
    }
    imageStore(direct, pixel, vec4(radiance, 1.0));
}
