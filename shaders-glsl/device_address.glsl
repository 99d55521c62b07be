// Reads through device addresses: a buffer that a pass binds is also read by its address, which
// the pass passes as a uvec2 (crates/renderer/src/device_address.rs says why and when). The
// reflection twin, which naga parses and which reads no device address, reads the binding
// instead: each caller defines its read macros both ways.
#ifndef LEAKLESS_DEVICE_ADDRESS_GLSL
#define LEAKLESS_DEVICE_ADDRESS_GLSL
#ifndef LEAKLESS_REFLECTION
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
// BLOCK(address).values: a read-only array of TYPE at a device address, aligned to ALIGN bytes.
#define ARRAY_AT(BLOCK, TYPE, ALIGN) \
    layout(buffer_reference, std430, buffer_reference_align = ALIGN) readonly buffer BLOCK { TYPE values[]; }
#endif
#endif
