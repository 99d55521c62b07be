//! G-buffer: rasterises the scene into world position, viewer-facing normal and albedo
//! (`gbuffer.vert` + `gbuffer.frag`).

use ash::vk;
use leakless_device::{
    BindingDecl, Bound, ColorTarget, Gpu, GraphicsDesc, GraphicsPipeline, Image, ImageDesc, VertexLayout,
};
use leakless_graph::{Access, BufferHandle, Graph, ImageHandle};
use leakless_scene::Vertex;

use crate::error::Result;
use crate::gpu_scene::{SceneHandles, SCENE_BINDINGS};
use crate::gpu_types::FRAME_LAYOUT;
use crate::shaders;

/// The pass's own bindings; it also binds the scene (`SCENE_BINDINGS`).
pub const BINDINGS: &[BindingDecl] = &[BindingDecl::uniform("frame", FRAME_LAYOUT)];

/// Every binding of the pass.
pub fn bindings() -> Vec<BindingDecl> {
    [BINDINGS, SCENE_BINDINGS].concat()
}

pub const FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;
const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// The view samples of a frame: one per pixel, `position.w = 0` where nothing was hit.
pub struct GBuffer {
    pub position: Image,
    pub normal: Image,
    pub albedo: Image,
    pub depth: Image,
}

impl GBuffer {
    pub fn new(gpu: &Gpu, extent: vk::Extent2D) -> Result<GBuffer> {
        let usage =
            vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::STORAGE | vk::ImageUsageFlags::TRANSFER_SRC;
        let color = |name| Image::new(gpu, &ImageDesc { name, extent, format: FORMAT, usage });
        Ok(GBuffer {
            position: color("gbuffer position")?,
            normal: color("gbuffer normal")?,
            albedo: color("gbuffer albedo")?,
            depth: Image::new(
                gpu,
                &ImageDesc {
                    name: "gbuffer depth",
                    extent,
                    format: DEPTH_FORMAT,
                    usage: vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
                },
            )?,
        })
    }

    pub fn import<'r>(&'r self, graph: &mut Graph<'r>) -> GBufferHandles {
        GBufferHandles {
            position: graph.import_image(&self.position),
            normal: graph.import_image(&self.normal),
            albedo: graph.import_image(&self.albedo),
            depth: graph.import_image(&self.depth),
        }
    }
}

pub struct GBufferHandles {
    pub position: ImageHandle,
    pub normal: ImageHandle,
    pub albedo: ImageHandle,
    pub depth: ImageHandle,
}

pub struct GBufferPass {
    pipeline: GraphicsPipeline,
}

impl GBufferPass {
    pub fn new(gpu: &Gpu) -> Result<Self> {
        let desc = GraphicsDesc {
            vertex: &shaders::GBUFFER_VERT,
            fragment: &shaders::GBUFFER_FRAG,
            vertex_layout: VertexLayout {
                stride: std::mem::size_of::<Vertex>() as u32,
                attributes: vec![
                    (0, vk::Format::R32G32B32_SFLOAT, std::mem::offset_of!(Vertex, position) as u32),
                    (1, vk::Format::R32G32B32_SFLOAT, std::mem::offset_of!(Vertex, normal) as u32),
                    (2, vk::Format::R32G32_SFLOAT, std::mem::offset_of!(Vertex, uv) as u32),
                ],
            },
            colors: vec![ColorTarget { format: FORMAT }; 3],
            depth: Some(DEPTH_FORMAT),
            cull: vk::CullModeFlags::NONE,
        };
        Ok(GBufferPass { pipeline: GraphicsPipeline::new(gpu, "gbuffer", &desc, &bindings())? })
    }

    pub fn add<'r>(
        &'r self,
        graph: &mut Graph<'r>,
        frame: &BufferHandle,
        scene: &SceneHandles,
        vertex_count: u32,
        out: &mut GBufferHandles,
    ) {
        let mut pass = graph.pass("gbuffer");
        let mut bound = vec![("frame", Bound::Buffer(pass.read(frame, Access::VertexShaderRead)))];
        pass.read(frame, Access::FragmentRead);
        let vertices = pass.read(&scene.vertices, Access::VertexBuffer);
        bound.extend(scene.declare(&mut pass, Access::FragmentRead));
        let position = pass.write(&mut out.position, Access::ColorAttachmentWrite);
        let normal = pass.write(&mut out.normal, Access::ColorAttachmentWrite);
        let albedo = pass.write(&mut out.albedo, Access::ColorAttachmentWrite);
        let depth = pass.write(&mut out.depth, Access::DepthAttachmentWrite);
        pass.record(move |cmd| {
            let targets = [(position, [0.0; 4]), (normal, [0.0; 4]), (albedo, [0.0; 4])];
            cmd.draw(&self.pipeline, &bound, &targets, Some(depth), vertices, vertex_count)
        });
    }
}
