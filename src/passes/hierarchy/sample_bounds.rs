//! Sample bounds: the box around every valid view sample (`sample_bounds.comp`), which the
//! Morton codes are quantised to.

use leakless_device::{BindingDecl, Bound, ComputePipeline, Gpu};
use leakless_graph::{Access, BufferHandle, Graph};

use crate::error::Result;
use crate::gpu_types::FRAME_LAYOUT;
use crate::passes::gbuffer::GBufferHandles;
use crate::shaders;

pub const BINDINGS: &[BindingDecl] = &[
    BindingDecl::uniform("frame", FRAME_LAYOUT),
    BindingDecl::storage_image("gbuffer_position"),
    BindingDecl::storage_words("sample_bounds"),
];

pub struct SampleBoundsPass {
    pipeline: ComputePipeline,
}

impl SampleBoundsPass {
    pub fn new(gpu: &Gpu) -> Result<Self> {
        Ok(SampleBoundsPass {
            pipeline: ComputePipeline::new(gpu, "sample bounds", &shaders::SAMPLE_BOUNDS_COMP, BINDINGS)?,
        })
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
        clear.record(move |cmd| {
            cmd.fill_buffer(target, 0, 12, u32::MAX);
            cmd.fill_buffer(target, 12, 12, 0);
            Ok(())
        });
        let mut pass = graph.pass("sample bounds");
        let bound = [
            ("frame", Bound::Buffer(pass.read(frame, Access::ComputeRead))),
            ("gbuffer_position", Bound::Image(pass.read(&gbuffer.position, Access::ComputeRead))),
            ("sample_bounds", Bound::Buffer(pass.write(bounds, Access::ComputeReadWrite))),
        ];
        let extent = gbuffer_extent(&bound);
        pass.record(move |cmd| cmd.dispatch(&self.pipeline, &bound, [extent.0, extent.1, 1]));
    }
}

/// The image size of the first image bound (the G-buffer).
pub(super) fn gbuffer_extent(bound: &[(&str, Bound<'_>)]) -> (u32, u32) {
    bound
        .iter()
        .find_map(|(_, b)| match b {
            Bound::Image(i) => Some((i.extent().width, i.extent().height)),
            _ => None,
        })
        .expect("a G-buffer image is bound")
}
