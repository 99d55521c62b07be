// The sum of one vec4 per invocation over the workgroup, by a tree in shared memory: the total
// is what invocation 0 gets back. The includer defines WORKGROUP_SUM_SIZE, its invocations (a
// power of two), and every invocation must call it (it holds barriers). A tree rather than
// atomics: the order of the additions, and so the frame, does not depend on scheduling.

shared vec4 workgroup_sum_slots[WORKGROUP_SUM_SIZE];

vec4 workgroup_sum(vec4 value) {
    uint i = gl_LocalInvocationIndex;
    workgroup_sum_slots[i] = value;
    barrier();
    for (uint stride = WORKGROUP_SUM_SIZE / 2u; stride > 0u; stride >>= 1u) {
        if (i < stride) {
            workgroup_sum_slots[i] += workgroup_sum_slots[i + stride];
        }
        barrier();
    }
    return workgroup_sum_slots[0];
}
