//! Morton codes: a 30-bit key per pixel from its view sample's position in the sample bounds,
//! with the pixel index as value (`morton.comp`).

use leakless_device::{ComputePipeline, Gpu, GpuStruct};
use leakless_graph::{shader_bindings, Access, BufferHandle, Graph};

use crate::error::Result;
use crate::gpu_types::Frame;
use crate::passes::gbuffer::GBufferHandles;
use crate::shaders;

shader_bindings! {
    pub struct MortonBindings {
        frame: uniform(Frame::LAYOUT),
        gbuffer_position: image,
        sample_bounds: words,
        morton_keys: words,
        morton_values: words,
    }
}

pub struct MortonPass {
    pipeline: ComputePipeline,
}

impl MortonPass {
    pub fn new(gpu: &Gpu) -> Result<Self> {
        let pipeline = ComputePipeline::new(gpu, "morton", &shaders::MORTON_COMP, MortonBindings::DECLS, None)?;
        Ok(MortonPass { pipeline })
    }

    pub fn add<'r>(
        &'r self,
        graph: &mut Graph<'r>,
        frame: &BufferHandle,
        gbuffer: &GBufferHandles,
        bounds: &BufferHandle,
        keys: &mut BufferHandle,
        values: &mut BufferHandle,
    ) {
        let extent = gbuffer.position.extent();
        let mut pass = graph.pass("morton");
        let own = MortonBindings {
            frame: pass.read(frame, Access::ComputeRead),
            gbuffer_position: pass.read(&gbuffer.position, Access::ComputeRead),
            sample_bounds: pass.read(bounds, Access::ComputeRead),
            morton_keys: pass.write(keys, Access::ComputeWrite),
            morton_values: pass.write(values, Access::ComputeWrite),
        };
        pass.record(move |ctx| ctx.dispatch(&self.pipeline, &[&own], &(), [extent.width, extent.height, 1]));
    }
}
