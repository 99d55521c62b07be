#version 460
// Fault injection (debug builds, LEAKLESS_FAULT_HANG): one invocation spins until the host
// writes a non-zero word, so that the pass it runs in outlasts LEAKLESS_GPU_TIMEOUT and the
// lost-device path can be tested (docs/architecture.md, "Lost devices"). The host releases
// it before the device is torn down; the loop is bounded so that it ends even if the host
// never does.

layout(local_size_x = 1) in;

layout(set = 1, binding = 0, std430) coherent volatile buffer Release { uint words[]; } release;

void main() {
    for (uint i = 0u; i < 0xffffffffu; ++i) {
        // An atomic read: the compiler may not hoist it out of the loop.
        if (atomicOr(release.words[0], 0u) != 0u) {
            return;
        }
    }
}
