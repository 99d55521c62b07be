#version 460
// Disk smoothing (leakless single frames; docs/architecture.md §1, "Shared directions"): each
// sample's visible-disk mass and gather radius become their mean over the samples of its
// surface around it, within the same distance visible_disk.comp lets neighbours lend their
// directions, whatever the resolution.
//
// Why: visible_disk.comp shares directions within a 3×3 block of pixels (5×5 where one is
// missing), so its noise is a few pixels across: grain at the pixel scale on a pier's face
// narrower than the disk, where every sample's mass is partial (the atrium at 320×240: 1.63×
// splat's grain; at 1920×1080 the block is a speck of the disk). The mass varies along a surface over the disk's scale,
// and a mean over a footprint a fixed share of the disk in pixels takes the grain out at
// every resolution. Only a single frame is smoothed, like the sharing: an accumulation keeps
// each sample's own measurement, since the blur is a bias that averaging frames would keep.
//
// Taps count on the sample's surface (facing alike, on its tangent plane, nearer than
// `share_distance`·r) and in symmetric pairs (or with the mirror tap off the screen): where
// the surface ends, the mass's slope along it cancels to first order, as in the sharing. A
// whole disk with whole neighbours stays exactly 1 at the frame's radius.
#include "common.glsl"
#include "gbuffer.glsl"
#include "disk_band.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

FRAME_BLOCK(0);
GBUFFER_BINDINGS(1)
// visible_disk.comp's image: mass, radius, rays down, lift.
layout(set = 1, binding = 4, rgba32f) uniform readonly image2D measured;
layout(set = 1, binding = 5, rgba32f) uniform writeonly image2D disk_mass;

layout(push_constant) uniform DiskSmoothParams {
    float radius;          // the frame's gather radius
    float share_distance;  // taps nearer than this share of the radius count
    uint pad0;
    uint pad1;
} params;

// Taps (2·REACH + 1)² with a stride that spans `share_distance`·r on the screen.
const int REACH = 3;
// A tap this share of the radius off the sample's tangent plane still counts, beyond the band's
// slope: the raster's rounding on a plane, in the scene's own units (the radius scales with it).
const float PLANE_ROUNDING = 2e-4;

// Whether the tap `q` lies on the surface of the sample at `x` (normal `n`); its position.
bool on_surface(ivec2 q, vec3 x, vec3 n, out bool off_screen) {
    off_screen = any(lessThan(q, ivec2(0))) || q.x >= int(frame.width) || q.y >= int(frame.height);
    if (off_screen) {
        return false;
    }
    vec4 s = imageLoad(gbuffer_position, q);
    vec3 d = s.xyz - x;
    float distance = length(d);
    return s.w != 0.0 && dot(imageLoad(gbuffer_normal, q).xyz, n) >= 0.9
        && distance <= params.share_distance * params.radius
        && abs(dot(d, n)) <= DISK_SLOPE * distance + PLANE_ROUNDING * params.radius;
}

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (pixel.x >= int(frame.width) || pixel.y >= int(frame.height)) {
        return;
    }
    vec4 own = imageLoad(measured, pixel);
    vec4 surface = imageLoad(gbuffer_position, pixel);
    if (surface.w == 0.0) {
        imageStore(disk_mass, pixel, own);
        return;
    }
    vec3 x = surface.xyz;
    vec3 n = imageLoad(gbuffer_normal, pixel).xyz;
    // The share distance in pixels here: the camera's focal length is the length of the
    // view-projection's second row (the view's rows are unit vectors).
    vec4 clip = frame.view_proj * vec4(x, 1.0);
    float focal = length(vec3(frame.view_proj[0][1], frame.view_proj[1][1], frame.view_proj[2][1]));
    float reach_pixels = params.share_distance * params.radius * focal * 0.5 * float(frame.height) / max(clip.w, 1e-6);
    int stride = max(int(reach_pixels / float(REACH)), 1);
    vec2 sum = own.rg;
    float count = 1.0;
    for (int dy = -REACH; dy <= REACH; ++dy) {
        for (int dx = -REACH; dx <= REACH; ++dx) {
            // Each pair once: the taps after the centre, with their mirror images.
            if (dy < 0 || (dy == 0 && dx <= 0)) {
                continue;
            }
            ivec2 offset = stride * ivec2(dx, dy);
            bool off, mirror_off;
            bool here = on_surface(pixel + offset, x, n, off);
            bool mirror = on_surface(pixel - offset, x, n, mirror_off);
            if (here && (mirror || mirror_off)) {
                sum += imageLoad(measured, pixel + offset).rg;
                count += 1.0;
            }
            if (mirror && (here || off)) {
                sum += imageLoad(measured, pixel - offset).rg;
                count += 1.0;
            }
        }
    }
    imageStore(disk_mass, pixel, vec4(sum / count, own.ba));
}
