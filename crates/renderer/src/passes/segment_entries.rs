//! Segment entries (`segment_entries.comp`): per tile of view samples, the BVH nodes where the
//! compute backend's traversals of its visibility segments start, and the region a segment
//! must lie in to start there. The steps from the root down to a tile's neighbourhood, which
//! every one of its segments took, are taken once a tile (gather.comp; trace_compute.glsl).

use ash::vk;
use bytemuck::{Pod, Zeroable};
use leakless_device::{gpu_struct, ImageDesc};
use leakless_graph::{shader_bindings, Graph, ImageHandle, PassName};

use crate::error::Result;
use crate::passes::gbuffer::{self, GBufferBindings, GBufferHandles};
use crate::passes::names::group;
use crate::passes::sample_clearance::BALL_TILE;
use crate::pipelines::{compute_pass, ComputePass, Threads};
use crate::shaders;

gpu_struct! {
    /// The `SegmentEntriesParams` push constants of segment_entries.comp.
    #[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
    pub struct SegmentEntriesParams {
        /// No visibility segment of the gather is longer than this.
        pub max_radius: f32,
        /// Pixels a side of a tile, which shares its entries.
        pub tile: u32,
        pub pad0: u32,
        pub pad1: u32,
    }
}

shader_bindings! {
    /// What segment_entries.comp binds besides the G-buffer and the scene's BVH.
    pub struct SegmentEntriesBindings {
        segment_region_lo: write image,
        segment_region_hi: write image,
        segment_entries: write image,
    }
    pub struct SegmentEntriesResources;
}

/// The entries of an `extent` frame's tiles (of the graph's pool), tiles of
/// [`BALL_TILE`] pixels as the sample clearance's, so that the gather finds both alike.
pub struct SegmentEntriesHandles {
    /// The region's low corner in `.xyz`, the count of entries in `.w`.
    pub region_lo: ImageHandle,
    /// Its high corner in `.xyz` (below the low one: no region).
    pub region_hi: ImageHandle,
    /// Up to four child references of the static part's BVH.
    pub entries: ImageHandle,
}

impl SegmentEntriesHandles {
    pub fn new(graph: &mut Graph<'_>, extent: vk::Extent2D) -> Result<SegmentEntriesHandles> {
        let tiles = vk::Extent2D { width: extent.width.div_ceil(BALL_TILE), height: extent.height.div_ceil(BALL_TILE) };
        let mut image = |name, format| {
            graph.image(&ImageDesc {
                name,
                extent: tiles,
                format,
                usage: vk::ImageUsageFlags::STORAGE | vk::ImageUsageFlags::TRANSFER_SRC,
            })
        };
        Ok(SegmentEntriesHandles {
            region_lo: image("segment region lo", gbuffer::FORMAT)?,
            region_hi: image("segment region hi", gbuffer::FORMAT)?,
            entries: image("segment entries", vk::Format::R32G32B32A32_UINT)?,
        })
    }
}

/// The side of segment_entries.comp's workgroups (of tiles).
const WORKGROUP: u32 = 8;

compute_pass! {
    /// Reads the BVH, traces nothing: the same module on every backend.
    pub static SEGMENT_ENTRIES in FRAME_PASSES: ComputePass<SegmentEntriesBindings, SegmentEntriesParams> =
        ComputePass::any(
            PassName::new("segment entries", group::SAMPLE_CLEARANCE),
            &shaders::SEGMENT_ENTRIES_COMP,
            &[GBufferBindings::DECLS],
        ).workgroup([WORKGROUP, WORKGROUP, 1]);
}

/// Writes each tile's region (its samples grown by `max_radius`, the longest segment the
/// gather traces) and the nodes under which lies every triangle that comes near it.
pub fn add<'r>(graph: &mut Graph<'r>, max_radius: f32, gbuffer: &GBufferHandles, out: &mut SegmentEntriesHandles) {
    let extent = out.entries.extent();
    let params = SegmentEntriesParams { max_radius, tile: BALL_TILE, ..Default::default() };
    let resources = SegmentEntriesResources {
        segment_region_lo: &mut out.region_lo,
        segment_region_hi: &mut out.region_hi,
        segment_entries: &mut out.entries,
    };
    let threads = Threads::Fixed([extent.width, extent.height, 1]);
    SEGMENT_ENTRIES.add_with(graph, resources, |pass| gbuffer.declare(pass), params, threads);
}
