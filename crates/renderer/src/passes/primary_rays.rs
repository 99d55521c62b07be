//! Primary visibility by ray casting: the G-buffer that `gbuffer.rs` rasterises, from one
//! closest-hit ray per pixel (`primary_rays.comp`). Which of the two a frame uses is
//! `--primary`'s choice ([`Primary`](crate::Primary)), `auto` the device tuning's.

use bytemuck::{Pod, Zeroable};
use leakless_device::{gpu_struct, GpuStruct};
use leakless_graph::{shader_bindings, BufferHandle, Graph, PassName};

use crate::gpu_types::Frame;
use crate::passes::gbuffer::GBufferHandles;
use crate::passes::names::group;
use crate::pipelines::{compute_pass, ComputePass};
use crate::shaders;

gpu_struct! {
    /// The `PrimaryRaysParams` push constants of primary_rays.comp.
    #[derive(Clone, Copy, Debug, Pod, Zeroable)]
    pub struct PrimaryRaysParams {
        /// The inverse of the frame's view-projection.
        pub world_from_clip: [[f32; 4]; 4],
        /// 1: the projection has a far plane.
        pub finite_far: u32,
        pub pad0: u32,
        pub pad1: u32,
        pub pad2: u32,
    }
}

shader_bindings! {
    pub struct PrimaryRaysBindings {
        frame: read uniform(Frame::LAYOUT),
        gbuffer_position: write image,
        gbuffer_normal: write image,
        gbuffer_albedo: write image,
    }
    pub struct PrimaryRaysResources;
}

compute_pass! {
    pub static PRIMARY_RAYS in FRAME_PASSES: ComputePass<PrimaryRaysBindings, PrimaryRaysParams> =
        ComputePass::traced(
            PassName::new("primary rays", group::VIEW),
            (&shaders::PRIMARY_RAYS_COMP_RAYQUERY, &shaders::PRIMARY_RAYS_COMP_COMPUTE),
            &[],
        )
        .on_demand();
}

/// Writes `out`'s position, normal and albedo (its depth is the raster's alone).
pub fn add<'r>(graph: &mut Graph<'r>, params: PrimaryRaysParams, frame: &BufferHandle, out: &mut GBufferHandles) {
    let extent = out.position.extent();
    let resources = PrimaryRaysResources {
        frame,
        gbuffer_position: &mut out.position,
        gbuffer_normal: &mut out.normal,
        gbuffer_albedo: &mut out.albedo,
    };
    PRIMARY_RAYS.add(graph, resources, params, [extent.width, extent.height, 1]);
}
