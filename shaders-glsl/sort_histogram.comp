#version 460
// Radix sort, step 1 of a digit pass: each workgroup counts the digits of its block of keys.
// Each thread counts its own elements in packed registers; the workgroup sums them in shared
// memory (no atomics: on CPU drivers every shared atomic is a locked instruction per lane).
#include "sort.glsl"

layout(local_size_x = SORT_WORKGROUP_SIZE) in;

SORT_PARAMS_BLOCK;
layout(set = 1, binding = 0, std430) readonly buffer KeysIn { uint data[]; } keys_in;
layout(set = 1, binding = 1, std430) writeonly buffer Histograms { uint data[]; } histograms;

shared uint s_packed[SORT_WORDS * SORT_WORKGROUP_SIZE];  // [word][thread]
shared uint s_segments[SORT_WORDS * SORT_SEGMENTS];      // [word][segment]

void main() {
    uint t = gl_LocalInvocationID.x;
    uint g = gl_WorkGroupID.x;
    uint first = g * SORT_BLOCK + t * SORT_ITEMS;
    uint packed[SORT_WORDS];
    for (uint w = 0u; w < SORT_WORDS; ++w) {
        packed[w] = 0u;
    }
    for (uint k = 0u; k < SORT_ITEMS; ++k) {
        uint i = first + k;
        sortCount(packed, i < params.len ? sortDigit(keys_in.data[i], params.key_limit, params.shift) : SORT_NO_DIGIT);
    }
    for (uint w = 0u; w < SORT_WORDS; ++w) {
        s_packed[w * SORT_WORKGROUP_SIZE + t] = packed[w];
    }
    barrier();
    {
        uint w = t / SORT_SEGMENTS;
        uint segment = t % SORT_SEGMENTS;
        uint row = w * SORT_WORKGROUP_SIZE + segment * SORT_SEGMENT_LENGTH;
        uint sum = 0u;
        for (uint j = 0u; j < SORT_SEGMENT_LENGTH; ++j) {
            sum += s_packed[row + j];
        }
        s_segments[w * SORT_SEGMENTS + segment] = sum;
    }
    barrier();
    if (t < SORT_RADIX) {
        uint w = t >> 1u;
        uint sum = 0u;
        for (uint j = 0u; j < SORT_SEGMENTS; ++j) {
            sum += s_segments[w * SORT_SEGMENTS + j];
        }
        histograms.data[t * params.group_count + g] = sortField(sum, t);
    }
}
