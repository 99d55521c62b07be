// Direct light from emissive triangles by next-event estimation with resampled importance
// sampling (Talbot et al. 2005; the candidate step of ReSTIR): each of `samples` estimates
// draws `candidates` points from the emitters' power CDF, uniform on the chosen triangle, keeps
// one in proportion to the light it would bring if nothing were in the way (emitted luminance
// × both cosines / r²), and traces one shadow ray to it. With hundreds of emitters, the ray
// goes where the light comes from; the weight (Σw / M) / target keeps the estimate unbiased.
// Needs trace.glsl, scene.glsl, emitters.glsl, lowdiscrepancy.glsl and random.glsl.
#ifndef LEAKLESS_AREA_LIGHT_GLSL
#define LEAKLESS_AREA_LIGHT_GLSL

float rec709_luminance(vec3 c) {
    return dot(c, vec3(0.2126, 0.7152, 0.0722));
}

// A candidate's unshadowed irradiance at `p` (shading normal n, geometric ng on its side) and
// the direction and distance to it; zero where the emitter faces away or lies behind.
vec3 unshadowed_irradiance(EmitterPoint e, vec3 p, vec3 n, vec3 ng, out vec3 l, out float dist) {
    vec3 d = e.position - p;
    dist = length(d);
    l = d / max(dist, 1e-30);
    float cos_surface = dot(n, l);
    float cos_light = abs(dot(e.normal, l));
    if (!(dist > 0.0) || cos_surface <= 0.0 || dot(ng, l) <= 0.0 || cos_light <= 0.0) {
        return vec3(0.0);
    }
    return emitted_toward(e, -l) * (cos_surface * cos_light / (dist * dist));
}

// Whether the segment from `p` (geometric normal `ng`, on the side of the light) to a point
// of an emitter is free. It ends a lift short of the emitter, on the segment: it cannot meet
// the emitter itself, and meets anything between, however close to the emitter.
bool emitter_visible(vec3 p, vec3 ng, vec3 emitter_position) {
    vec3 origin = offset_ray(p, ng);
    vec3 d = nudge_toward(emitter_position, p) - origin;
    float len = length(d);
    return len > 0.0 && !traceOccluded(origin, d / len, 0.0, len);
}

// Irradiance at `p` from the emitters: the mean of `samples` resampled estimates with a shadow
// ray each, estimates first .. first + samples − 1 of the pixel's sequence (`sequence_seed`),
// whose point (estimate · candidates + c) is candidate c: the frames of an accumulation
// continue one stratified sequence.
vec3 area_light_irradiance(vec3 p, vec3 n, vec3 ng, uint emitter_count, uint first, uint samples, uint candidates,
                           uint sequence_seed, inout Rng rng) {
    vec3 total = vec3(0.0);
    for (uint s = 0u; s < samples; ++s) {
        float weight_sum = 0.0;
        float chosen_target = 0.0;
        vec3 chosen_e = vec3(0.0);
        vec3 chosen_l = vec3(0.0);
        float chosen_dist = 0.0;
        vec3 chosen_position = vec3(0.0);
        for (uint c = 0u; c < candidates; ++c) {
            vec3 u = ld_sample3((first + s) * candidates + c, 0u, sequence_seed);
            uint k = select_emitter(u.z, emitter_count);
            Emitter em = emitters.emitters[k];
            EmitterPoint e = emitter_point(em.triangle, u.xy);
            vec3 l;
            float dist;
            vec3 irr = unshadowed_irradiance(e, p, n, ng, l, dist);
            float target = rec709_luminance(irr);
            // Source density over area: the emitter's chance over its area.
            float w = target > 0.0 ? target * e.area / em.probability : 0.0;
            weight_sum += w;
            if (w > 0.0 && rng_next(rng) * weight_sum < w) {
                chosen_target = target;
                chosen_e = irr;
                chosen_l = l;
                chosen_dist = dist;
                chosen_position = e.position;
            }
        }
        if (chosen_target <= 0.0) {
            continue;
        }
        if (!emitter_visible(p, ng, chosen_position)) {
            continue;
        }
        total += chosen_e * (weight_sum / (float(candidates) * chosen_target));
    }
    return total / float(max(samples, 1u));
}

#endif
