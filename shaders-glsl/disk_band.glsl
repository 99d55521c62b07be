// The band around a view sample's tangent plane within which a point counts as on its surface:
// what the visible disk, the gather (disk.glsl) and disk smoothing share, without the scene's
// bindings disk.glsl needs.
#ifndef LEAKLESS_DISK_BAND_GLSL
#define LEAKLESS_DISK_BAND_GLSL

const float DISK_SLOPE = 0.1763;            // tan 10°: the band around the tangent plane

#endif
