//! Tonemap (`tonemap.vert` + `tonemap.frag`): the displayed layer, automatically exposed
//! from the frame's luminance statistics (or by a fixed exposure), through the filmic curve
//! into an 8-bit target: the window's swapchain image, or the image a PNG is saved from.

use ash::vk;
use bytemuck::{Pod, Zeroable};
use leakless_device::{gpu_struct, ColorTarget, Gpu, GpuStruct, GraphicsDesc, GraphicsPipeline};
use leakless_graph::{shader_bindings, Access, BufferHandle, Graph, ImageHandle, Stage};

use crate::error::Result;
use crate::passes::luminance::LuminanceStats;
use crate::passes::names;
use crate::shaders;

/// What the window (or the PNG) shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ViewLayer {
    /// Final radiance: direct + indirect.
    #[default]
    Final,
    Direct,
    Indirect,
    /// The indirect light the visibility test removed.
    Leaked,
    /// Heat map: photons the gather examined per pixel.
    Candidates,
    /// Heat map: visibility rays traced per pixel.
    VisibilityRays,
    /// Heat map: frames each pixel's temporal history holds (1 where nothing is reused).
    History,
}

impl ViewLayer {
    pub const ALL: [ViewLayer; 7] = [
        ViewLayer::Final,
        ViewLayer::Direct,
        ViewLayer::Indirect,
        ViewLayer::Leaked,
        ViewLayer::Candidates,
        ViewLayer::VisibilityRays,
        ViewLayer::History,
    ];

    pub fn name(self) -> &'static str {
        match self {
            ViewLayer::Final => "final",
            ViewLayer::Direct => "direct",
            ViewLayer::Indirect => "indirect",
            ViewLayer::Leaked => "leaked",
            ViewLayer::Candidates => "candidates per pixel",
            ViewLayer::VisibilityRays => "visibility rays per pixel",
            ViewLayer::History => "history length (frames reused)",
        }
    }

    /// The next layer (V cycles).
    pub fn next(self) -> ViewLayer {
        let i = Self::ALL.iter().position(|&l| l == self).expect("listed");
        Self::ALL[(i + 1) % Self::ALL.len()]
    }

    /// `DISPLAY_*` of display.glsl.
    pub fn mode(self) -> u32 {
        match self {
            ViewLayer::Candidates => 1,
            ViewLayer::VisibilityRays => 2,
            ViewLayer::History => 3,
            _ => 0,
        }
    }
}

gpu_struct! {
    /// The `TonemapParams` push constants of tonemap.frag.
    #[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
    pub struct TonemapParams {
        pub mode: u32,
        /// > 0: fixed exposure; 0: automatic.
        pub exposure: f32,
        /// 1: the target is UNORM and the shader sRGB-encodes; 0: the target's format does.
        pub encode_srgb: u32,
        pub pad0: u32,
        /// Layer pixels per target pixel: the target may be larger than the layers (nearest
        /// neighbour).
        pub source_scale: [f32; 2],
        pub pad1: u32,
        pub pad2: u32,
    }
}

shader_bindings! {
    pub struct TonemapBindings {
        displayed: read image,
        stats: read block(LuminanceStats::LAYOUT),
    }
    pub struct TonemapResources;
}

/// The tonemap for one target format.
pub struct TonemapPass {
    pipeline: GraphicsPipeline,
    format: vk::Format,
}

/// Whether writing `format` encodes sRGB in hardware.
fn is_srgb(format: vk::Format) -> bool {
    matches!(format, vk::Format::B8G8R8A8_SRGB | vk::Format::R8G8B8A8_SRGB | vk::Format::A8B8G8R8_SRGB_PACK32)
}

impl TonemapPass {
    pub fn new(gpu: &Gpu, format: vk::Format) -> Result<Self> {
        let desc = GraphicsDesc {
            vertex: &shaders::TONEMAP_VERT,
            fragment: &shaders::TONEMAP_FRAG,
            vertex_layout: None,
            colors: vec![ColorTarget { format }],
            depth: None,
            cull: vk::CullModeFlags::NONE,
            push: Some(TonemapParams::LAYOUT),
        };
        Ok(TonemapPass {
            pipeline: GraphicsPipeline::new(
                gpu,
                "tonemap",
                &desc,
                crate::frame_set::FRAME_SET,
                TonemapBindings::DECLS,
            )?,
            format,
        })
    }

    pub fn format(&self) -> vk::Format {
        self.format
    }

    /// Tonemaps `displayed` (shown as `layer`) into `target`, whose format must be this
    /// pass's and which may be larger (scaled up, nearest neighbour); `exposure` `None` is
    /// automatic, from `stats`.
    pub fn add<'r>(
        &'r self,
        graph: &mut Graph<'r>,
        layer: ViewLayer,
        exposure: Option<f32>,
        displayed: &ImageHandle,
        stats: &BufferHandle,
        target: &mut ImageHandle,
    ) {
        assert_eq!(target.format(), self.format, "tonemap target format");
        let (from, to) = (displayed.extent(), target.extent());
        let params = TonemapParams {
            mode: layer.mode(),
            exposure: exposure.unwrap_or(0.0),
            encode_srgb: !is_srgb(self.format) as u32,
            source_scale: [from.width as f32 / to.width as f32, from.height as f32 / to.height as f32],
            ..Default::default()
        };
        let mut pass = graph.pass(names::TONEMAP);
        let own = TonemapBindings::declare(&mut pass, Stage::Fragment, TonemapResources { displayed, stats });
        let out = pass.write(target, Access::ColorAttachmentWrite);
        pass.record(move |ctx| ctx.draw(&self.pipeline, &[&own], &params, &[(out, [0.0; 4])], None, None, 3));
    }
}
