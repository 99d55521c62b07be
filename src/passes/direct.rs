//! Direct light: Lambertian reflection of every punctual light at each view sample, with one
//! shadow ray per light (`direct.comp`).

use leakless_device::{BindingDecl, Bound, ComputePipeline, Gpu};
use leakless_graph::{Access, Graph, ImageHandle};

use crate::error::Result;
use crate::passes::{view_bindings, ViewInputs};
use crate::shaders;
use crate::trace::Backend;

/// The pass's own bindings, after those of [`ViewInputs`].
pub const BINDINGS: &[BindingDecl] = &[BindingDecl::storage_image("direct")];

pub struct DirectPass {
    pipeline: ComputePipeline,
}

impl DirectPass {
    pub fn new(gpu: &Gpu, backend: Backend) -> Result<Self> {
        let shader = backend.pick(&shaders::DIRECT_COMP_RAYQUERY, &shaders::DIRECT_COMP_COMPUTE);
        Ok(DirectPass { pipeline: ComputePipeline::new(gpu, "direct", shader, &view_bindings(backend, BINDINGS))? })
    }

    pub fn add<'r>(&'r self, graph: &mut Graph<'r>, view: &ViewInputs<'_>, direct: &mut ImageHandle) {
        let mut pass = graph.pass("direct");
        let mut bound = view.declare(&mut pass);
        let out = pass.write(direct, Access::ComputeWrite);
        bound.push(("direct", Bound::Image(out)));
        pass.record(move |cmd| {
            let e = out.extent();
            cmd.dispatch(&self.pipeline, &bound, [e.width, e.height, 1])
        });
    }
}
