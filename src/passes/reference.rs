//! Reference path tracer: adds samples of the indirect radiance leaving each view sample to a
//! running sum (`reference.comp`).

use leakless_device::{BindingDecl, Bound, ComputePipeline, Gpu};
use leakless_graph::{Access, Graph, ImageHandle};

use crate::error::Result;
use crate::gpu_types::{ReferenceParams, REFERENCE_PARAMS_LAYOUT};
use crate::passes::uniform::Uniform;
use crate::passes::{view_bindings, ViewInputs};
use crate::shaders;
use crate::trace::Backend;

/// The pass's own bindings, after those of [`ViewInputs`].
pub const BINDINGS: &[BindingDecl] =
    &[BindingDecl::storage_image("accumulated"), BindingDecl::uniform("params", REFERENCE_PARAMS_LAYOUT)];

pub struct ReferencePass {
    pipeline: ComputePipeline,
    params: Uniform<ReferenceParams>,
}

impl ReferencePass {
    pub fn new(gpu: &Gpu, backend: Backend) -> Result<Self> {
        let shader = backend.pick(&shaders::REFERENCE_COMP_RAYQUERY, &shaders::REFERENCE_COMP_COMPUTE);
        Ok(ReferencePass {
            pipeline: ComputePipeline::new(gpu, "reference", shader, &view_bindings(backend, BINDINGS))?,
            params: Uniform::new(gpu, "reference params")?,
        })
    }

    /// Adds `params.sample_count` samples per view sample to `accumulated`.
    pub fn add<'r>(
        &'r self,
        graph: &mut Graph<'r>,
        params: &ReferenceParams,
        view: &ViewInputs<'_>,
        accumulated: &mut ImageHandle,
    ) -> Result<()> {
        self.params.set(params)?;
        let params = graph.import_buffer(&self.params.buffer);
        let mut pass = graph.pass("reference");
        let mut bound = view.declare(&mut pass);
        bound.push(("params", Bound::Buffer(pass.read(&params, Access::ComputeRead))));
        let out = pass.write(accumulated, Access::ComputeReadWrite);
        bound.push(("accumulated", Bound::Image(out)));
        pass.record(move |cmd| {
            let e = out.extent();
            cmd.dispatch(&self.pipeline, &bound, [e.width, e.height, 1])
        });
        Ok(())
    }
}
