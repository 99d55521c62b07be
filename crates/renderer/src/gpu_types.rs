//! Rust twins of the structs declared in `shaders-glsl/common.glsl` and `scene.glsl`. Each is
//! declared with `gpu_struct!`, and pipeline creation checks size and every member offset
//! against the shader's reflection, so the two sides cannot drift apart silently. Structs of
//! one pass live in that pass's file.

use bytemuck::{Pod, Zeroable};
use leakless_device::gpu_struct;

gpu_struct! {
    /// The `Frame` uniform block (`FRAME_BLOCK` in common.glsl): camera and output size,
    /// uploaded once per frame.
    #[derive(Clone, Copy, Debug, Pod, Zeroable)]
    pub struct Frame {
        pub view_proj: [[f32; 4]; 4],
        pub camera_position: [f32; 4],
        pub width: u32,
        pub height: u32,
        pub light_count: u32,
        pub emitter_count: u32,
    }
}

gpu_struct! {
    /// `struct Light` of common.glsl.
    #[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
    pub struct Light {
        pub position: [f32; 3],
        pub kind: u32,
        pub direction: [f32; 3],
        pub cos_outer: f32,
        pub intensity: [f32; 3],
        pub cos_inner: f32,
    }
}

pub const LIGHT_POINT: u32 = 0;
pub const LIGHT_SPOT: u32 = 1;
pub const LIGHT_DIRECTIONAL: u32 = 2;

gpu_struct! {
    /// `struct Material` of common.glsl.
    #[derive(Clone, Copy, Debug, Pod, Zeroable)]
    pub struct Material {
        pub base_color: [f32; 4],
        pub texture_offset: u32,
        pub texture_width: u32,
        pub texture_height: u32,
        pub alpha_cutoff: f32,
        pub emission: [f32; 3],
        pub double_sided: u32,
        pub emission_texture_offset: u32,
        pub emission_texture_width: u32,
        pub emission_texture_height: u32,
        pub pad0: u32,
    }
}

gpu_struct! {
    /// `struct Emitter` of emitters.glsl: one emissive triangle and its place in the CDF that
    /// next-event estimation picks emitters by.
    #[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
    pub struct Emitter {
        pub triangle: u32,
        pub cdf: f32,
        pub probability: f32,
        pub pad0: u32,
    }
}

gpu_struct! {
    /// `struct Ray` of raycast.comp (also made on the CPU by `raygen`).
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct GpuRay {
        pub origin: [f32; 3],
        pub tmin: f32,
        pub dir: [f32; 3],
        pub tmax: f32,
    }
}

gpu_struct! {
    /// `struct RayHit` of raycast.comp.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct RayHit {
        pub t: f32,
        /// `u32::MAX` on a miss (occlusion rays: 0 = occluded).
        pub triangle: u32,
        pub barycentrics: [f32; 2],
    }
}
