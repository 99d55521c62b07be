#version 460
// Photon tracing (docs/architecture.md §1): each thread traces light paths, taking the next
// untraced one when its path ends (one path per thread on a GPU). A light is chosen in
// proportion to its emitted power (CDF from crates/renderer/src/photon_lights.rs), a direction (and for
// directional lights an origin) is drawn from Owen-scrambled Sobol points, and the path bounces
// Lambertian-ly. The first hit is direct light and is not stored (unless `store_direct`, a
// diagnostic); every later hit appends a photon carrying the flux that arrives there, up to
// `max_bounces` stored hits per path.
#include "trace.glsl"
#include "common.glsl"
#include "random.glsl"
#include "lowdiscrepancy.glsl"
#include "photon.glsl"
#include "counters.glsl"
#include "emitters.glsl"

layout(local_size_x = 64) in;

// One light's entry in the power CDF. Twin: `PhotonLight` in crates/renderer/src/passes/photons.rs.
struct PhotonLight {
    vec3 flux;  // power_rgb / p(light): a path from this light carries flux / paths; for an
                // emissive triangle 1 / p, times the power it emits where the path starts
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
    uint threads;        // threads dispatched: paths beyond them are taken as others end
    uint ordered;        // 1: take paths in `path_order`; 0: in index order (the same photons)
    uint punctual_count; // lights before the emissive triangles in the table
    uint pad1;
    uint pad2;
} params;
layout(set = 1, binding = 0, std430) readonly buffer Lights { Light lights[]; } lights;
layout(set = 1, binding = 1, std430) readonly buffer PhotonLights { PhotonLight entries[]; } photon_lights;
layout(set = 1, binding = 2, std430) writeonly buffer Photons { Photon photons[]; } photons;
// The order threads take paths in: grouped by emission cell (emission_order.rs), so the lanes
// of a SIMD group start from neighbouring points of the light.
layout(set = 1, binding = 4, std430) readonly buffer PathOrder { uint paths[]; } path_order;
layout(set = 1, binding = 3, std430) buffer PhotonCounters {
    uint stored;      // photons written (never more than capacity)
    uint overflowed;  // photons dropped because the buffer was full
    uint rays;        // closest-hit rays traced (for `bench`'s rays per second)
    uint next_path;   // paths taken after the first `threads` (zeroed before the pass)
} photon_counters;

// Sample groups of a path (lowdiscrepancy.glsl): emission, then one per bounce.
const uint GROUP_EMISSION = 0u;
const uint GROUP_FIRST_BOUNCE = 1u;
// Where on an emissive triangle a path starts, and from which face: a group of its own, far
// past the bounces', so that the emission pair keeps placing the direction.
const uint GROUP_EMITTER_POINT = 0x8000u;

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
    uint slot;
    RESERVE_ONE(photon_counters.stored, slot);
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

// A path's state between bounces.
struct PathState {
    uint path;
    uint index;        // its place in the low-discrepancy sequence
    uint light_index;
    vec3 flux;
    vec3 origin;
    vec3 dir;
    uint h;            // bounces before the next hit
};

// Path `path`'s emission: dimensions 0, 1 (the (0,2)-pair) place the direction or the disk
// point, dimension 2 picks the light. Frames that accumulate continue one low-discrepancy
// sequence instead of reseeding it.
PathState emit(uint path) {
    PathState st;
    st.path = path;
    st.index = path + params.path_offset;
    st.h = 0u;
    vec3 u = ld_sample3(st.index, GROUP_EMISSION, params.seed);
    st.light_index = select_light(u.z);
    if (st.light_index >= params.punctual_count) {
        // An emissive triangle: a uniform point, a face (either, for a two-sided surface), a
        // cosine-distributed direction; flux π·A·s·Le(x) / p.
        vec3 v = ld_sample3(st.index, GROUP_EMITTER_POINT, params.seed);
        EmitterPoint e = emitter_point(emitters.emitters[st.light_index - params.punctual_count].triangle, v.xy);
        bool two_sided = e.material.double_sided != 0u;
        vec3 n = two_sided && v.z >= 0.5 ? -e.normal : e.normal;
        float sides = two_sided ? 2.0 : 1.0;
        st.flux = photon_lights.entries[st.light_index].flux * (PI * e.area * sides) * emitted_toward(e, n)
                / float(params.paths);
        st.dir = sample_cosine(n, u.x, u.y);
        st.origin = offset_ray(e.position, n);
        return st;
    }
    Light light = lights.lights[st.light_index];
    st.flux = photon_lights.entries[st.light_index].flux / float(params.paths);
    if (light.kind == LIGHT_DIRECTIONAL) {
        // A disk of the bounding sphere's radius, perpendicular to the light, behind the
        // sphere: its parallel rays cover everything in the scene. (Moved back by 1.001 R:
        // any distance >= R gives the same rays; the margin keeps geometry that touches the
        // sphere's far side off t = 0.)
        st.dir = normalize(light.direction);
        vec3 t, b;
        basis(st.dir, t, b);
        vec2 d = params.scene_radius * concentric_disk(u.xy);
        st.origin = params.scene_center - (1.001 * params.scene_radius) * st.dir + d.x * t + d.y * b;
    } else {
        st.origin = light.position;
        st.dir = light.kind == LIGHT_SPOT ? sample_spot(light, u.xy) : uniform_sphere(u.xy);
    }
    return st;
}

// One hit of the path: stores its photon and turns `st` into the next segment; false when the
// path ends. Hits h = 0, 1, ..., max_bounces (h = bounces before the hit); h = 0 is direct
// light, stored only with store_direct; h = 1..=max_bounces are the stored indirect hits.
bool bounce(inout PathState st) {
    Hit hit = traceClosest(st.origin, st.dir, 0.0, 1e30);
    if (hit.triangle == NO_HIT) {
        return false;
    }
    // Inside its triangle by a lift, not on an edge it shares with another surface (see
    // nudge_toward): stored there, and the next bounce leaves from there.
    vec3 y = nudge_toward(triangle_position(hit.triangle, hit.barycentrics),
                          triangle_position(hit.triangle, vec2(1.0 / 3.0)));
    vec3 ns = triangle_shading_normal(hit.triangle, hit.barycentrics);
    if (dot(ns, st.dir) > 0.0) {
        ns = -ns;  // two-sided: face the incoming photon
    }
    vec3 ng = triangle_geometric_normal(hit.triangle);
    if (dot(ng, st.dir) > 0.0) {
        ng = -ng;
    }
    if (st.h >= 1u || params.store_direct != 0u) {
        store_photon(Photon(y, st.path, ng, st.h, st.dir, st.light_index, st.flux, 0u));
    }
    if (st.h == params.max_bounces) {
        return false;
    }
    // Lambertian bounce: cosine-weighted around the facing shading normal; the cosine pdf
    // cancels the BRDF's cos/π, leaving flux × albedo.
    vec2 v = ld_sample2(st.index, GROUP_FIRST_BOUNCE + st.h, params.seed);
    vec3 next = sample_cosine(ns, v.x, v.y);
    if (dot(next, ng) <= 0.0) {
        return false;  // below the actual surface: the shading normal lied; no light this way
    }
    vec3 rho = material_albedo(triangle_material(hit.triangle), triangle_uv(hit.triangle, hit.barycentrics)).rgb;
    st.flux *= rho;
    if (st.flux == vec3(0.0)) {
        return false;
    }
    st.origin = offset_ray(y, ng);
    st.dir = next;
    st.h += 1u;
    return true;
}

void main() {
    // Each thread starts path `gl_GlobalInvocationID.x` and, when a path ends, takes the next
    // untraced one (`params.threads` onward), so a lane does not idle while another lane of
    // its SIMD group bounces on (photons.rs says when the threads are fewer than the paths).
    uint taken = gl_GlobalInvocationID.x;
    if (taken >= min(params.threads, params.paths) || params.light_count == 0u) {
        return;
    }
    PathState st = emit(params.ordered != 0u ? path_order.paths[taken] : taken);
    uint rays = 0u;
    while (true) {
        rays += 1u;
        if (!bounce(st)) {
            if (params.threads >= params.paths) {
                break;  // one path a thread (a GPU's tuning): no path is left to take
            }
            taken = params.threads + atomicAdd(photon_counters.next_path, 1u);
            if (taken >= params.paths) {
                break;
            }
            st = emit(params.ordered != 0u ? path_order.paths[taken] : taken);
        }
    }
    ADD_COUNT(photon_counters.rays, rays);
}
