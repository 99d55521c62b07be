// Low-discrepancy samples: Owen-scrambled Sobol points, padded by index shuffling (Burley,
// "Practical Hash-based Owen Scrambling", JCGT 9(4), 2020).
//
// A path's random decisions are split into groups of up to four dimensions (emission, then one
// group per bounce). Within a group, point `index` is the Sobol point of a shuffled index
// (a nested-uniform scramble of the index, seeded per group), each coordinate Owen-scrambled by
// a hash seeded per (group, dimension). The shuffle maps every aligned block of 2^m indices
// onto an aligned block of 2^m Sobol points, which is itself a (0, m, 2)-net in dimensions 0
// and 1: the first 2^m paths stay stratified in each group, while groups are decorrelated. Everything is a pure function of
// (index, group, dimension, seed): a fixed seed gives bit-identical samples on any device and
// in any dispatch order; another seed gives another, equally well-distributed, point set.
#ifndef LEAKLESS_LOWDISCREPANCY_GLSL
#define LEAKLESS_LOWDISCREPANCY_GLSL

// Sobol points in dimensions 0..2, as 32-bit fractions. Dimension 0 is the van der Corput
// sequence (bit reversal); 1 and 2 use the primitive polynomials of Joe and Kuo's
// new-joe-kuo-6.21201, (s, a, m) = (1, 0, {1}) and (2, 1, {1, 3}), whose direction numbers
// follow from two-term recurrences, v1_k = v1_(k-1) ^ (v1_(k-1) >> 1) and
// v2_k = v2_(k-1) ^ v2_(k-2) ^ (v2_(k-2) >> 2), computed on the fly: a table of direction
// numbers indexed per invocation costs lavapipe twice the whole photon pass.
uvec3 sobol3(uint index) {
    uint x1 = 0u, x2 = 0u;
    uint v1 = 0x80000000u;
    uint v2 = 0x80000000u, v2_next = 0xc0000000u;
    uvec3 x = uvec3(bitfieldReverse(index), 0u, 0u);
    for (; index != 0u; index >>= 1u) {
        if ((index & 1u) != 0u) {
            x.y ^= v1;
            x.z ^= v2;
        }
        v1 ^= v1 >> 1u;
        uint v2_after = v2_next ^ v2 ^ (v2 >> 2u);
        v2 = v2_next;
        v2_next = v2_after;
    }
    return x;
}

uvec2 sobol2(uint index) {
    uint v1 = 0x80000000u;
    uvec2 x = uvec2(bitfieldReverse(index), 0u);
    for (; index != 0u; index >>= 1u) {
        if ((index & 1u) != 0u) {
            x.y ^= v1;
        }
        v1 ^= v1 >> 1u;
    }
    return x;
}

// A 32-bit integer hash (Wellons' lowbias32): seeds for the scrambles.
uint ld_hash(uint x) {
    x ^= x >> 16u;
    x *= 0x7feb352du;
    x ^= x >> 15u;
    x *= 0x846ca68bu;
    x ^= x >> 16u;
    return x;
}

uint ld_hash_combine(uint seed, uint v) {
    return ld_hash(seed ^ (v + 0x9e3779b9u + (seed << 6u) + (seed >> 2u)));
}

// A permutation of 32-bit words in which each output bit depends only on the same and lower
// input bits (Laine–Karras style; Vegdahl's constants). Applied to bit-reversed words it is a
// nested uniform (Owen) scramble.
uint lk_permutation(uint x, uint seed) {
    x ^= x * 0x3d20adeau;
    x += seed;
    x *= (seed >> 16u) | 1u;
    x ^= x * 0x05526c56u;
    x ^= x * 0x53a22864u;
    return x;
}

uint nested_uniform_scramble(uint x, uint seed) {
    return bitfieldReverse(lk_permutation(bitfieldReverse(x), seed));
}

// 32-bit fraction → [0, 1) with 24 bits (exactly representable, never 1.0).
float ld_to_float(uint x) {
    return float(x >> 8u) * (1.0 / 16777216.0);
}

// Dimensions 0..2 of point `index` of group `group`, for the sequence seeded by `seed`.
vec3 ld_sample3(uint index, uint group, uint seed) {
    uint group_seed = ld_hash_combine(ld_hash(seed), group);
    uvec3 x = sobol3(nested_uniform_scramble(index, group_seed));
    return vec3(ld_to_float(nested_uniform_scramble(x.x, ld_hash_combine(group_seed, 1u))),
                ld_to_float(nested_uniform_scramble(x.y, ld_hash_combine(group_seed, 2u))),
                ld_to_float(nested_uniform_scramble(x.z, ld_hash_combine(group_seed, 3u))));
}

// Dimensions 0 and 1 of point `index` of group `group`: the (0, 2)-sequence pair.
vec2 ld_sample2(uint index, uint group, uint seed) {
    uint group_seed = ld_hash_combine(ld_hash(seed), group);
    uvec2 x = sobol2(nested_uniform_scramble(index, group_seed));
    return vec2(ld_to_float(nested_uniform_scramble(x.x, ld_hash_combine(group_seed, 1u))),
                ld_to_float(nested_uniform_scramble(x.y, ld_hash_combine(group_seed, 2u))));
}

#endif
