//! Raycast: traces a buffer of rays and writes one hit record per ray (`raycast.comp`).

use bytemuck::{Pod, Zeroable};
use leakless_device::{gpu_struct, GpuStruct};
use leakless_graph::{shader_bindings, BufferHandle, Graph, PassName, Stage};

use crate::gpu_scene::{SceneBindings, SceneHandles};
use crate::gpu_types::{GpuRay, RayHit};
use crate::passes::names::group;
use crate::pipelines::ComputePassDef;
use crate::shaders;
use crate::trace::TraceHandles;

gpu_struct! {
    /// The `RaycastParams` push constants of raycast.comp.
    #[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
    pub struct RaycastParams {
        pub ray_count: u32,
        /// 1: traceOccluded, 0: traceClosest.
        pub occlusion: u32,
        pub pad0: u32,
        pub pad1: u32,
    }
}

shader_bindings! {
    pub struct RaycastBindings {
        rays: read array(GpuRay::LAYOUT),
        ray_hits: write array(RayHit::LAYOUT),
    }
    pub struct RaycastResources;
}

pub static RAYCAST: ComputePassDef = ComputePassDef::traced(
    PassName::new("raycast", group::TOOLS),
    (&shaders::RAYCAST_COMP_RAYQUERY, &shaders::RAYCAST_COMP_COMPUTE),
    &[RaycastBindings::DECLS, SceneBindings::DECLS],
)
.push(RaycastParams::LAYOUT);

#[allow(clippy::too_many_arguments)]
pub fn add<'r>(
    graph: &mut Graph<'r>,
    ray_count: u32,
    occlusion: bool,
    scene: &SceneHandles,
    trace: &TraceHandles,
    rays: &BufferHandle,
    hits: &mut BufferHandle,
) {
    let params = RaycastParams { ray_count, occlusion: occlusion as u32, ..Default::default() };
    let mut pass = graph.pass(RAYCAST.name);
    let own = RaycastBindings::declare(&mut pass, Stage::Compute, RaycastResources { rays, ray_hits: hits });
    let surfaces = scene.declare(&mut pass, Stage::Compute);
    let trace = trace.declare(&mut pass);
    pass.dispatch(RAYCAST.name, (own, surfaces, trace), params, [ray_count, 1, 1]);
}
