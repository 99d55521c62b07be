//! Compose: final radiance = direct + scaled indirect sum, and the indirect layer itself
//! (`compose.comp`).

use bytemuck::{Pod, Zeroable};
use leakless_device::{gpu_struct, ComputePipeline, Gpu, GpuStruct};
use leakless_graph::{shader_bindings, Access, BufferHandle, Graph, ImageHandle};

use crate::error::Result;
use crate::gpu_types::Frame;
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
        frame: uniform(Frame::LAYOUT),
        direct: image,
        indirect_sum: image,
        indirect: image,
        radiance: image,
        leaked: image,
        gather_counts: image,
    }
}

pub struct ComposePass {
    pipeline: ComputePipeline,
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

impl ComposePass {
    pub fn new(gpu: &Gpu) -> Result<Self> {
        let pipeline = ComputePipeline::new(
            gpu,
            "compose",
            &shaders::COMPOSE_COMP,
            ComposeBindings::DECLS,
            Some(&ComposeParams::LAYOUT),
        )?;
        Ok(ComposePass { pipeline })
    }

    pub fn add<'r>(
        &'r self,
        graph: &mut Graph<'r>,
        params: ComposeParams,
        frame: &BufferHandle,
        images: ComposeImages<'_>,
    ) {
        let extent = images.radiance.extent();
        let mut pass = graph.pass("compose");
        let own = ComposeBindings {
            frame: pass.read(frame, Access::ComputeRead),
            direct: pass.read(images.direct, Access::ComputeRead),
            indirect_sum: pass.read(images.indirect_sum, Access::ComputeRead),
            indirect: pass.write(images.indirect, Access::ComputeWrite),
            radiance: pass.write(images.radiance, Access::ComputeWrite),
            leaked: pass.write(images.leaked, Access::ComputeReadWrite),
            gather_counts: pass.write(images.gather_counts, Access::ComputeReadWrite),
        };
        pass.record(move |ctx| ctx.dispatch(&self.pipeline, &[&own], &params, [extent.width, extent.height, 1]));
    }
}
