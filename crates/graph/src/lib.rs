//! The pass graph: each pass declares the resources it reads and writes (a write takes the
//! handle mutably, so a call site shows what a pass changes); the graph derives every barrier
//! and layout transition from those declarations, brackets each pass with a debug label, GPU
//! timestamps and a crash marker under one name, and runs the passes in order.

pub mod barrier;
mod graph;
mod runner;

pub use graph::{BufferHandle, Graph, Handle, ImageHandle, PassBuilder};
pub use leakless_device::sync::Access;
pub use runner::{GraphRunner, PassTiming, Timing};
