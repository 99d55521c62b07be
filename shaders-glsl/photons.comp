#version 460
// Photon tracing (docs/architecture.md §1): one thread per light path. A light is chosen in proportion to
// its emitted power (CDF from src/photon_lights.rs), a direction (and for directional lights an
// origin) is drawn from Owen-scrambled Sobol points, and the path bounces Lambertian-ly. The
// first hit is direct light and is not stored (unless `store_direct`, a diagnostic); every
// later hit appends a photon carrying the flux that arrives there, up to `max_bounces` stored
// hits per path.
#include "trace.glsl"
#include "common.glsl"
#include "random.glsl"
#include "lowdiscrepancy.glsl"
#include "photon.glsl"

layout(local_size_x = 64) in;

// One light's entry in the power CDF. Twin: `PhotonLight` in src/passes/photons.rs.
struct PhotonLight {
    vec3 flux;  // power_rgb / p(light): a path from this light carries flux / paths
    float cdf;  // Σ p(light j) for j <= this light; the last is 1
};

layout(push_constant) uniform PhotonParams {
    vec3 scene_center;   // bounding sphere of the geometry: directional lights' emission disk
    float scene_radius;
    uint paths;
    uint max_bounces;    // stored hits per path
    uint seed;
    uint capacity;       // photons the output buffer holds
    uint light_count;
    uint store_direct;   // 1: store the first hit too (diagnostic: emitted flux)
    uint path_offset;    // index of path 0 in the sequence: accumulated frames continue it
    uint pad1;
} params;
layout(set = 0, binding = 1, std430) readonly buffer Lights { Light lights[]; } lights;
layout(set = 0, binding = 2, std430) readonly buffer PhotonLights { PhotonLight entries[]; } photon_lights;
layout(set = 0, binding = 3, std430) writeonly buffer Photons { Photon photons[]; } photons;
layout(set = 0, binding = 4, std430) buffer PhotonCounters {
    uint stored;      // photons written (never more than capacity)
    uint overflowed;  // photons dropped because the buffer was full
    uint rays;        // closest-hit rays traced (for `bench`'s rays per second)
    uint pad0;
} photon_counters;

// Sample groups of a path (lowdiscrepancy.glsl): emission, then one per bounce.
const uint GROUP_EMISSION = 0u;
const uint GROUP_FIRST_BOUNCE = 1u;

// The first light whose CDF exceeds u (lights of zero power are never chosen).
uint select_light(float u) {
    uint lo = 0u;
    uint hi = params.light_count - 1u;
    while (lo < hi) {
        uint mid = (lo + hi) / 2u;
        if (u < photon_lights.entries[mid].cdf) {
            hi = mid;
        } else {
            lo = mid + 1u;
        }
    }
    return lo;
}

vec3 uniform_sphere(vec2 u) {
    float z = 1.0 - 2.0 * u.x;
    float r = sqrt(max(0.0, 1.0 - z * z));
    float phi = 2.0 * PI * u.y;
    return vec3(r * cos(phi), r * sin(phi), z);
}

// Shirley–Chiu concentric map of the unit square onto the unit disk (area-preserving, keeps
// the stratification of the square).
vec2 concentric_disk(vec2 u) {
    vec2 o = 2.0 * u - 1.0;
    if (o.x == 0.0 && o.y == 0.0) {
        return vec2(0.0);
    }
    float r, theta;
    if (abs(o.x) > abs(o.y)) {
        r = o.x;
        theta = (PI / 4.0) * (o.y / o.x);
    } else {
        r = o.y;
        theta = PI / 2.0 - (PI / 4.0) * (o.x / o.y);
    }
    return r * vec2(cos(theta), sin(theta));
}

// A direction inside a spot light's outer cone, importance-sampled exactly by glTF's smooth
// falloff f(c) = clamp((c − c_outer) / Δ, 0, 1)², c = cos(angle to the axis), Δ = max(c_inner −
// c_outer, 1e-4) as in light.glsl. Over solid angle (dω = dc dφ) the density of c is ∝ f(c):
// a ramp t² (t = (c − c_outer)/Δ ∈ [0, T], T = min(1, (1 − c_outer)/Δ); mass Δ T³/3) then a
// flat part (mass max(0, 1 − c_outer − Δ)). u.x picks the part and is rescaled within it (so
// its stratification carries over); inverse CDFs t = T u^(1/3) and c uniform. The pdf is
// f(c) / ∫f dω exactly, so every path of the light carries the same flux.
vec3 sample_spot(Light light, vec2 u) {
    float c_outer = light.cos_outer;
    float delta = max(light.cos_inner - c_outer, 1e-4);
    float t_max = min(1.0, (1.0 - c_outer) / delta);
    float ramp = delta * t_max * t_max * t_max / 3.0;
    float flat_mass = max(0.0, 1.0 - c_outer - delta);
    float v = u.x * (ramp + flat_mass);
    float c;
    if (v < ramp) {
        c = c_outer + delta * t_max * pow(v / ramp, 1.0 / 3.0);
    } else {
        c = c_outer + delta + (v - ramp);
    }
    c = min(c, 1.0);
    float s = sqrt(max(0.0, 1.0 - c * c));
    float phi = 2.0 * PI * u.y;
    vec3 t, b;
    basis(light.direction, t, b);
    return normalize(c * light.direction + s * (cos(phi) * t + sin(phi) * b));
}

void store_photon(Photon p) {
    uint slot = atomicAdd(photon_counters.stored, 1u);
    if (slot < params.capacity) {
        photons.photons[slot] = p;
    } else {
        // Full: drop it, count it, and pull `stored` back to the capacity. Every increment
        // past the capacity is followed by this same thread's atomicMin, so the last
        // operation on `stored` is a min and it ends at exactly the capacity.
        atomicAdd(photon_counters.overflowed, 1u);
        atomicMin(photon_counters.stored, params.capacity);
    }
}

void main() {
    uint path = gl_GlobalInvocationID.x;
    if (path >= params.paths || params.light_count == 0u) {
        return;
    }
    // Emission: dimensions 0, 1 (the (0,2)-pair) place the direction or the disk point,
    // dimension 2 picks the light.
    // Frames that accumulate continue one low-discrepancy sequence instead of reseeding it.
    uint index = path + params.path_offset;
    vec3 u = ld_sample3(index, GROUP_EMISSION, params.seed);
    uint light_index = select_light(u.z);
    Light light = lights.lights[light_index];
    vec3 flux = photon_lights.entries[light_index].flux / float(params.paths);
    vec3 origin, dir;
    if (light.kind == LIGHT_DIRECTIONAL) {
        // A disk of the bounding sphere's radius, perpendicular to the light, behind the
        // sphere: its parallel rays cover everything in the scene. (Moved back by 1.001 R:
        // any distance >= R gives the same rays; the margin keeps geometry that touches the
        // sphere's far side off t = 0.)
        dir = normalize(light.direction);
        vec3 t, b;
        basis(dir, t, b);
        vec2 d = params.scene_radius * concentric_disk(u.xy);
        origin = params.scene_center - (1.001 * params.scene_radius) * dir + d.x * t + d.y * b;
    } else {
        origin = light.position;
        dir = light.kind == LIGHT_SPOT ? sample_spot(light, u.xy) : uniform_sphere(u.xy);
    }

    // Hits h = 0, 1, ..., max_bounces (0-based; h = bounces before the hit). h = 0 is direct
    // light, stored only with store_direct; h = 1..=max_bounces are the stored indirect hits.
    uint last_hit = params.max_bounces;
    uint rays = 0u;
    for (uint h = 0u; h <= last_hit; ++h) {
        Hit hit = traceClosest(origin, dir, 0.0, 1e30);
        rays += 1u;
        if (hit.triangle == NO_HIT) {
            break;
        }
        // Inside its triangle by a lift, not on an edge it shares with another surface (see
        // nudge_toward): stored there, and the next bounce leaves from there.
        vec3 y = nudge_toward(triangle_position(hit.triangle, hit.barycentrics),
                              triangle_position(hit.triangle, vec2(1.0 / 3.0)));
        vec3 ns = triangle_shading_normal(hit.triangle, hit.barycentrics);
        if (dot(ns, dir) > 0.0) {
            ns = -ns;  // two-sided: face the incoming photon
        }
        vec3 ng = triangle_geometric_normal(hit.triangle);
        if (dot(ng, dir) > 0.0) {
            ng = -ng;
        }
        if (h >= 1u || params.store_direct != 0u) {
            store_photon(Photon(y, path, ng, h, dir, light_index, flux, 0u));
        }
        if (h == last_hit) {
            break;
        }
        // Lambertian bounce: cosine-weighted around the facing shading normal; the cosine pdf
        // cancels the BRDF's cos/π, leaving flux × albedo.
        vec2 v = ld_sample2(index, GROUP_FIRST_BOUNCE + h, params.seed);
        vec3 next = sample_cosine(ns, v.x, v.y);
        if (dot(next, ng) <= 0.0) {
            break;  // below the actual surface: the shading normal lied; no light this way
        }
        vec3 rho = material_albedo(triangle_material(hit.triangle), triangle_uv(hit.triangle, hit.barycentrics)).rgb;
        flux *= rho;
        if (flux == vec3(0.0)) {
            break;
        }
        origin = offset_ray(y, ng);
        dir = next;
    }
    atomicAdd(photon_counters.rays, rays);
}
