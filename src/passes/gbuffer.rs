//! G-buffer: rasterises the scene into world position, viewer-facing normal and albedo
//! (`gbuffer.vert` + `gbuffer.frag`).

use ash::vk;
use leakless_device::{
    BindingDecl, Bound, ColorTarget, Gpu, GraphicsDesc, GraphicsPipeline, Image, ImageDesc,
    VertexLayout,
};
use leakless_graph::{Access, BufferHandle, Graph, ImageHandle};
use leakless_scene::Vertex;

use crate::error::Result;
use crate::gpu_types::{FRAME_LAYOUT, MATERIAL_LAYOUT, U32_LAYOUT};
use crate::shaders;

pub const BINDINGS: &[BindingDecl] = &[
    BindingDecl::uniform("frame", FRAME_LAYOUT),
    BindingDecl::storage_array("materials", MATERIAL_LAYOUT),
    BindingDecl::storage_array("triangle_materials", U32_LAYOUT),
    BindingDecl::storage_array("texels", U32_LAYOUT),
];

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
        let usage = vk::ImageUsageFlags::COLOR_ATTACHMENT
            | vk::ImageUsageFlags::STORAGE
            | vk::ImageUsageFlags::TRANSFER_SRC;
        let color = |name| {
            Image::new(
                gpu,
                &ImageDesc {
                    name,
                    extent,
                    format: FORMAT,
                    usage,
                },
            )
        };
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

/// Scene buffers the G-buffer reads.
pub struct SceneInputs<'a> {
    pub vertices: &'a BufferHandle,
    pub vertex_count: u32,
    pub materials: &'a BufferHandle,
    pub triangle_materials: &'a BufferHandle,
    pub texels: &'a BufferHandle,
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
                    (
                        0,
                        vk::Format::R32G32B32_SFLOAT,
                        std::mem::offset_of!(Vertex, position) as u32,
                    ),
                    (
                        1,
                        vk::Format::R32G32B32_SFLOAT,
                        std::mem::offset_of!(Vertex, normal) as u32,
                    ),
                    (
                        2,
                        vk::Format::R32G32_SFLOAT,
                        std::mem::offset_of!(Vertex, uv) as u32,
                    ),
                ],
            },
            colors: vec![ColorTarget { format: FORMAT }; 3],
            depth: Some(DEPTH_FORMAT),
            cull: vk::CullModeFlags::NONE,
        };
        Ok(GBufferPass {
            pipeline: GraphicsPipeline::new(gpu, "gbuffer", &desc, BINDINGS)?,
        })
    }

    pub fn add<'r>(
        &'r self,
        graph: &mut Graph<'r>,
        frame: &BufferHandle,
        scene: SceneInputs<'_>,
        out: &mut GBufferHandles,
    ) {
        let mut pass = graph.pass("gbuffer");
        let frame = pass.read(frame, Access::VertexShaderRead);
        let vertices = pass.read(scene.vertices, Access::VertexBuffer);
        let materials = pass.read(scene.materials, Access::FragmentRead);
        let triangle_materials = pass.read(scene.triangle_materials, Access::FragmentRead);
        let texels = pass.read(scene.texels, Access::FragmentRead);
        let position = pass.write(&mut out.position, Access::ColorAttachmentWrite);
        let normal = pass.write(&mut out.normal, Access::ColorAttachmentWrite);
        let albedo = pass.write(&mut out.albedo, Access::ColorAttachmentWrite);
        let depth = pass.write(&mut out.depth, Access::DepthAttachmentWrite);
        let vertex_count = scene.vertex_count;
        pass.record(move |cmd| {
            cmd.draw(
                &self.pipeline,
                &[
                    ("frame", Bound::Buffer(frame)),
                    ("materials", Bound::Buffer(materials)),
                    ("triangle_materials", Bound::Buffer(triangle_materials)),
                    ("texels", Bound::Buffer(texels)),
                ],
                &[(position, [0.0; 4]), (normal, [0.0; 4]), (albedo, [0.0; 4])],
                Some(depth),
                vertices,
                vertex_count,
            )
        });
    }
}
