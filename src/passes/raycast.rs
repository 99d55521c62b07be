//! Raycast: traces a buffer of rays and writes one hit record per ray (`raycast.comp`).

use bytemuck::{Pod, Zeroable};
use leakless_device::{gpu_struct, BindingDecl, ComputePipeline, Gpu, GpuStruct};
use leakless_graph::{shader_bindings, Access, BufferHandle, Graph};

use crate::error::Result;
use crate::gpu_scene::{SceneBindings, SceneHandles};
use crate::gpu_types::{GpuRay, RayHit};
use crate::shaders;
use crate::trace::{Backend, TraceHandles};

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
        rays: array(GpuRay::LAYOUT),
        ray_hits: array(RayHit::LAYOUT),
    }
}

pub fn bindings(backend: Backend) -> Vec<BindingDecl> {
    [RaycastBindings::DECLS, SceneBindings::DECLS, backend.bindings()].concat()
}

pub struct RaycastPass {
    pipeline: ComputePipeline,
}

impl RaycastPass {
    pub fn new(gpu: &Gpu, backend: Backend) -> Result<Self> {
        let shader = backend.pick(&shaders::RAYCAST_COMP_RAYQUERY, &shaders::RAYCAST_COMP_COMPUTE);
        let pipeline = ComputePipeline::new(gpu, "raycast", shader, &bindings(backend), Some(&RaycastParams::LAYOUT))?;
        Ok(RaycastPass { pipeline })
    }

    #[allow(clippy::too_many_arguments)]
    pub fn add<'r>(
        &'r self,
        graph: &mut Graph<'r>,
        ray_count: u32,
        occlusion: bool,
        scene: &SceneHandles,
        trace: &TraceHandles,
        rays: &BufferHandle,
        hits: &mut BufferHandle,
    ) {
        let params = RaycastParams { ray_count, occlusion: occlusion as u32, ..Default::default() };
        let mut pass = graph.pass("raycast");
        let own = RaycastBindings {
            rays: pass.read(rays, Access::ComputeRead),
            ray_hits: pass.write(hits, Access::ComputeWrite),
        };
        let surfaces = scene.declare(&mut pass, Access::ComputeRead);
        let trace = trace.declare(&mut pass);
        pass.record(move |ctx| ctx.dispatch(&self.pipeline, &[&own, &surfaces, &trace], &params, [ray_count, 1, 1]));
    }
}
