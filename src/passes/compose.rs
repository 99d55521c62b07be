//! Compose: final radiance = direct + scaled indirect sum, and the indirect layer itself
//! (`compose.comp`).

use leakless_device::{BindingDecl, Bound, ComputePipeline, Gpu};
use leakless_graph::{Access, BufferHandle, Graph, ImageHandle};

use crate::error::Result;
use crate::gpu_types::{ComposeParams, COMPOSE_PARAMS_LAYOUT, FRAME_LAYOUT};
use crate::passes::uniform::Uniform;
use crate::shaders;

pub const BINDINGS: &[BindingDecl] = &[
    BindingDecl::uniform("frame", FRAME_LAYOUT),
    BindingDecl::storage_image("direct"),
    BindingDecl::storage_image("indirect_sum"),
    BindingDecl::storage_image("indirect"),
    BindingDecl::storage_image("radiance"),
    BindingDecl::uniform("params", COMPOSE_PARAMS_LAYOUT),
    BindingDecl::storage_image("leaked"),
];

pub struct ComposePass {
    pipeline: ComputePipeline,
    params: Uniform<ComposeParams>,
}

/// The images compose reads and writes.
pub struct ComposeImages<'a> {
    pub direct: &'a ImageHandle,
    pub indirect_sum: &'a ImageHandle,
    pub indirect: &'a mut ImageHandle,
    pub radiance: &'a mut ImageHandle,
    pub leaked: &'a mut ImageHandle,
}

impl ComposePass {
    pub fn new(gpu: &Gpu) -> Result<Self> {
        Ok(ComposePass {
            pipeline: ComputePipeline::new(gpu, "compose", &shaders::COMPOSE_COMP, BINDINGS)?,
            params: Uniform::new(gpu, "compose params")?,
        })
    }

    pub fn add<'r>(
        &'r self,
        graph: &mut Graph<'r>,
        indirect_scale: f32,
        leaked_written: bool,
        frame: &BufferHandle,
        images: ComposeImages<'_>,
    ) -> Result<()> {
        self.params.set(&ComposeParams {
            indirect_scale,
            leaked_written: leaked_written as u32,
            ..Default::default()
        })?;
        let params = graph.import_buffer(&self.params.buffer);
        let mut pass = graph.pass("compose");
        let mut bound = vec![
            ("frame", Bound::Buffer(pass.read(frame, Access::ComputeRead))),
            ("params", Bound::Buffer(pass.read(&params, Access::ComputeRead))),
            ("direct", Bound::Image(pass.read(images.direct, Access::ComputeRead))),
            ("indirect_sum", Bound::Image(pass.read(images.indirect_sum, Access::ComputeRead))),
            ("indirect", Bound::Image(pass.write(images.indirect, Access::ComputeWrite))),
            ("leaked", Bound::Image(pass.write(images.leaked, Access::ComputeReadWrite))),
        ];
        let out = pass.write(images.radiance, Access::ComputeWrite);
        bound.push(("radiance", Bound::Image(out)));
        pass.record(move |cmd| {
            let e = out.extent();
            cmd.dispatch(&self.pipeline, &bound, [e.width, e.height, 1])
        });
        Ok(())
    }
}
