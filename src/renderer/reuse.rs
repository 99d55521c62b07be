//! What temporal reuse remembers of the frame its history was written in: the camera, and
//! the animated instances' vertices, so that this frame can carry each pixel's surface point
//! back to where it was.

use glam::Mat4;
use leakless_scene::Vertex;

use crate::passes::temporal::{TemporalMode, TemporalParams, CLAMP_KERNELS, CLAMP_RELATIVE};

/// Frames a history holds by default: about half a second at 30 frames a second.
pub const DEFAULT_HISTORY_FRAMES: u32 = 16;
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
