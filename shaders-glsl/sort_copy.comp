#version 460
// Radix sort: after an odd number of digit passes the sorted pairs are in the sort's scratch
// buffers; this copies them back into the caller's.
#include "sort.glsl"

layout(local_size_x = SORT_WORKGROUP_SIZE) in;

SORT_PARAMS_BLOCK;
layout(set = 1, binding = 0, std430) readonly buffer KeysIn { uint data[]; } keys_in;
layout(set = 1, binding = 1, std430) readonly buffer ValuesIn { uint data[]; } values_in;
layout(set = 1, binding = 2, std430) writeonly buffer KeysOut { uint data[]; } keys_out;
layout(set = 1, binding = 3, std430) writeonly buffer ValuesOut { uint data[]; } values_out;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i < params.len) {
        keys_out.data[i] = keys_in.data[i];
        values_out.data[i] = values_in.data[i];
    }
}
