//! The pass graph: each pass declares the resources it reads and writes (a write takes the
//! handle mutably, so a call site shows what a pass changes); the graph derives every barrier
//! and layout transition from those declarations, brackets each pass with a debug label, GPU
//! timestamps and a crash marker under one name, and runs the passes in order.
//!
//! Resources are imported (the scene's buffers) or owned by the runner's pool by name, kept
//! from frame to frame and remade when their description changes. Frames run in flight: the
//! host records the next frame while the GPU runs the last, and per-frame resources (uploads,
//! readbacks) have one copy per frame in flight. A pass's bindings are declared once, with
//! [`shader_bindings!`], and checked against the shader's reflection.

pub mod barrier;
mod bindings;
mod fill;
mod graph;
mod history;
mod name;
mod pipelines;
mod pool;
mod runner;

pub use bindings::{BindingGroup, Bindings, DeclareBindings, PassContext, Resolved, Stage};
pub use fill::Fill;
pub use graph::{Buf, BufferHandle, Graph, Handle, ImageHandle, Img, PassBuilder};
pub use history::History;
pub use leakless_device::sync::Access;
pub use leakless_device::{vk, BindingAccess, BindingDecl, Bound};
pub use name::PassName;
pub use pipelines::PipelineTable;
pub use pool::ResourcePool;
pub use runner::{CompletedFrame, GraphRunner, PassTiming, Submitted, Timing, MAX_PASSES};
