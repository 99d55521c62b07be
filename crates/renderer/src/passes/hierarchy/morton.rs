//! Morton codes: a 30-bit key per pixel from its view sample's position in the sample bounds,
//! with the pixel index as value (`morton.comp`).

use leakless_device::GpuStruct;
use leakless_graph::{shader_bindings, BufferHandle, Graph, PassName};

use crate::gpu_types::Frame;
use crate::passes::gbuffer::{GBufferBindings, GBufferHandles};
use crate::passes::names::group;
use crate::pipelines::{compute_pass, ComputePass, Threads};
use crate::shaders;

shader_bindings! {
    pub struct MortonBindings {
        frame: read uniform(Frame::LAYOUT),
        sample_bounds: read words,
        morton_keys: write words,
        morton_values: write words,
    }
    pub struct MortonResources;
}

compute_pass! {
    pub static MORTON in FRAME_PASSES: ComputePass<MortonBindings, ()> =
        ComputePass::any(PassName::new("morton", group::HIERARCHY), &shaders::MORTON_COMP, &[GBufferBindings::DECLS]);
}

pub fn add<'r>(
    graph: &mut Graph<'r>,
    frame: &BufferHandle,
    gbuffer: &GBufferHandles,
    bounds: &BufferHandle,
    keys: &mut BufferHandle,
    values: &mut BufferHandle,
) {
    let extent = gbuffer.position.extent();
    let resources = MortonResources { frame, sample_bounds: bounds, morton_keys: keys, morton_values: values };
    let threads = Threads::Fixed([extent.width, extent.height, 1]);
    MORTON.add_with(graph, resources, |pass| gbuffer.declare(pass), (), threads);
}
