//! Morton codes: a 30-bit key per pixel from its view sample's position in the sample bounds,
//! with the pixel index as value (`morton.comp`).

use leakless_device::{BindingDecl, Bound, ComputePipeline, Gpu};
use leakless_graph::{Access, BufferHandle, Graph};

use super::sample_bounds::gbuffer_extent;
use crate::error::Result;
use crate::gpu_types::FRAME_LAYOUT;
use crate::passes::gbuffer::GBufferHandles;
use crate::shaders;

pub const BINDINGS: &[BindingDecl] = &[
    BindingDecl::uniform("frame", FRAME_LAYOUT),
    BindingDecl::storage_image("gbuffer_position"),
    BindingDecl::storage_words("sample_bounds"),
    BindingDecl::storage_words("morton_keys"),
    BindingDecl::storage_words("morton_values"),
];

pub struct MortonPass {
    pipeline: ComputePipeline,
}

impl MortonPass {
    pub fn new(gpu: &Gpu) -> Result<Self> {
        Ok(MortonPass { pipeline: ComputePipeline::new(gpu, "morton", &shaders::MORTON_COMP, BINDINGS)? })
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
        let mut pass = graph.pass("morton");
        let bound = [
            ("gbuffer_position", Bound::Image(pass.read(&gbuffer.position, Access::ComputeRead))),
            ("frame", Bound::Buffer(pass.read(frame, Access::ComputeRead))),
            ("sample_bounds", Bound::Buffer(pass.read(bounds, Access::ComputeRead))),
            ("morton_keys", Bound::Buffer(pass.write(keys, Access::ComputeWrite))),
            ("morton_values", Bound::Buffer(pass.write(values, Access::ComputeWrite))),
        ];
        let extent = gbuffer_extent(&bound);
        pass.record(move |cmd| cmd.dispatch(&self.pipeline, &bound, [extent.0, extent.1, 1]));
    }
}
