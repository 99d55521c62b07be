//! The image's lighting level (`lighting_level.comp`): the ratio of a moving frame's new
//! estimates to the histories they are blended with, over the whole image, as a short running
//! mean; where it stands out from 1, the factor temporal reuse scales the history it shows next
//! frame by, so that a light changing too slowly for any neighbourhood to tell is followed
//! without lag (docs/architecture.md §1, "Motion").

use ash::vk;
use bytemuck::{Pod, Zeroable};
use leakless_device::{gpu_struct, BufferDesc, ImageDesc, MemoryLocation};
use leakless_graph::{shader_bindings, BufferHandle, Graph, History, PassName};

use crate::error::Result;
use crate::passes::gbuffer;
use crate::passes::names::group;
use crate::pipelines::{compute_pass, ComputePass};
use crate::shaders;

/// How many deviations of its own the ratio's running mean must stand out from 1 by before it
/// scales anything (in full at twice that). Chosen with `bench motion` (the door and the moving
/// light, 128×72, the last frame against 512 samples): 2 and 3 give the moving light's HDR-FLIP
/// 0.51× the baseline's (0.61× without the level) and the door's flicker 0.68× and 0.69× (0.66×
/// without); 2 follows a slow ramp further (the moving light's mean 0.983 of the truth against
/// 0.979). The Cornell box orbit, the atrium pan and the doorway walk, whose lights hold still,
/// are unchanged by either.
pub const LEVEL_SIGMAS: f32 = 2.0;

/// Frames the ratio's running mean holds at most, for a history of `history_frames`: half of
/// them. The lag the ratio measures builds over the history's frames, and a longer mean follows
/// it late; a shorter one is noisier (a quarter: the door's flicker 0.90× the baseline's, 0.69×
/// with half; a whole history's: the moving light's HDR-FLIP 0.52× against 0.51×).
pub fn level_frames(history_frames: f32) -> f32 {
    (0.5 * history_frames).max(1.0)
}

/// The side of temporal.comp's workgroups, each of which writes one partial sum.
const GROUP: u32 = 8;

gpu_struct! {
    /// The `LevelParams` push constants of lighting_level.comp.
    #[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
    pub struct LevelParams {
        /// temporal.comp's workgroups (partial sums).
        pub groups: u32,
        /// 1: a moving frame whose level history is valid; 0: the level starts anew at 1.
        pub measure: u32,
        pub most_frames: f32,
        pub sigmas: f32,
    }
}

shader_bindings! {
    pub struct LevelBindings {
        level_partials: read words,
        level_previous: read image,
        level_current: write image,
    }
    pub struct LevelResources;
}

compute_pass! {
    pub static LIGHTING_LEVEL in FRAME_PASSES: ComputePass<LevelBindings, LevelParams> =
        ComputePass::any(PassName::new("lighting level", group::REUSE), &shaders::LIGHTING_LEVEL_COMP, &[]);
}

/// The 1×1 history pair of the level: the factor, the ratio's mean and spread, its frames.
pub fn history(graph: &mut Graph<'_>) -> Result<History> {
    let usage = vk::ImageUsageFlags::STORAGE;
    let extent = vk::Extent2D { width: 1, height: 1 };
    Ok(graph.history_image(&ImageDesc { name: "reuse level", extent, format: gbuffer::FORMAT, usage })?)
}

/// The buffer temporal.comp writes its workgroups' sums into, for a frame of `extent`.
pub fn partials(graph: &mut Graph<'_>, extent: vk::Extent2D) -> Result<BufferHandle> {
    let size = 16 * groups(extent) as u64;
    let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
    Ok(graph.buffer(&BufferDesc { name: "reuse level partials", size, usage, location: MemoryLocation::GpuOnly })?)
}

fn groups(extent: vk::Extent2D) -> u32 {
    extent.width.div_ceil(GROUP) * extent.height.div_ceil(GROUP)
}

/// Sums `partials` (of a frame of `extent`) into this frame's level; `measure`: the frame moved
/// and the level's history is valid (otherwise the level starts anew at 1); `history_frames`:
/// the frames a pixel's history holds at most.
pub fn add<'r>(
    graph: &mut Graph<'r>,
    extent: vk::Extent2D,
    measure: bool,
    history_frames: f32,
    partials: &BufferHandle,
    level: &mut History,
) {
    let params = LevelParams {
        groups: groups(extent),
        measure: (measure && level.valid) as u32,
        most_frames: level_frames(history_frames),
        sigmas: LEVEL_SIGMAS,
    };
    let resources =
        LevelResources { level_partials: partials, level_previous: &level.previous, level_current: &mut level.current };
    LIGHTING_LEVEL.add(graph, resources, params, [256, 1, 1]);
}
