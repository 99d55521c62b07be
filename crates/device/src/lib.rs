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
mod commands;
mod error;
mod frame_set;
mod gpu;
mod instance;
mod layout;
mod memory;
mod pipeline;
mod query;
mod select;
pub mod shader;
mod swapchain;
pub mod sync;

pub use accel::{
    accel_build_sizes, accel_instance, accel_instances, accel_scratch, AccelGeometry, AccelSizeQueries, AccelSizes,
    AccelerationStructure,
};
pub use ash::vk;
pub use bind::{
    check_bindings, check_push_constants, BindingDecl, Bound, Contents, MatchedBindings, FRAME_SET, PASS_SET,
};
pub use cmd::Cmd;
pub use commands::{CommandSlot, Semaphore, SubmitSync};
pub use error::{DeviceError, Result};
pub use frame_set::{BoundFrameSet, FrameBinding, PUSH_RANGE};
pub use gpu::{Capabilities, Gpu, GpuOptions, RawVulkan, WindowHandles};
pub use layout::{GpuStruct, PushConstants, RustLayout};
pub use memory::{Buffer, BufferDesc, Image, ImageDesc, MemoryLocation};
pub use pipeline::{ColorTarget, ComputePipeline, GraphicsDesc, GraphicsPipeline, Specialization, VertexLayout};
pub use query::TimestampPool;
pub use select::{DeviceLimits, DeviceReport, DeviceType, PerStageLimits};
pub use shader::BindingAccess;
pub use swapchain::{Acquired, PresentMode, PresentOutcome, Swapchain};
