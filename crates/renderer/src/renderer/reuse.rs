//! Temporal reuse's state and its stage of the frame: what it remembers of the frame its
//! history was written in (the camera, and the animated instances' vertices, so that this
//! frame can carry each pixel's surface point back to where it was), and the passes that
//! reproject, filter and blend (`ReuseState::add`).

use glam::Mat4;
use leakless_graph::{BufferHandle, Graph, ImageHandle};
use leakless_scene::Vertex;

use super::frame::layer;
use super::stages::{FrameStage, Layers};
use crate::error::Result;
use crate::passes::gbuffer::GBufferHandles;
use crate::passes::lighting_level;
use crate::passes::spatial::{self, SpatialImages};
use crate::passes::temporal::{
    self, Reused, TemporalHistories, TemporalInputs, TemporalMode, TemporalParams, CLAMP_KERNELS, CLAMP_RELATIVE,
};

/// The time a history holds (at the rate frames come, `Renderer::set_reuse_history_rate`): a
/// second. Half a second left the Cornell box's orbit flickering 0.71× the baseline's in excess
/// of its references, a second 0.30× (`bench motion`, 256×144), at 1–3% more error against
/// the references where the light changes (the lag of what the lighting change misses).
pub const HISTORY_SECONDS: f64 = 1.0;
/// Frames a history holds by default: a second at 30 frames a second.
pub const DEFAULT_HISTORY_FRAMES: u32 = 30;
/// The most frames a history may hold (two seconds at 64 frames a second): longer only lags.
pub const MAX_HISTORY_FRAMES: u32 = 128;
/// The spatial filter's bias is measured over this many histories' frames: it changes only as
/// the view does, slowly, and a longer mean knows it better.
pub const BIAS_HISTORIES: u32 = 4;

pub(super) struct ReuseState {
    /// The history's frame's view-projection and camera position.
    pub view_proj: Mat4,
    pub camera: glam::Vec3,
    /// The pose version whose instance vertices `vertices` hold.
    pub pose_version: u64,
    pub vertices: Vec<Vertex>,
    /// Frames a pixel's history holds at most.
    pub history_frames: u32,
    /// Whether moving frames are filtered spatially.
    pub spatial: bool,
}

impl ReuseState {
    pub fn new(pose_version: u64, vertices: &[Vertex]) -> Self {
        ReuseState {
            view_proj: Mat4::IDENTITY,
            camera: glam::Vec3::ZERO,
            pose_version,
            vertices: vertices.to_vec(),
            history_frames: DEFAULT_HISTORY_FRAMES,
            spatial: true,
        }
    }

    /// The pass's parameters for a frame of `mode`; `still_batches`: the photon batches in an
    /// accumulation's mean. `instances_moved`: the pose differs from the history's.
    /// `kernel_pixels`: the gather kernel's radius in pixels one metre from the camera.
    pub fn params(
        &self,
        mode: TemporalMode,
        still_batches: u32,
        first_moving_triangle: u32,
        instances_moved: bool,
        kernel_pixels: f32,
    ) -> TemporalParams {
        TemporalParams {
            previous_view_proj: self.view_proj.to_cols_array_2d(),
            previous_camera: self.camera.extend(1.0).to_array(),
            mode: mode as u32,
            max_history: self.history_frames as f32,
            still_batches: still_batches as f32,
            first_moving_triangle,
            instances_moved: instances_moved as u32,
            clamp_relative: CLAMP_RELATIVE,
            spatial: (mode == TemporalMode::Motion && self.spatial) as u32,
            bias_frames: (BIAS_HISTORIES * self.history_frames) as f32,
            kernel_pixels,
            clamp_kernels: CLAMP_KERNELS,
            level: (mode == TemporalMode::Motion) as u32,
            pad1: 0,
        }
    }

    /// Remembers the frame just written as the history's: its camera, and the pose's vertices
    /// when they changed.
    pub fn remember(&mut self, view_proj: Mat4, camera: glam::Vec3, pose_version: u64, vertices: &[Vertex]) {
        self.view_proj = view_proj;
        self.camera = camera;
        if pose_version != self.pose_version {
            self.pose_version = pose_version;
            self.vertices.clear();
            self.vertices.extend_from_slice(vertices);
        }
    }
}

/// What temporal reuse reads of the frame besides its layers.
pub(super) struct ReuseInputs<'a> {
    pub frame: &'a BufferHandle,
    pub gbuffer: &'a GBufferHandles,
    /// The scene's pose now (its version) and its first animated triangle.
    pub pose_version: u64,
    pub first_moving_triangle: u32,
    /// The gather kernel's radius in pixels one metre away: the filter's reach and the
    /// clamp's footprint follow it.
    pub kernel_pixels: f32,
}

impl ReuseState {
    /// Temporal reuse: the frames before, reprojected, with this frame's `layers` (or, while
    /// nothing moves, weighing into the accumulation's mean); a moving frame's own estimate
    /// filtered spatially first. Gives the layers with the reused indirect light and radiance,
    /// the history the history view shows, and the mode it ran in.
    pub(super) fn add<'r>(
        &self,
        g: &mut Graph<'r>,
        s: &FrameStage<'_>,
        input: ReuseInputs<'_>,
        layers: Layers,
    ) -> Result<(Layers, ImageHandle, TemporalMode)> {
        let extent = s.extent;
        let mut histories = TemporalHistories::new(g, extent)?;
        let mode = match (histories.valid(), s.plan.progressive && s.plan.index > 0) {
            (false, _) => TemporalMode::Restart,
            (true, true) => TemporalMode::Still,
            (true, false) => TemporalMode::Motion,
        };
        let instances_moved = mode == TemporalMode::Motion && self.pose_version != input.pose_version;
        let previous: Vec<[f32; 3]> = match instances_moved {
            true => self.vertices.iter().map(|v| v.position).collect(),
            false => vec![[0.0; 3]],
        };
        let storage = ash::vk::BufferUsageFlags::STORAGE_BUFFER;
        let previous_positions = g.upload("previous instance positions", storage, bytemuck::cast_slice(&previous))?;
        let kernel_pixels = input.kernel_pixels;
        let params = self.params(mode, s.plan.batches, input.first_moving_triangle, instances_moved, kernel_pixels);
        // Spatial reuse of a moving frame's own estimate, before the history weighs in.
        let mut spatial = SpatialImages::new(g, extent)?;
        if params.spatial != 0 {
            spatial::add(g, input.frame, input.gbuffer, &layers.indirect, &mut spatial, kernel_pixels);
        }
        let mut level_partials = lighting_level::partials(g, extent)?;
        let mut reused_indirect = layer(g, extent, "reused indirect")?;
        let mut reused_radiance = layer(g, extent, "reused radiance")?;
        let inputs = TemporalInputs {
            frame: input.frame,
            gbuffer: input.gbuffer,
            previous_positions: &previous_positions,
            direct: &layers.direct,
            indirect: &layers.indirect,
            radiance: &layers.radiance,
            filtered: &spatial.result,
            level_partials: &mut level_partials,
        };
        let out = Reused { indirect: &mut reused_indirect, radiance: &mut reused_radiance };
        temporal::add(g, params, inputs, &mut histories, out);
        let motion = mode == TemporalMode::Motion;
        lighting_level::add(g, extent, motion, params.max_history, &level_partials, &mut histories.level);
        let layers = Layers { indirect: reused_indirect, radiance: reused_radiance, ..layers };
        Ok((layers, histories.irradiance.current, mode))
    }
}
