//! The Vulkan device layer of leakless.
//!
//! It hides Vulkan boilerplate, not Vulkan concepts: a [`Gpu`] is an instance, a chosen
//! physical device, a logical device with one queue, a memory allocator and the optional
//! extensions (debug labels, ray queries). Resources ([`Buffer`], [`Image`]) free themselves
//! when dropped. Pipelines are built from SPIR-V embedded at build time and check the
//! bindings a pass declares against the shader's reflection. Every `unsafe` Vulkan call of
//! the project lives in this crate.

mod accel;
mod bind;
mod cmd;
mod error;
mod gpu;
mod instance;
mod memory;
mod pipeline;
mod query;
mod select;
pub mod shader;
pub mod sync;

pub use accel::{
    accel_build_sizes, accel_instance, accel_instances, accel_scratch, AccelGeometry, AccelSizeQueries, AccelSizes,
    AccelerationStructure,
};
pub use ash::vk;
pub use bind::{check_bindings, BindingDecl, Bound, Contents, RustLayout};
pub use cmd::Cmd;
pub use error::{DeviceError, Result};
pub use gpu::{Capabilities, Gpu, GpuOptions};
pub use memory::{Buffer, BufferDesc, Image, ImageDesc, MemoryLocation};
pub use pipeline::{ColorTarget, ComputePipeline, GraphicsDesc, GraphicsPipeline, VertexLayout};
pub use query::TimestampPool;
pub use select::{DeviceReport, DeviceType};

/// Declares the Rust-side layout of a `#[repr(C)]` struct shared with a shader: its size and
/// the byte offset of each named field, so `check_bindings` can compare them with reflection.
#[macro_export]
macro_rules! rust_layout {
    ($ty:ty { $($field:ident),* $(,)? }) => {
        $crate::RustLayout {
            size: ::core::mem::size_of::<$ty>() as u32,
            members: &[$($crate::shader::Member {
                name: stringify!($field),
                offset: ::core::mem::offset_of!($ty, $field) as u32,
            }),*],
        }
    };
}
