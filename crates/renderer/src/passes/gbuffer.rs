//! G-buffer: rasterises the scene into world position, viewer-facing normal and albedo
//! (`gbuffer.vert` + `gbuffer.frag`).

use ash::vk;
use leakless_device::{ColorTarget, Gpu, GpuStruct, GraphicsDesc, GraphicsPipeline, ImageDesc};
use leakless_graph::{shader_bindings, Access, BufferHandle, Graph, ImageHandle, PassBuilder, Stage};

use crate::error::Result;
use crate::frame_set::FRAME_SET;
use crate::gpu_scene::SceneHandles;
use crate::gpu_types::Frame;
use crate::passes::names;
use crate::shaders;

pub const FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;
const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

shader_bindings! {
    /// The raster pass's own bindings; it also binds the scene.
    pub struct RasterBindings {
        frame: read uniform(Frame::LAYOUT),
    }
    pub struct RasterResources;
}

shader_bindings! {
    /// The G-buffer as every pass that reads it binds it (`GBUFFER_BINDINGS(n)` of
    /// gbuffer.glsl).
    pub struct GBufferBindings {
        gbuffer_position: read image,
        gbuffer_normal: read image,
        gbuffer_albedo: read image,
    }
    pub struct GBufferResources;
}

/// The view samples of a frame: one per pixel, `position.w = triangle + 1`, 0 where nothing
/// was hit. Images of the graph's pool, kept from frame to frame.
pub struct GBufferHandles {
    pub position: ImageHandle,
    pub normal: ImageHandle,
    pub albedo: ImageHandle,
    pub depth: ImageHandle,
}

impl GBufferHandles {
    /// Declares that a compute `pass` reads the G-buffer.
    pub fn declare(&self, pass: &mut PassBuilder<'_, '_>) -> GBufferBindings {
        let resources = GBufferResources {
            gbuffer_position: &self.position,
            gbuffer_normal: &self.normal,
            gbuffer_albedo: &self.albedo,
        };
        GBufferBindings::declare(pass, Stage::Compute, resources)
    }

    /// The G-buffer images of an `extent` frame (made anew when the size changes).
    pub fn new(graph: &mut Graph<'_>, extent: vk::Extent2D) -> Result<GBufferHandles> {
        let usage =
            vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::STORAGE | vk::ImageUsageFlags::TRANSFER_SRC;
        let mut color = |name| graph.image(&ImageDesc { name, extent, format: FORMAT, usage });
        Ok(GBufferHandles {
            position: color("gbuffer position")?,
            normal: color("gbuffer normal")?,
            albedo: color("gbuffer albedo")?,
            depth: graph.image(&ImageDesc {
                name: "gbuffer depth",
                extent,
                format: DEPTH_FORMAT,
                usage: vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
            })?,
        })
    }
}

pub struct GBufferPass {
    pipeline: GraphicsPipeline,
}

impl GBufferPass {
    pub fn new(gpu: &Gpu) -> Result<Self> {
        let desc = GraphicsDesc {
            vertex: &shaders::GBUFFER_VERT,
            fragment: &shaders::GBUFFER_FRAG,
            // The vertex stage reads the scene's buffers by gl_VertexIndex (gbuffer.vert).
            vertex_layout: None,
            colors: vec![ColorTarget { format: FORMAT }; 3],
            depth: Some(DEPTH_FORMAT),
            cull: vk::CullModeFlags::NONE,
            push: None,
        };
        let pipeline = GraphicsPipeline::new(gpu, "gbuffer", &desc, FRAME_SET, RasterBindings::DECLS)?;
        Ok(GBufferPass { pipeline })
    }

    pub fn add<'r>(
        &'r self,
        graph: &mut Graph<'r>,
        frame: &BufferHandle,
        scene: &SceneHandles,
        vertex_count: u32,
        out: &mut GBufferHandles,
    ) {
        let mut pass = graph.pass(names::GBUFFER);
        let own = RasterBindings::declare(&mut pass, Stage::Vertex, RasterResources { frame });
        // The fragment stage reads the frame too. Both stages read the surfaces, which the
        // frame set binds: the vertex stage their corners, the fragment stage the rest.
        pass.read(frame, Access::FragmentRead);
        scene.declare(&mut pass, Stage::Vertex);
        scene.declare(&mut pass, Stage::Fragment);
        let position = pass.write(&mut out.position, Access::ColorAttachmentWrite);
        let normal = pass.write(&mut out.normal, Access::ColorAttachmentWrite);
        let albedo = pass.write(&mut out.albedo, Access::ColorAttachmentWrite);
        let depth = pass.write(&mut out.depth, Access::DepthAttachmentWrite);
        pass.record(move |ctx| {
            let targets = [(position, [0.0; 4]), (normal, [0.0; 4]), (albedo, [0.0; 4])];
            ctx.draw(&self.pipeline, &[&own], &(), &targets, Some(depth), None, vertex_count)
        });
    }
}
