//! Sample bounds: the box around every valid view sample (`sample_bounds.comp`), which the
//! Morton codes are quantised to.

use leakless_device::GpuStruct;
use leakless_graph::{shader_bindings, BufferHandle, Fill, Graph, PassName};

use crate::gpu_types::Frame;
use crate::passes::gbuffer::{GBufferBindings, GBufferHandles};
use crate::passes::names::group;
use crate::pipelines::{compute_pass, ComputePass, Threads};
use crate::shaders;

shader_bindings! {
    pub struct SampleBoundsBindings {
        frame: read uniform(Frame::LAYOUT),
        sample_bounds: read_write words,
    }
    pub struct SampleBoundsResources;
}

const SAMPLE_BOUNDS_CLEAR: PassName = PassName::new("sample bounds clear", group::HIERARCHY);

compute_pass! {
    pub static SAMPLE_BOUNDS in FRAME_PASSES: ComputePass<SampleBoundsBindings, ()> =
        ComputePass::any(
            PassName::new("sample bounds", group::HIERARCHY),
            &shaders::SAMPLE_BOUNDS_COMP,
            &[GBufferBindings::DECLS],
        );
}

pub fn add<'r>(graph: &mut Graph<'r>, frame: &BufferHandle, gbuffer: &GBufferHandles, bounds: &mut BufferHandle) {
    // Start from an empty box: min keys all ones, max keys all zeros.
    let empty = [Fill::range(0, 12, u32::MAX), Fill::range(12, 12, 0)];
    graph.fill(SAMPLE_BOUNDS_CLEAR, &mut [(&mut *bounds, &empty)]);
    let extent = gbuffer.position.extent();
    let resources = SampleBoundsResources { frame, sample_bounds: bounds };
    let threads = Threads::Fixed([extent.width, extent.height, 1]);
    SAMPLE_BOUNDS.add_with(graph, resources, |pass| gbuffer.declare(pass), (), threads);
}
