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

pub const FRAME_LAYOUT: RustLayout =
    rust_layout!(Frame { view_proj, camera_position, width, height, light_count, pad0 });

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

pub const LIGHT_LAYOUT: RustLayout = rust_layout!(Light { position, kind, direction, cos_outer, intensity, cos_inner });

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

pub const MATERIAL_LAYOUT: RustLayout =
    rust_layout!(Material { base_color, texture_offset, texture_width, texture_height, alpha_cutoff });

/// `struct SceneVertex` of scene.glsl is `leakless_scene::Vertex`.
pub const VERTEX_LAYOUT: RustLayout = rust_layout!(leakless_scene::Vertex { position, normal, uv });

/// A plain `uint` array element (`uint ids[]`, `uint words[]`).
pub const U32_LAYOUT: RustLayout = RustLayout { size: 4, members: &[] };

/// The `ReferenceParams` block of reference.comp.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct ReferenceParams {
    pub first_sample: u32,
    pub sample_count: u32,
    pub max_bounces: u32,
    pub seed: u32,
    pub roulette_start: u32,
    pub pad0: u32,
    pub pad1: u32,
    pub pad2: u32,
}

pub const REFERENCE_PARAMS_LAYOUT: RustLayout =
    rust_layout!(ReferenceParams { first_sample, sample_count, max_bounces, seed, roulette_start, pad0, pad1, pad2 });

/// The `ComposeParams` block of compose.comp.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct ComposeParams {
    pub indirect_scale: f32,
    pub leaked_written: u32,
    pub pad1: u32,
    pub pad2: u32,
}

pub const COMPOSE_PARAMS_LAYOUT: RustLayout =
    rust_layout!(ComposeParams { indirect_scale, leaked_written, pad1, pad2 });

/// `struct Ray` of raycast.comp.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuRay {
    pub origin: [f32; 3],
    pub tmin: f32,
    pub dir: [f32; 3],
    pub tmax: f32,
}

pub const RAY_LAYOUT: RustLayout = rust_layout!(GpuRay { origin, tmin, dir, tmax });

/// `struct RayHit` of raycast.comp.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct RayHit {
    pub t: f32,
    /// `u32::MAX` on a miss (occlusion rays: 0 = occluded).
    pub triangle: u32,
    pub barycentrics: [f32; 2],
}

pub const RAY_HIT_LAYOUT: RustLayout = rust_layout!(RayHit { t, triangle, barycentrics });

/// The `RaycastParams` block of raycast.comp.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct RaycastParams {
    pub ray_count: u32,
    pub occlusion: u32,
    pub pad0: u32,
    pub pad1: u32,
}

pub const RAYCAST_PARAMS_LAYOUT: RustLayout = rust_layout!(RaycastParams { ray_count, occlusion, pad0, pad1 });
