//! Temporal reuse: the indirect light of the frames before, reprojected to this one, rejected
//! where the surface differs, clamped to this frame's neighbourhood and blended with it; the
//! frame's spatially filtered estimate enters with the filter's bias divided out
//! (`temporal.comp`; docs/architecture.md §1, "Motion").

use ash::vk;
use bytemuck::{Pod, Zeroable};
use leakless_device::{gpu_struct, GpuStruct, ImageDesc};
use leakless_graph::{shader_bindings, BufferHandle, Graph, History, ImageHandle, PassName};

use crate::error::Result;
use crate::gpu_types::Frame;
use crate::passes::gbuffer::{self, GBufferBindings, GBufferHandles};
use crate::passes::lighting_level;
use crate::passes::names::group;
use crate::pipelines::{compute_pass, ComputePass, Threads};
use crate::shaders;

/// What the pass does with the history (`MODE_*` of temporal.comp).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TemporalMode {
    /// No history: the frame passes through and starts one.
    Restart = 0,
    /// Something moved: reproject, reject, clamp, blend.
    Motion = 1,
    /// Nothing moved: the history is carried and weighs into the accumulation's mean.
    Still = 2,
}

gpu_struct! {
    /// The `TemporalParams` push constants of temporal.comp.
    #[derive(Clone, Copy, Debug, Pod, Zeroable)]
    pub struct TemporalParams {
        /// The view-projection of the frame the history was written in.
        pub previous_view_proj: [[f32; 4]; 4],
        /// That frame's camera position (.xyz).
        pub previous_camera: [f32; 4],
        pub mode: u32,
        /// Frames a pixel's history holds at most (about half a second of frames).
        pub max_history: f32,
        /// Still: the photon batches in the accumulation's mean.
        pub still_batches: f32,
        /// Triangles from this one on belong to animated instances.
        pub first_moving_triangle: u32,
        /// 1: the animated instances moved since the history's frame (their vertices then are
        /// bound as `previous_positions`).
        pub instances_moved: u32,
        /// How far the history may leave the new frame's neighbourhood mean, as a fraction of it.
        pub clamp_relative: f32,
        /// 1: `filtered` holds the frame's spatially reused irradiance.
        pub spatial: u32,
        /// Frames the spatial filter's bias is measured over at most.
        pub bias_frames: f32,
        /// The gather kernel's radius in pixels, one metre from the camera.
        pub kernel_pixels: f32,
        /// The clamp's footprint's half width, in kernel radii ([`CLAMP_KERNELS`]).
        pub clamp_kernels: f32,
        /// 1: the history shown is scaled by `level_previous`'s factor (lighting_level.rs).
        pub level: u32,
        pub pad1: u32,

    }
}

/// How far a reprojected history may stray beyond the span of the new frame's (spatially
/// reused) pixel and neighbourhood mean, as a fraction (see temporal.comp). Measured with
/// `bench motion` on the door, the moving light and the Cornell box orbit (docs/results.md,
/// "Motion"): 0.5 let the light of the closing door lag (its frames 12% too bright), 0.1
/// averaged less on the still parts; 0.25 keeps both within a few percent.
pub const CLAMP_RELATIVE: f32 = 0.25;

/// The half width of the footprint whose mean the history is clamped to, in gather-kernel radii
/// at the pixel's distance (a footprint two kernels across, 7×7 taps; 19×19 pixels at least, 97
/// at most). A single frame's blotches are a kernel across: a narrower footprint falls inside
/// one and clamps the history to it. Only taps of the pixel's kind of surface count (static or
/// animated, facing its way), so the light of another wall or of what a doorway shows does not
/// widen the range. Chosen with `bench motion` (the atrium and the moving light, 128×72, the
/// last frame against 1024 samples), together with the spatial filter's reach: against a fixed
/// 19×19 footprint of every tap and the filter's three iterations everywhere, the atrium's
/// HDR-FLIP is 0.73× and its relMSE 0.37×, the moving light's unchanged; one radius keeps less
/// of that (HDR-FLIP 0.93×).
pub const CLAMP_KERNELS: f32 = 2.0;

shader_bindings! {
    pub struct TemporalBindings {
        frame: read uniform(Frame::LAYOUT),
        direct: read image,
        indirect: read image,
        radiance: read image,
        history_previous: read image,
        history_current: write image,
        surface_previous: read image,
        surface_current: write image,
        normal_previous: read image,
        normal_current: write image,
        reused_indirect: write image,
        reused_radiance: write image,
        filtered: read image,
        filtered_mean_previous: read image,
        filtered_mean_current: write image,
        own_mean_previous: read image,
        own_mean_current: write image,
        previous_positions: read array(f32::LAYOUT),
        level_previous: read image,
        level_partials: write words,
    }
    pub struct TemporalResources;
}

compute_pass! {
    pub static TEMPORAL in FRAME_PASSES: ComputePass<TemporalBindings, TemporalParams> =
        ComputePass::any(
            PassName::new("temporal reuse", group::REUSE),
            &shaders::TEMPORAL_COMP,
            &[GBufferBindings::DECLS],
        );
}

/// The pass's history pairs: demodulated irradiance (.a: frames held), the surface each pixel
/// saw (position with triangle + 1, normal), and the long means whose ratio is the spatial
/// filter's bias (the filtered irradiance with its frames in .a, the pixel's own).
pub struct TemporalHistories {
    pub irradiance: History,
    pub surface: History,
    pub normal: History,
    pub filtered_mean: History,
    pub own_mean: History,
    /// The image's lighting level (lighting_level.rs), 1×1.
    pub level: History,
}

/// The name of the history image the app's history-length view shows.
pub const IRRADIANCE_HISTORY: &str = "reuse irradiance";

impl TemporalHistories {
    /// Asks the graph for the pairs; the frame must then run [`add`], which writes them.
    pub fn new(graph: &mut Graph<'_>, extent: vk::Extent2D) -> Result<Self> {
        let usage = vk::ImageUsageFlags::STORAGE | vk::ImageUsageFlags::TRANSFER_SRC;
        let mut pair = |name| graph.history_image(&ImageDesc { name, extent, format: gbuffer::FORMAT, usage });
        Ok(TemporalHistories {
            irradiance: pair(IRRADIANCE_HISTORY)?,
            surface: pair("reuse surface")?,
            normal: pair("reuse normal")?,
            filtered_mean: pair("reuse filtered mean")?,
            own_mean: pair("reuse own mean")?,
            level: lighting_level::history(graph)?,
        })
    }

    /// Whether every pair holds the last frame's images.
    pub fn valid(&self) -> bool {
        self.irradiance.valid
            && self.surface.valid
            && self.normal.valid
            && self.filtered_mean.valid
            && self.own_mean.valid
            && self.level.valid
    }
}

/// This frame's shown layers and what the pass reads to reproject them.
pub struct TemporalInputs<'a> {
    pub frame: &'a BufferHandle,
    pub gbuffer: &'a GBufferHandles,
    /// The animated instances' vertices in the history's frame (any buffer when they did not
    /// move).
    pub previous_positions: &'a BufferHandle,
    pub direct: &'a ImageHandle,
    pub indirect: &'a ImageHandle,
    pub radiance: &'a ImageHandle,
    /// The frame's irradiance after spatial reuse (unread unless `params.spatial`).
    pub filtered: &'a ImageHandle,
    /// Where each workgroup writes its sums for the lighting level (`lighting_level::partials`).
    pub level_partials: &'a mut BufferHandle,
}

/// The reused layers, out.
pub struct Reused<'a> {
    pub indirect: &'a mut ImageHandle,
    pub radiance: &'a mut ImageHandle,
}

pub fn add<'r>(
    graph: &mut Graph<'r>,
    params: TemporalParams,
    inputs: TemporalInputs<'_>,
    histories: &mut TemporalHistories,
    out: Reused<'_>,
) {
    let extent = out.radiance.extent();
    let resources = TemporalResources {
        frame: inputs.frame,
        direct: inputs.direct,
        indirect: inputs.indirect,
        radiance: inputs.radiance,
        history_previous: &histories.irradiance.previous,
        history_current: &mut histories.irradiance.current,
        surface_previous: &histories.surface.previous,
        surface_current: &mut histories.surface.current,
        normal_previous: &histories.normal.previous,
        normal_current: &mut histories.normal.current,
        reused_indirect: out.indirect,
        reused_radiance: out.radiance,
        filtered: inputs.filtered,
        filtered_mean_previous: &histories.filtered_mean.previous,
        filtered_mean_current: &mut histories.filtered_mean.current,
        own_mean_previous: &histories.own_mean.previous,
        own_mean_current: &mut histories.own_mean.current,
        previous_positions: inputs.previous_positions,
        level_previous: &histories.level.previous,
        level_partials: inputs.level_partials,
    };
    let threads = Threads::Fixed([extent.width, extent.height, 1]);
    TEMPORAL.add_with(graph, resources, |pass| inputs.gbuffer.declare(pass), params, threads);
}
