// Light arriving from punctual lights: unshadowed irradiance, and irradiance with one shadow
// ray. Needs trace.glsl (for the shadow ray) included before it.
#ifndef LEAKLESS_LIGHT_GLSL
#define LEAKLESS_LIGHT_GLSL
#include "common.glsl"

// Direction toward the light and distance to it (infinite for directional lights).
void light_direction(Light light, vec3 p, out vec3 l, out float dist) {
    if (light.kind == LIGHT_DIRECTIONAL) {
        l = -light.direction;
        dist = 1e30;
    } else {
        vec3 d = light.position - p;
        dist = length(d);
        l = d / dist;
    }
}

// Irradiance at `p` on a surface of normal `n` from one light, ignoring occlusion.
vec3 irradiance(Light light, vec3 p, vec3 n) {
    vec3 l;
    float dist;
    light_direction(light, p, l, dist);
    float cos_theta = max(dot(n, l), 0.0);
    if (light.kind == LIGHT_DIRECTIONAL) {
        return light.intensity * cos_theta;
    }
    float falloff = 1.0;
    if (light.kind == LIGHT_SPOT) {
        // glTF's recommended smooth falloff between the outer and inner cone.
        float cos_angle = dot(-l, light.direction);
        float t = clamp((cos_angle - light.cos_outer) / max(light.cos_inner - light.cos_outer, 1e-4), 0.0, 1.0);
        falloff = t * t;
    }
    return light.intensity * (falloff * cos_theta / (dist * dist));
}

// Irradiance including the shadow ray. `ng` is the geometric normal on the same side as the
// shading normal `n`: light behind the actual surface does not count, and the shadow ray
// leaves from that side.
vec3 visible_irradiance(Light light, vec3 p, vec3 n, vec3 ng) {
    vec3 l;
    float dist;
    light_direction(light, p, l, dist);
    // At the light itself there is no direction (a point can land there: a path vertex moved
    // back along its ray, positions a million metres out quantised to 1/16 m).
    if (!(dist > 0.0) || dot(n, l) <= 0.0 || dot(ng, l) <= 0.0) {
        return vec3(0.0);
    }
    vec3 e = irradiance(light, p, n);
    if (e == vec3(0.0)) {
        return e;
    }
    vec3 origin = offset_ray(p, ng);
    return traceOccluded(origin, l, 0.0, dist) ? vec3(0.0) : e;
}

#endif
