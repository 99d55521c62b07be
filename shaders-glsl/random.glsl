// Deterministic per-sample random numbers: a PCG hash of (pixel, sample, seed) seeds a small
// PCG stream, so a frame is reproducible bit for bit and independent of dispatch order.
#ifndef LEAKLESS_RANDOM_GLSL
#define LEAKLESS_RANDOM_GLSL

uvec4 pcg4d(uvec4 v) {
    v = v * 1664525u + 1013904223u;
    v.x += v.y * v.w; v.y += v.z * v.x; v.z += v.x * v.y; v.w += v.y * v.z;
    v ^= v >> 16u;
    v.x += v.y * v.w; v.y += v.z * v.x; v.z += v.x * v.y; v.w += v.y * v.z;
    return v;
}

struct Rng {
    uint state;
};

Rng rng_seed(uvec2 pixel, uint sample_index, uint seed) {
    return Rng(pcg4d(uvec4(pixel, sample_index, seed)).x);
}

// Uniform in [0, 1): 24 random bits.
float rng_next(inout Rng rng) {
    rng.state = rng.state * 747796405u + 2891336453u;
    uint word = ((rng.state >> ((rng.state >> 28u) + 4u)) ^ rng.state) * 277803737u;
    word = (word >> 22u) ^ word;
    return float(word >> 8u) * (1.0 / 16777216.0);
}

// An orthonormal basis around unit `n` (Duff et al. 2017, branchless).
void basis(vec3 n, out vec3 t, out vec3 b) {
    float s = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + n.z);
    float c = n.x * n.y * a;
    t = vec3(1.0 + s * n.x * n.x * a, s * c, -s * n.x);
    b = vec3(c, s + n.y * n.y * a, -n.y);
}

// Cosine-weighted direction around `n` (pdf cos θ / π).
vec3 sample_cosine(vec3 n, float u1, float u2) {
    float r = sqrt(u1);
    float phi = 2.0 * PI * u2;
    vec3 t, b;
    basis(n, t, b);
    return normalize(r * cos(phi) * t + r * sin(phi) * b + sqrt(max(0.0, 1.0 - u1)) * n);
}

#endif
