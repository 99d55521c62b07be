//! Rust twins of the structs declared in `shaders-glsl/common.glsl`. Each pass declares them
//! with `rust_layout!`, and pipeline creation checks size and every member offset against the
//! shader's reflection, so the two sides cannot drift apart silently.

use bytemuck::{Pod, Zeroable};
use leakless_device::{rust_layout, RustLayout};

/// The `Frame` uniform block (`FRAME_BLOCK` in common.glsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct Frame {
    pub view_proj: [[f32; 4]; 4],
    pub camera_position: [f32; 4],
    pub width: u32,
    pub height: u32,
    pub light_count: u32,
    pub pad0: u32,
}

pub const FRAME_LAYOUT: RustLayout = rust_layout!(Frame {
    view_proj,
    camera_position,
    width,
    height,
    light_count,
    pad0
});

/// `struct Light` of common.glsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct Light {
    pub position: [f32; 3],
    pub kind: u32,
    pub direction: [f32; 3],
    pub cos_outer: f32,
    pub intensity: [f32; 3],
    pub cos_inner: f32,
}

pub const LIGHT_LAYOUT: RustLayout = rust_layout!(Light {
    position,
    kind,
    direction,
    cos_outer,
    intensity,
    cos_inner
});

pub const LIGHT_POINT: u32 = 0;
pub const LIGHT_SPOT: u32 = 1;
pub const LIGHT_DIRECTIONAL: u32 = 2;

/// `struct Material` of common.glsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct Material {
    pub base_color: [f32; 4],
    pub texture_offset: u32,
    pub texture_width: u32,
    pub texture_height: u32,
    pub alpha_cutoff: f32,
}

pub const MATERIAL_LAYOUT: RustLayout = rust_layout!(Material {
    base_color,
    texture_offset,
    texture_width,
    texture_height,
    alpha_cutoff
});

/// A plain `uint` array element (`uint ids[]`, `uint words[]`).
pub const U32_LAYOUT: RustLayout = RustLayout {
    size: 4,
    members: &[],
};
