//! Buffers that shaders read through their device addresses as well as their bindings.
//!
//! lavapipe compiles a storage-buffer load whose address differs between lanes into a loop over
//! the lanes with a bounds-checked branch per lane and word, and a load through a device
//! address (`GL_EXT_buffer_reference`) into one masked vector gather. The hottest scattered
//! reads (the compute BVH's nodes and triangles, the hierarchy's nodes in the splat) therefore
//! go through addresses, where the indices come from data this renderer built and tested, so
//! the bounds checks guard nothing. The buffer stays bound: the binding is what reflection
//! checks and what the graph orders the pass by; the shader's reflection twin reads it there.
//! On a GPU the two loads cost the same.

use ash::vk;

/// `address` as the `uvec2` a shader makes a buffer reference of (`GL_EXT_buffer_reference_uvec2`).
///
/// # Panics
/// On `None`: the buffer was made without `SHADER_DEVICE_ADDRESS` usage, a bug of the caller.
pub fn address_words(address: Option<vk::DeviceAddress>) -> [u32; 2] {
    let address = address.expect("a buffer read through its device address is made with SHADER_DEVICE_ADDRESS usage");
    [address as u32, (address >> 32) as u32]
}
