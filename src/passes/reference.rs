//! Reference path tracer: adds samples of the indirect radiance leaving each view sample to a
//! running sum (`reference.comp`).

use bytemuck::{Pod, Zeroable};
use leakless_device::{gpu_struct, ComputePipeline, Gpu, GpuStruct};
use leakless_graph::{shader_bindings, Access, Graph, ImageHandle};

use crate::error::Result;
use crate::passes::{view_bindings, ViewInputs};
use crate::shaders;
use crate::trace::Backend;

gpu_struct! {
    /// The `ReferenceParams` push constants of reference.comp.
    #[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
    pub struct ReferenceParams {
        /// Samples already in the sum (0: start over).
        pub first_sample: u32,
        /// Samples this dispatch adds.
        pub sample_count: u32,
        pub max_bounces: u32,
        pub seed: u32,
        /// Bounces before Russian roulette may end a path.
        pub roulette_start: u32,
        /// 1: start the sum over while `first_sample` continues the sequence (a progressive
        /// reference's frames: each is a whole image, averaged by the accumulate pass).
        pub restart: u32,
        pub pad1: u32,
        pub pad2: u32,
    }
}

shader_bindings! {
    /// The pass's own bindings, after those of [`ViewInputs`].
    pub struct ReferenceBindings {
        accumulated: image,
    }
}

pub struct ReferencePass {
    pipeline: ComputePipeline,
}

impl ReferencePass {
    pub fn new(gpu: &Gpu, backend: Backend) -> Result<Self> {
        let shader = backend.pick(&shaders::REFERENCE_COMP_RAYQUERY, &shaders::REFERENCE_COMP_COMPUTE);
        let decls = view_bindings(backend, ReferenceBindings::DECLS);
        let pipeline = ComputePipeline::new(gpu, "reference", shader, &decls, Some(&ReferenceParams::LAYOUT))?;
        Ok(ReferencePass { pipeline })
    }

    /// Adds `params.sample_count` samples per view sample to `accumulated` (overwrites it
    /// when `params.first_sample` is 0).
    pub fn add<'r>(
        &'r self,
        graph: &mut Graph<'r>,
        params: ReferenceParams,
        view: &ViewInputs<'_>,
        accumulated: &mut ImageHandle,
    ) {
        let extent = accumulated.extent();
        let mut pass = graph.pass("reference");
        let (inputs, surfaces, trace) = view.declare(&mut pass);
        let own = ReferenceBindings { accumulated: pass.write(accumulated, Access::ComputeReadWrite) };
        pass.record(move |ctx| {
            let groups: [&dyn leakless_graph::Bindings; 4] = [&inputs, &surfaces, &trace, &own];
            ctx.dispatch(&self.pipeline, &groups, &params, [extent.width, extent.height, 1])
        });
    }
}
