//! Raycast: traces a buffer of rays and writes one hit record per ray (`raycast.comp`).

use bytemuck::{Pod, Zeroable};
use leakless_device::{gpu_struct, GpuStruct, Specialization};
use leakless_graph::{shader_bindings, BufferHandle, Graph, PassName};

use crate::gpu_types::{GpuRay, RayHit};
use crate::passes::names::group;
use crate::pipelines::{compute_pass, ComputePass};
use crate::shaders;

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

gpu_struct! {
    /// `struct RayWork` of raycast.comp: what the compute traversal did for one ray, counted
    /// where the pipeline counts ([`RAYCAST_COUNTING`]).
    #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
    pub struct RayWork {
        /// Bottom-level nodes processed (interior or leaf), the root included.
        pub nodes: u32,
        /// Ray/triangle tests.
        pub triangles: u32,
    }
}

shader_bindings! {
    pub struct RaycastBindings {
        rays: read array(GpuRay::LAYOUT),
        ray_hits: write array(RayHit::LAYOUT),
        ray_work: write array(RayWork::LAYOUT),
    }
    pub struct RaycastResources;
}

compute_pass! {
    pub static RAYCAST in TOOL_PASSES: ComputePass<RaycastBindings, RaycastParams> =
        ComputePass::traced(
            PassName::new("raycast", group::TOOLS),
            (&shaders::RAYCAST_COMP_RAYQUERY, &shaders::RAYCAST_COMP_COMPUTE),
            &[],
        );
}

/// The same pass counting the compute traversal's work per ray (`TRACE_COUNT_WORK`), in a
/// pipeline set of its own (no frame counts): `bench rays` times
/// [`RAYCAST`] and counts with this one. The compute backend's only: ray queries count nothing.
pub static RAYCAST_COUNTING: ComputePass<RaycastBindings, RaycastParams> = ComputePass::traced(
    PassName::new("raycast counting", group::TOOLS),
    (&shaders::RAYCAST_COMP_RAYQUERY, &shaders::RAYCAST_COMP_COMPUTE),
    &[],
)
.specialize(|_| Specialization::new().with("TRACE_COUNT_WORK", 1));

/// Traces `rays` with `def` ([`RAYCAST`], or [`RAYCAST_COUNTING`], which also writes `work`).
#[allow(clippy::too_many_arguments)]
pub fn add<'r>(
    graph: &mut Graph<'r>,
    def: &ComputePass<RaycastBindings, RaycastParams>,
    (ray_count, occlusion): (u32, bool),
    rays: &BufferHandle,
    hits: &mut BufferHandle,
    work: &mut BufferHandle,
) {
    let params = RaycastParams { ray_count, occlusion: occlusion as u32, ..Default::default() };
    let resources = RaycastResources { rays, ray_hits: hits, ray_work: work };
    def.add(graph, resources, params, [ray_count, 1, 1]);
}
