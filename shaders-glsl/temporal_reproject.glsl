// Temporal reuse's reprojection (temporal.comp includes it after its bindings): where a pixel's
// surface point was in the history's frame, and what the history held there, read bilinearly
// from the taps of last frame that saw the same surface.

vec3 previous_vertex(uint v) {
    uint i = 3u * (v - 3u * params.first_moving_triangle);
    return vec3(previous_positions.xyz[i], previous_positions.xyz[i + 1u], previous_positions.xyz[i + 2u]);
}

// Where the surface point `p` of `triangle` was in the history's frame.
vec3 previous_position(vec3 p, uint triangle) {
    if (params.instances_moved == 0u || triangle < params.first_moving_triangle) {
        return p;
    }
    vec3 a = vertex_position(3u * triangle), b = vertex_position(3u * triangle + 1u);
    vec3 c = vertex_position(3u * triangle + 2u);
    vec3 ab = b - a, ac = c - a, ap = p - a;
    float d00 = dot(ab, ab), d01 = dot(ab, ac), d11 = dot(ac, ac);
    float d20 = dot(ap, ab), d21 = dot(ap, ac);
    float det = d00 * d11 - d01 * d01;
    float v = det > 0.0 ? (d11 * d20 - d01 * d21) / det : 0.0;
    float w = det > 0.0 ? (d00 * d21 - d01 * d20) / det : 0.0;
    return (1.0 - v - w) * previous_vertex(3u * triangle) + v * previous_vertex(3u * triangle + 1u)
         + w * previous_vertex(3u * triangle + 2u);
}

// The history at the surface point `p` of `triangle` with normal `n` (.a = its frames; 0 when
// no tap of last frame saw the same surface), the filter's bias there, and where the point was
// on last frame's screen.
vec4 reprojected_history(vec3 p, uint triangle, vec3 n, out vec4 filtered_mean, out vec3 own_mean, out vec2 at) {
    filtered_mean = vec4(0.0);
    own_mean = vec3(0.0);
    at = vec2(-1.0);
    vec3 was = previous_position(p, triangle);
    vec4 clip = params.previous_view_proj * vec4(was, 1.0);
    if (clip.w <= 0.0) {
        return vec4(0.0);
    }
    vec2 size = vec2(frame.width, frame.height);
    at = (clip.xy / clip.w * 0.5 + 0.5) * size - 0.5;
    ivec2 base = ivec2(floor(at));
    vec2 f = at - vec2(base);
    // Slope-aware: the distance from the tap's point to the plane of this one, against a
    // tolerance growing with the distance to the camera (the raster's precision).
    float tolerance = 0.01 * length(was - params.previous_camera.xyz) + 1e-4;
    bool moving = triangle >= params.first_moving_triangle;
    vec4 sum = vec4(0.0);
    float weight = 0.0;
    for (int k = 0; k < 4; k++) {
        ivec2 q = base + ivec2(k & 1, k >> 1);
        if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, ivec2(size)))) {
            continue;
        }
        vec4 s = imageLoad(surface_previous, q);
        if (s.w == 0.0) {
            continue;
        }
        uint t = uint(s.w) - 1u;
        bool same = moving ? t == triangle : t < params.first_moving_triangle;
        vec3 nq = imageLoad(normal_previous, q).xyz;
        if (!same || abs(dot(nq, s.xyz - was)) > tolerance || (!moving && dot(nq, n) < 0.9)) {
            continue;
        }
        float w = (k & 1) == 1 ? f.x : 1.0 - f.x;
        w *= (k >> 1) == 1 ? f.y : 1.0 - f.y;
        if (w > 0.0) {
            sum += w * imageLoad(history_previous, q);
            filtered_mean += w * imageLoad(filtered_mean_previous, q);
            own_mean += w * imageLoad(own_mean_previous, q).rgb;
            weight += w;
        }
    }
    // A history read mostly from taps of other surfaces is not this surface's.
    filtered_mean = weight > 0.25 ? filtered_mean / weight : vec4(0.0);
    own_mean = weight > 0.25 ? own_mean / weight : vec3(0.0);
    return weight > 0.25 ? sum / weight : vec4(0.0);
}
