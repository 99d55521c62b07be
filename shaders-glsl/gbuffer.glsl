#pragma once
// The G-buffer as every compute pass that reads it binds it, one group here and in Rust
// (passes::gbuffer::GBufferBindings): GBUFFER_BINDINGS(n) declares position (.w = triangle + 1,
// 0 where nothing was hit), viewer-facing normal and albedo at bindings n, n + 1 and n + 2.
#define GBUFFER_BINDINGS(n) \
    layout(set = 1, binding = n, rgba32f) uniform readonly image2D gbuffer_position; \
    layout(set = 1, binding = n + 1, rgba32f) uniform readonly image2D gbuffer_normal; \
    layout(set = 1, binding = n + 2, rgba32f) uniform readonly image2D gbuffer_albedo;
