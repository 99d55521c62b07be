//! Sample clearance (`sample_clearance.comp`): per view sample, the point its visibility
//! segments leave from and the radius of the ball around it that holds no geometry but the
//! sample's own plane. The gather proves a segment clear without tracing it where the segment
//! leaves this ball only inside the photon's (photon_clearance.rs; gather.comp).

use ash::vk;
use bytemuck::{Pod, Zeroable};
use leakless_device::{gpu_struct, ImageDesc};
use leakless_graph::{shader_bindings, Graph, ImageHandle, PassName};

use crate::error::Result;
use crate::passes::gbuffer::{self, GBufferBindings, GBufferHandles};
use crate::passes::names::group;
use crate::pipelines::{compute_pass, ComputePass, Threads};
use crate::shaders;

gpu_struct! {
    /// The `SampleClearanceParams` push constants of sample_clearance.comp.
    #[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
    pub struct SampleClearanceParams {
        /// The camera's position: segments leave from the sample moved toward it.
        pub eye: [f32; 3],
        /// No visibility segment of the gather is longer than this: the search stops there.
        pub max_radius: f32,
        /// Pixels a side of a tile, which shares one ball.
        pub tile: u32,
        pub pad0: u32,
        pub pad1: u32,
        pub pad2: u32,
    }
}

shader_bindings! {
    /// What sample_clearance.comp binds besides the G-buffer and the scene's BVH.
    pub struct SampleClearanceBindings {
        sample_clearance: write image,
        sample_clearance_plane: write image,
    }
    pub struct SampleClearanceResources;
}

/// The balls of an `extent` frame's tiles (of the graph's pool).
pub struct SampleClearanceHandles {
    /// The ball's centre (a sample's segments' start) in `.xyz`, its radius in `.w` (0 without
    /// a surface).
    pub balls: ImageHandle,
    /// The plane the ball leaves out: its normal in `.xyz`; a segment must stay above `.w`.
    pub planes: ImageHandle,
}

/// Pixels a side of the tiles that share a ball. A sample takes the ball of its own tile or
/// of one of the eight around it that reaches farthest from its segments' start: on the
/// basilica at 320×240 and 10k paths that leaves 106.9k of its 145.3k unproven segments with
/// 8-pixel tiles, 106.8k with a ball every pixel (which took 25 times as long to search as the
/// 8-pixel tiles' 7 ms), 109.7k with 16-pixel tiles.
pub const BALL_TILE: u32 = 8;

impl SampleClearanceHandles {
    pub fn new(graph: &mut Graph<'_>, extent: vk::Extent2D) -> Result<SampleClearanceHandles> {
        let tiles = vk::Extent2D { width: extent.width.div_ceil(BALL_TILE), height: extent.height.div_ceil(BALL_TILE) };
        let mut image = |name| {
            graph.image(&ImageDesc {
                name,
                extent: tiles,
                format: gbuffer::FORMAT,
                usage: vk::ImageUsageFlags::STORAGE | vk::ImageUsageFlags::TRANSFER_SRC,
            })
        };
        Ok(SampleClearanceHandles { balls: image("sample clearance")?, planes: image("sample clearance plane")? })
    }
}

/// The side of sample_clearance.comp's workgroups (of tiles).
const WORKGROUP: u32 = 8;

compute_pass! {
    /// The search walks the scene's BVH on every backend (it needs distances, not hits).
    pub static SAMPLE_CLEARANCE in FRAME_PASSES: ComputePass<SampleClearanceBindings, SampleClearanceParams> =
        ComputePass::any(
            PassName::new("sample clearance", group::SAMPLE_CLEARANCE),
            &shaders::SAMPLE_CLEARANCE_COMP,
            &[GBufferBindings::DECLS],
        ).workgroup([WORKGROUP, WORKGROUP, 1]);
}

/// Writes the ball of each tile's middle sample into `out`, searching up to `max_radius` (the
/// longest segment the gather may trace) from segments leaving toward `eye`.
pub fn add<'r>(
    graph: &mut Graph<'r>,
    eye: [f32; 3],
    max_radius: f32,
    gbuffer: &GBufferHandles,
    out: &mut SampleClearanceHandles,
) {
    let extent = out.balls.extent();
    let params = SampleClearanceParams { eye, max_radius, tile: BALL_TILE, ..Default::default() };
    let resources =
        SampleClearanceResources { sample_clearance: &mut out.balls, sample_clearance_plane: &mut out.planes };
    let threads = Threads::Fixed([extent.width, extent.height, 1]);
    SAMPLE_CLEARANCE.add_with(graph, resources, |pass| gbuffer.declare(pass), params, threads);
}
