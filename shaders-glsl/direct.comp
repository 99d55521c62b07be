#version 460
// Direct light: radiance reflected toward the camera by a Lambertian surface from every
// punctual light it sees, L = ρ/π · Σ V · E_light, with one shadow ray per light (V).
#include "trace.glsl"
#include "common.glsl"
#include "gbuffer.glsl"
#include "light.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

FRAME_BLOCK(0);
layout(set = 0, binding = 1, std430) readonly buffer Lights { Light lights[]; } lights;
GBUFFER_BINDINGS(2)
layout(set = 0, binding = 5, rgba32f) uniform writeonly image2D direct;

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
        radiance = albedo / PI * e;
    }
    imageStore(direct, pixel, vec4(radiance, 1.0));
}
