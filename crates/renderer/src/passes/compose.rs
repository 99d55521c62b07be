//! Compose: final radiance = direct + scaled indirect sum, and the indirect layer itself
//! (`compose.comp`).

use bytemuck::{Pod, Zeroable};
use leakless_device::{gpu_struct, GpuStruct};
use leakless_graph::{shader_bindings, BufferHandle, Graph, ImageHandle, PassName};

use crate::gpu_types::Frame;
use crate::passes::names::group;
use crate::pipelines::{compute_pass, ComputePass};
use crate::shaders;

gpu_struct! {
    /// The `ComposeParams` push constants of compose.comp.
    #[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
    pub struct ComposeParams {
        /// 1/spp for the reference's running sum, 1 for one photon frame, 0 without indirect
        /// light.
        pub indirect_scale: f32,
        /// 0: no gather wrote the leaked and count layers this frame; compose zeroes them.
        pub gathered: u32,
        pub pad1: u32,
        pub pad2: u32,
    }
}

shader_bindings! {
    pub struct ComposeBindings {
        frame: read uniform(Frame::LAYOUT),
        direct: read image,
        indirect_sum: read image,
        indirect: write image,
        radiance: write image,
        leaked: write image,
        gather_counts: write image,
    }
    pub struct ComposeResources;
}

compute_pass! {
    pub static COMPOSE in FRAME_PASSES: ComputePass<ComposeBindings, ComposeParams> =
        ComputePass::any(PassName::new("compose", group::COMPOSE), &shaders::COMPOSE_COMP, &[]);
}

/// The images compose reads and writes.
pub struct ComposeImages<'a> {
    pub direct: &'a ImageHandle,
    pub indirect_sum: &'a ImageHandle,
    pub indirect: &'a mut ImageHandle,
    pub radiance: &'a mut ImageHandle,
    pub leaked: &'a mut ImageHandle,
    pub gather_counts: &'a mut ImageHandle,
}

pub fn add<'r>(graph: &mut Graph<'r>, params: ComposeParams, frame: &BufferHandle, images: ComposeImages<'_>) {
    let extent = images.radiance.extent();
    let resources = ComposeResources {
        frame,
        direct: images.direct,
        indirect_sum: images.indirect_sum,
        indirect: images.indirect,
        radiance: images.radiance,
        leaked: images.leaked,
        gather_counts: images.gather_counts,
    };
    COMPOSE.add(graph, resources, params, [extent.width, extent.height, 1]);
}
