// Reductions over a cluster of lanes: `width` aligned lanes of a subgroup (a power of two), the
// lanes that walk one photon in the splat (SPLAT_LANES) or one leaf's lists in the gather
// (WALK_CLUSTER). Included after GL_KHR_shader_subgroup_shuffle is enabled.
#ifndef LEAKLESS_CLUSTER_GLSL
#define LEAKLESS_CLUSTER_GLSL

// The least of a cluster's values, by exchanges across halves, quarters, ... of the cluster.
// naga parses no subgroup operation (counters.glsl): the reflection twin's cluster is one lane.
uint cluster_min(uint x, uint width) {
#ifndef LEAKLESS_REFLECTION
    for (uint m = 1u; m < width; m <<= 1u) {
        x = min(x, subgroupShuffleXor(x, m));
    }
#endif
    return x;
}

#endif
