//! Direct light: Lambertian reflection of every punctual light at each view sample, with one
//! shadow ray per light (`direct.comp`).

use leakless_device::{ComputePipeline, Gpu};
use leakless_graph::{shader_bindings, Access, Graph, ImageHandle};

use crate::error::Result;
use crate::passes::{view_bindings, ViewInputs};
use crate::shaders;
use crate::trace::Backend;

shader_bindings! {
    /// The pass's own bindings, after those of [`ViewInputs`].
    pub struct DirectBindings {
        direct: image,
    }
}

pub struct DirectPass {
    pipeline: ComputePipeline,
}

impl DirectPass {
    pub fn new(gpu: &Gpu, backend: Backend) -> Result<Self> {
        let shader = backend.pick(&shaders::DIRECT_COMP_RAYQUERY, &shaders::DIRECT_COMP_COMPUTE);
        let decls = view_bindings(backend, DirectBindings::DECLS);
        Ok(DirectPass { pipeline: ComputePipeline::new(gpu, "direct", shader, &decls, None)? })
    }

    pub fn add<'r>(&'r self, graph: &mut Graph<'r>, view: &ViewInputs<'_>, direct: &mut ImageHandle) {
        let extent = direct.extent();
        let mut pass = graph.pass("direct");
        let (inputs, surfaces, trace) = view.declare(&mut pass);
        let own = DirectBindings { direct: pass.write(direct, Access::ComputeWrite) };
        pass.record(move |ctx| {
            ctx.dispatch(&self.pipeline, &[&inputs, &surfaces, &trace, &own], &(), [extent.width, extent.height, 1])
        });
    }
}
