//! What a render leaves on disk: the layered EXR, a tonemapped PNG, the stats JSON.

pub mod exr;
pub mod png;
pub mod stats;
