#version 460
// Radix sort, step 3 of a digit pass: each workgroup moves its block of (key, value) pairs to
// their sorted positions for this digit, stably. The rank of an element among the elements of
// its digit in the block is the number of elements with that digit held by earlier threads
// (a workgroup prefix sum per digit, in shared memory) plus those earlier in its own thread.
// No subgroup operations: nothing assumes a subgroup size.
#include "sort.glsl"

layout(local_size_x = SORT_WORKGROUP_SIZE) in;

SORT_PARAMS_BLOCK;
layout(set = 1, binding = 0, std430) readonly buffer KeysIn { uint data[]; } keys_in;
layout(set = 1, binding = 1, std430) readonly buffer ValuesIn { uint data[]; } values_in;
layout(set = 1, binding = 2, std430) readonly buffer Histograms { uint data[]; } histograms;
layout(set = 1, binding = 3, std430) writeonly buffer KeysOut { uint data[]; } keys_out;
layout(set = 1, binding = 4, std430) writeonly buffer ValuesOut { uint data[]; } values_out;

shared uint s_packed[SORT_WORDS * SORT_WORKGROUP_SIZE];  // [word][thread]
shared uint s_segments[SORT_WORDS * SORT_SEGMENTS];      // [word][segment]
shared uint s_offsets[SORT_RADIX];

void main() {
    uint t = gl_LocalInvocationID.x;
    uint g = gl_WorkGroupID.x;
    if (t < SORT_RADIX) {
        s_offsets[t] = histograms.data[t * params.group_count + g];
    }

    uint first = g * SORT_BLOCK + t * SORT_ITEMS;
    uint keys[SORT_ITEMS];
    uint digits[SORT_ITEMS];
    uint packed[SORT_WORDS];
    for (uint w = 0u; w < SORT_WORDS; ++w) {
        packed[w] = 0u;
    }
    for (uint k = 0u; k < SORT_ITEMS; ++k) {
        uint i = first + k;
        keys[k] = i < params.len ? keys_in.data[i] : 0u;
        digits[k] = i < params.len ? sortDigit(keys[k], params.key_limit, params.shift) : SORT_NO_DIGIT;
        sortCount(packed, digits[k]);
    }
    for (uint w = 0u; w < SORT_WORDS; ++w) {
        s_packed[w * SORT_WORKGROUP_SIZE + t] = packed[w];
    }
    barrier();

    // Exclusive scan of every column over the threads: first within segments...
    {
        uint w = t / SORT_SEGMENTS;
        uint segment = t % SORT_SEGMENTS;
        uint row = w * SORT_WORKGROUP_SIZE + segment * SORT_SEGMENT_LENGTH;
        uint run = 0u;
        for (uint j = 0u; j < SORT_SEGMENT_LENGTH; ++j) {
            uint x = s_packed[row + j];
            s_packed[row + j] = run;
            run += x;
        }
        s_segments[w * SORT_SEGMENTS + segment] = run;
    }
    barrier();
    // ...then over the segment totals of each column.
    if (t < SORT_WORDS) {
        uint run = 0u;
        for (uint j = 0u; j < SORT_SEGMENTS; ++j) {
            uint x = s_segments[t * SORT_SEGMENTS + j];
            s_segments[t * SORT_SEGMENTS + j] = run;
            run += x;
        }
    }
    barrier();

    for (uint k = 0u; k < SORT_ITEMS; ++k) {
        uint d = digits[k];
        if (d == SORT_NO_DIGIT) {
            continue;
        }
        uint w = d >> 1u;
        uint before = sortField(s_segments[w * SORT_SEGMENTS + t / SORT_SEGMENT_LENGTH] + s_packed[w * SORT_WORKGROUP_SIZE + t], d);
        for (uint j = 0u; j < k; ++j) {
            before += digits[j] == d ? 1u : 0u;
        }
        uint dst = s_offsets[d] + before;
        keys_out.data[dst] = keys[k];
        values_out.data[dst] = values_in.data[first + k];
    }
}
