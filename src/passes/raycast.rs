//! Raycast: traces a buffer of rays and writes one hit record per ray (`raycast.comp`).

use leakless_device::{BindingDecl, Bound, ComputePipeline, Gpu};
use leakless_graph::{Access, BufferHandle, Graph};

use crate::error::Result;
use crate::gpu_scene::{SceneHandles, SCENE_BINDINGS};
use crate::gpu_types::{RaycastParams, RAYCAST_PARAMS_LAYOUT, RAY_HIT_LAYOUT, RAY_LAYOUT};
use crate::passes::uniform::Uniform;
use crate::shaders;
use crate::trace::{Backend, TraceHandles};

pub const BINDINGS: &[BindingDecl] = &[
    BindingDecl::storage_array("rays", RAY_LAYOUT),
    BindingDecl::storage_array("ray_hits", RAY_HIT_LAYOUT),
    BindingDecl::uniform("params", RAYCAST_PARAMS_LAYOUT),
];

pub fn bindings(backend: Backend) -> Vec<BindingDecl> {
    [BINDINGS, SCENE_BINDINGS, backend.bindings()].concat()
}

pub struct RaycastPass {
    pipeline: ComputePipeline,
    params: Uniform<RaycastParams>,
}

impl RaycastPass {
    pub fn new(gpu: &Gpu, backend: Backend) -> Result<Self> {
        let shader = backend.pick(&shaders::RAYCAST_COMP_RAYQUERY, &shaders::RAYCAST_COMP_COMPUTE);
        Ok(RaycastPass {
            pipeline: ComputePipeline::new(gpu, "raycast", shader, &bindings(backend))?,
            params: Uniform::new(gpu, "raycast params")?,
        })
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
    ) -> Result<()> {
        self.params.set(&RaycastParams { ray_count, occlusion: occlusion as u32, ..Default::default() })?;
        let params = graph.import_buffer(&self.params.buffer);
        let mut pass = graph.pass("raycast");
        let mut bound = vec![
            ("rays", Bound::Buffer(pass.read(rays, Access::ComputeRead))),
            ("params", Bound::Buffer(pass.read(&params, Access::ComputeRead))),
            ("ray_hits", Bound::Buffer(pass.write(hits, Access::ComputeWrite))),
        ];
        bound.extend(scene.declare(&mut pass, Access::ComputeRead));
        bound.extend(trace.declare(&mut pass));
        pass.record(move |cmd| cmd.dispatch(&self.pipeline, &bound, [ray_count, 1, 1]));
        Ok(())
    }
}
