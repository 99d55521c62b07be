#version 460
// Builds one level of the view-sample hierarchy, bottom up: a leaf from its `branching`
// sorted samples, an interior node from its `branching` children. Each node gets the bounds,
// the normal cone and the largest gather radius of its valid samples (a sample's radius is the
// frame's, grown or shrunk where its visible disk is partial: visible_disk.comp), so that the
// splat lists a photon wherever a grown disk may reach it.
#include "common.glsl"
#include "gbuffer.glsl"
#include "hierarchy.glsl"

layout(local_size_x = 64) in;

GBUFFER_BINDINGS(0)
layout(set = 1, binding = 3, std430) readonly buffer SortedKeys { uint keys[]; } sorted_keys;
layout(set = 1, binding = 4, std430) readonly buffer SortedSamples { uint pixels[]; } sorted_samples;
layout(set = 1, binding = 5, std430) readonly buffer Levels { Level levels[]; } levels;
layout(set = 1, binding = 6, std430) buffer Nodes { Node nodes[]; } nodes;
// .g: each sample's gather radius (visible_disk.comp writes it for every pixel).
layout(set = 1, binding = 7, rgba32f) uniform readonly image2D disk_mass;
// Each sorted sample's position (written by the leaves' level): what the splat's test of a wide
// leaf reads, written only where the splat makes that test (the device tuning's, splat.comp).
layout(set = 1, binding = 8, std430) writeonly buffer SamplePositions { SamplePosition positions[]; } sample_positions;
layout(constant_id = 13) const bool LEAF_SAMPLES = false;
layout(push_constant) uniform BuildParams {
    uint level;
    uint branching;
    uint sample_count;
    uint image_width;
} params;

const float HUGE = 3.0e38;

void main() {
    Level lv = levels.levels[params.level];
    uint i = gl_GlobalInvocationID.x;
    if (i >= lv.count) {
        return;
    }
    Node node;
    node.bounds_min = vec3(HUGE);
    node.bounds_max = vec3(-HUGE);
    node.level = params.level;
    node.valid_samples = 0u;
    node.radius_max = 0.0;
    node.pad0 = 0u;
    vec3 axis_sum = vec3(0.0);
    if (params.level == 0u) {
        node.first_child = i * params.branching;
        node.child_count = min(params.branching, params.sample_count - node.first_child);
        for (uint s = node.first_child; s < node.first_child + node.child_count; ++s) {
            if (sorted_keys.keys[s] == INVALID_SAMPLE_KEY) {
                if (LEAF_SAMPLES) {
                    sample_positions.positions[s] = SamplePosition(vec3(0.0), 0u);
                }
                continue;
            }
            uint pixel = sorted_samples.pixels[s];
            ivec2 xy = ivec2(pixel % params.image_width, pixel / params.image_width);
            vec3 p = imageLoad(gbuffer_position, xy).xyz;
            if (LEAF_SAMPLES) {
                sample_positions.positions[s] = SamplePosition(p, 1u);
            }
            node.bounds_min = min(node.bounds_min, p);
            node.bounds_max = max(node.bounds_max, p);
            node.radius_max = max(node.radius_max, imageLoad(disk_mass, xy).y);
            axis_sum += imageLoad(gbuffer_normal, xy).xyz;
            node.valid_samples += 1u;
        }
    } else {
        Level below = levels.levels[params.level - 1u];
        node.first_child = below.offset + i * params.branching;
        node.child_count = min(params.branching, below.offset + below.count - node.first_child);
        for (uint c = node.first_child; c < node.first_child + node.child_count; ++c) {
            Node child = nodes.nodes[c];
            if (child.valid_samples == 0u) {
                continue;
            }
            node.bounds_min = min(node.bounds_min, child.bounds_min);
            node.bounds_max = max(node.bounds_max, child.bounds_max);
            node.radius_max = max(node.radius_max, child.radius_max);
            axis_sum += child.cone_axis * float(child.valid_samples);
            node.valid_samples += child.valid_samples;
        }
    }
    // The cone: the mean direction, opened until it holds every normal (or child cone).
    float len = length(axis_sum);
    node.cone_axis = len > 1e-6 ? axis_sum / len : vec3(0.0, 0.0, 1.0);
    float angle = len > 1e-6 ? 0.0 : PI;
    if (len > 1e-6) {
        if (params.level == 0u) {
            for (uint s = node.first_child; s < node.first_child + node.child_count; ++s) {
                if (sorted_keys.keys[s] == INVALID_SAMPLE_KEY) {
                    continue;
                }
                uint pixel = sorted_samples.pixels[s];
                vec3 n = imageLoad(gbuffer_normal, ivec2(pixel % params.image_width, pixel / params.image_width)).xyz;
                angle = max(angle, acos(clamp(dot(node.cone_axis, n), -1.0, 1.0)));
            }
        } else {
            for (uint c = node.first_child; c < node.first_child + node.child_count; ++c) {
                Node child = nodes.nodes[c];
                if (child.valid_samples != 0u) {
                    angle = max(angle, acos(clamp(dot(node.cone_axis, child.cone_axis), -1.0, 1.0)) + child.cone_angle);
                }
            }
        }
    }
    // A little slack covers acos rounding, so culling never drops a sample the gather keeps.
    node.cone_angle = min(angle + 1e-4, PI);
    nodes.nodes[lv.offset + i] = node;
}
