// The view-sample cluster hierarchy (Moreau et al. 2016): view samples sorted by Morton code,
// leaves of `branching` consecutive samples, parents of `branching` consecutive children.
// Node i of level l covers sorted samples [i·span_l, (i+1)·span_l) with span_l = B^(l+1).
#ifndef LEAKLESS_HIERARCHY_GLSL
#define LEAKLESS_HIERARCHY_GLSL

// One node: bounds, normal cone and largest gather radius of its valid samples. An empty node (no valid
// sample) has min > max, so every sphere test fails.
struct Node {
    vec3 bounds_min;
    uint first_child;   // first node of the level below, or the first sorted sample of a leaf
    vec3 bounds_max;
    uint child_count;   // nodes below, or samples of a leaf
    vec3 cone_axis;
    float cone_angle;   // half-angle in radians; ≥ π/2 + ... means no normal-cone culling
    uint level;         // 0 = leaf
    uint valid_samples;
    float radius_max;   // the largest gather radius of its valid samples (a sample's own:
                        // visible_disk.comp grows or shrinks it where its disk is partial)
    uint pad0;
};

// Where each level starts in the node array, and how many samples a node of it covers.
struct Level {
    uint offset;
    uint count;
    uint span;
    uint pad0;
};

// A sorted sample's position, copied from the G-buffer by the leaves' build so that the splat
// reads a leaf's samples in one contiguous run; `valid` 0 where the pixel has no surface.
struct SamplePosition {
    vec3 position;
    uint valid;
};

const uint INVALID_SAMPLE_KEY = 0xffffffffu;

#endif
