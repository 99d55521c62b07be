//! Sample bounds: the box around every valid view sample (`sample_bounds.comp`), which the
//! Morton codes are quantised to.

use leakless_device::{ComputePipeline, Gpu, GpuStruct};
use leakless_graph::{shader_bindings, Access, BufferHandle, Graph};

use crate::error::Result;
use crate::gpu_types::Frame;
use crate::passes::gbuffer::GBufferHandles;
use crate::shaders;

shader_bindings! {
    pub struct SampleBoundsBindings {
        frame: uniform(Frame::LAYOUT),
        gbuffer_position: image,
        sample_bounds: words,
    }
}

pub struct SampleBoundsPass {
    pipeline: ComputePipeline,
}

impl SampleBoundsPass {
    pub fn new(gpu: &Gpu) -> Result<Self> {
        let shader = &shaders::SAMPLE_BOUNDS_COMP;
        let pipeline = ComputePipeline::new(gpu, "sample bounds", shader, SampleBoundsBindings::DECLS, None)?;
        Ok(SampleBoundsPass { pipeline })
    }

    pub fn add<'r>(
        &'r self,
        graph: &mut Graph<'r>,
        frame: &BufferHandle,
        gbuffer: &GBufferHandles,
        bounds: &mut BufferHandle,
    ) {
        // Start from an empty box: min keys all ones, max keys all zeros.
        let mut clear = graph.pass("sample bounds clear");
        let target = clear.write(bounds, Access::TransferWrite);
        clear.record(move |ctx| {
            let target = ctx.buffer(target);
            ctx.cmd.fill_buffer(target, 0, 12, u32::MAX);
            ctx.cmd.fill_buffer(target, 12, 12, 0);
            Ok(())
        });
        let extent = gbuffer.position.extent();
        let mut pass = graph.pass("sample bounds");
        let own = SampleBoundsBindings {
            frame: pass.read(frame, Access::ComputeRead),
            gbuffer_position: pass.read(&gbuffer.position, Access::ComputeRead),
            sample_bounds: pass.write(bounds, Access::ComputeReadWrite),
        };
        pass.record(move |ctx| ctx.dispatch(&self.pipeline, &[&own], &(), [extent.width, extent.height, 1]));
    }
}
