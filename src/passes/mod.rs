//! One pass per file, named after what it computes; each declares its bindings once and adds
//! itself to the frame's graph with the resources it reads and writes.

pub mod direct;
pub mod gbuffer;
pub mod readback;
