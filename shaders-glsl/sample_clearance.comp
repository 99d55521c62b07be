#version 460
// Sample clearance: for each tile of view samples, the ball around the point its middle
// sample's visibility segments leave from that holds no triangle except those wholly on or
// under the plane τ (a quarter of that sample's lift) above its surface: photon_clearance.comp's
// ball, from the other end. Any sample whose segments start inside a ball and above its plane
// can use it: the gather gives each the best of its tile's and the neighbours'.
//
// Why: the photon's ball alone proves a segment only while the sample stands inside it, so
// near a wall or a column, where every photon's ball is small, most segments were traced
// (on the basilica such rays are most of the gather's time). A segment
// that leaves the sample's ball only where it has entered the photon's meets nothing either,
// and the sample's ball is as large as the sample is far from the wall (gather.comp).
//
// The centre is the segments' start before a convex curved mesh's lift (the gather checks how
// far its start stands from it), and a tile whose middle has no surface gets radius 0.
#include "common.glsl"
#include "scene.glsl"
#include "gbuffer.glsl"
#include "disk.glsl"
#include "clearance_search.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

GBUFFER_BINDINGS(0)
// Per tile: the ball's centre (.xyz) and radius (.w), and the plane it leaves out: the normal
// (.xyz) and the height above which a segment must stay, dot(v, normal) > .w.
layout(set = 1, binding = 3, rgba32f) uniform writeonly image2D sample_clearance;
layout(set = 1, binding = 4, rgba32f) uniform writeonly image2D sample_clearance_plane;
layout(push_constant) uniform SampleClearanceParams {
    vec3 eye;          // the camera's position: segments leave from the sample moved toward it
    float max_radius;  // no segment of the gather is longer than this
    uint tile;         // one ball a tile × tile block of pixels, around its middle sample's start
    uint pad0;
    uint pad1;
    uint pad2;
} params;

void main() {
    ivec2 t = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(t, imageSize(sample_clearance)))) {
        return;
    }
    ivec2 xy = min(t * int(params.tile) + int(params.tile / 2u), imageSize(gbuffer_position) - 1);
    vec4 position = imageLoad(gbuffer_position, xy);
    if (position.w == 0.0) {
        imageStore(sample_clearance, t, vec4(0.0));
        imageStore(sample_clearance_plane, t, vec4(0.0, 0.0, 0.0, 3.0e38));
        return;
    }
    vec3 x = position.xyz;
    vec3 ng = sample_geometric_normal(uint(position.w) - 1u, imageLoad(gbuffer_normal, xy).xyz);
    vec3 q = sample_segment_start(x, ng, params.eye);
    float tau = 0.25 * dot(q - x, ng);
    // The nudge toward the eye rises off the surface too, so tau is at least a quarter lift.
    float radius = tau > 0.0 ? clearance_radius(q, ClearancePlane(x, ng, tau), params.max_radius) : 0.0;
    imageStore(sample_clearance, t, vec4(q, radius));
    imageStore(sample_clearance_plane, t, vec4(ng, dot(x, ng) + 1.5 * tau));
}
