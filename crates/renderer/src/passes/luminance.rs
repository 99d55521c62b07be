//! Luminance statistics of a frame (`luminance.comp`, then `luminance_total.comp`): the
//! log-average of the displayed layer, which sets the automatic exposure of the tonemap, and
//! the summed luminance of the indirect and leaked layers, which gives the leaked energy
//! fraction without reading an image back.

use ash::vk;
use bytemuck::{Pod, Zeroable};
use leakless_device::{gpu_struct, BufferDesc, GpuStruct, MemoryLocation};
use leakless_graph::{shader_bindings, BufferHandle, Graph, ImageHandle, PassName};

use crate::error::Result;
use crate::passes::names::group;
use crate::pipelines::{compute_pass, ComputePass};
use crate::shaders;

const TILE: u32 = 16;

gpu_struct! {
    /// The `LuminanceParams` push constants of luminance.comp.
    #[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
    pub struct LuminanceParams {
        /// What the displayed image's pixels mean (`DISPLAY_*` of display.glsl).
        pub mode: u32,
        pub width: u32,
        pub height: u32,
        pub tiles_x: u32,
    }
}

gpu_struct! {
    /// The `TotalParams` push constants of luminance_total.comp.
    #[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
    pub struct TotalParams {
        pub tiles: u32,
        pub pad0: u32,
        pub pad1: u32,
        pub pad2: u32,
    }
}

gpu_struct! {
    /// The `LuminanceStats` block: what the frame's luminance sums to.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct LuminanceStats {
        /// Σ ln(value) over the displayed pixels whose value exceeds 1e-6.
        pub log_sum: f32,
        /// How many pixels those are.
        pub lit_pixels: f32,
        /// Σ luminance of the indirect layer.
        pub indirect_sum: f32,
        /// Σ luminance of the leaked layer.
        pub leaked_sum: f32,
    }
}

impl LuminanceStats {
    /// The automatic exposure (what the tonemap computes): log-average to middle grey.
    pub fn auto_exposure(&self) -> f32 {
        if self.lit_pixels > 0.0 {
            0.18 / (self.log_sum / self.lit_pixels).exp()
        } else {
            1.0
        }
    }

    /// Leaked / (leaked + kept) indirect luminance over the image.
    pub fn leaked_fraction(&self) -> f64 {
        let (lost, kept) = (self.leaked_sum as f64, self.indirect_sum as f64);
        if lost + kept > 0.0 {
            lost / (lost + kept)
        } else {
            0.0
        }
    }
}

shader_bindings! {
    pub struct TileBindings {
        displayed: read image,
        indirect: read image,
        leaked: read image,
        partials: write words,
    }
    pub struct TileResources;
}

shader_bindings! {
    pub struct TotalBindings {
        partials: read words,
        stats: write block(LuminanceStats::LAYOUT),
    }
    pub struct TotalResources;
}

/// The images the statistics read.
pub struct LuminanceInputs<'a> {
    /// What the tonemap will show, and what its pixels mean.
    pub displayed: &'a ImageHandle,
    pub mode: u32,
    pub indirect: &'a ImageHandle,
    pub leaked: &'a ImageHandle,
}

compute_pass! {
    pub static LUMINANCE_TILES in FRAME_PASSES: ComputePass<TileBindings, LuminanceParams> =
        ComputePass::any(PassName::new("luminance tiles", group::LUMINANCE), &shaders::LUMINANCE_COMP, &[]);
}

compute_pass! {
    pub static LUMINANCE_TOTAL in FRAME_PASSES: ComputePass<TotalBindings, TotalParams> =
        ComputePass::any(PassName::new("luminance total", group::LUMINANCE), &shaders::LUMINANCE_TOTAL_COMP, &[]);
}

/// Adds both stages; returns the [`LuminanceStats`] buffer (of the graph's pool).
pub fn add<'r>(graph: &mut Graph<'r>, input: LuminanceInputs<'_>) -> Result<BufferHandle> {
    let extent = input.displayed.extent();
    let tiles_x = extent.width.div_ceil(TILE);
    let tiles = tiles_x * extent.height.div_ceil(TILE);
    let storage = vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC;
    let mut buffer =
        |name, size| graph.buffer(&BufferDesc { name, size, usage: storage, location: MemoryLocation::GpuOnly });
    let mut partials = buffer("luminance partials", 16 * tiles as u64)?;
    let mut stats = buffer("luminance stats", std::mem::size_of::<LuminanceStats>() as u64)?;

    let params = LuminanceParams { mode: input.mode, width: extent.width, height: extent.height, tiles_x };
    let resources = TileResources {
        displayed: input.displayed,
        indirect: input.indirect,
        leaked: input.leaked,
        partials: &mut partials,
    };
    LUMINANCE_TILES.add(graph, resources, params, [extent.width, extent.height, 1]);

    let params = TotalParams { tiles, ..Default::default() };
    LUMINANCE_TOTAL.add(graph, TotalResources { partials: &partials, stats: &mut stats }, params, [256, 1, 1]);
    Ok(stats)
}
