//! Direct light: Lambertian reflection of every punctual light at each view sample
//! (`direct.comp`).

use leakless_device::{BindingDecl, Bound, ComputePipeline, Gpu};
use leakless_graph::{Access, BufferHandle, Graph, ImageHandle};

use crate::error::Result;
use crate::gpu_types::{FRAME_LAYOUT, LIGHT_LAYOUT};
use crate::passes::gbuffer::GBufferHandles;
use crate::shaders;

pub const BINDINGS: &[BindingDecl] = &[
    BindingDecl::uniform("frame", FRAME_LAYOUT),
    BindingDecl::storage_array("lights", LIGHT_LAYOUT),
    BindingDecl::storage_image("gbuffer_position"),
    BindingDecl::storage_image("gbuffer_normal"),
    BindingDecl::storage_image("gbuffer_albedo"),
    BindingDecl::storage_image("direct"),
];

pub struct DirectPass {
    pipeline: ComputePipeline,
}

impl DirectPass {
    pub fn new(gpu: &Gpu) -> Result<Self> {
        Ok(DirectPass {
            pipeline: ComputePipeline::new(gpu, "direct", &shaders::DIRECT_COMP, None, BINDINGS)?,
        })
    }

    pub fn add<'r>(
        &'r self,
        graph: &mut Graph<'r>,
        frame: &BufferHandle,
        lights: &BufferHandle,
        gbuffer: &GBufferHandles,
        direct: &mut ImageHandle,
    ) {
        let mut pass = graph.pass("direct");
        let frame = pass.read(frame, Access::ComputeRead);
        let lights = pass.read(lights, Access::ComputeRead);
        let position = pass.read(&gbuffer.position, Access::ComputeRead);
        let normal = pass.read(&gbuffer.normal, Access::ComputeRead);
        let albedo = pass.read(&gbuffer.albedo, Access::ComputeRead);
        let out = pass.write(direct, Access::ComputeWrite);
        pass.record(move |cmd| {
            let e = out.extent();
            cmd.dispatch(
                &self.pipeline,
                &[
                    ("frame", Bound::Buffer(frame)),
                    ("lights", Bound::Buffer(lights)),
                    ("gbuffer_position", Bound::Image(position)),
                    ("gbuffer_normal", Bound::Image(normal)),
                    ("gbuffer_albedo", Bound::Image(albedo)),
                    ("direct", Bound::Image(out)),
                ],
                [e.width, e.height, 1],
            )
        });
    }
}
