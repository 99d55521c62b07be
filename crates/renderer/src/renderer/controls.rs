//! What steers the renderer between frames: its settings, the tuning, and the app's and the
//! CLI's switches (accumulation, pause, temporal reuse). A change that alters the image
//! restarts accumulation; one that alters the estimate forgets temporal reuse's history too.

use leakless_graph::Timing;

use super::{resolve, reuse, Renderer};
use crate::error::Result;
use crate::passes::frame_passes;
use crate::passes::tonemap::ViewLayer;
use crate::pipelines::Pipelines;
use crate::settings::{Method, RenderSettings};
use crate::trace::BackendChoice;
use crate::tuning::DeviceTuning;

impl Renderer {
    /// Per-pass timestamps in one submission (default), or one timed submission per pass.
    pub fn set_timing(&mut self, timing: Timing) {
        self.runner.set_timing(timing);
    }

    /// Restarts accumulation: the next frame starts a new image.
    pub(super) fn restart(&mut self) {
        self.accumulation.restart();
    }

    /// Changes any settings at once; validated first, and a change that needs a new backend
    /// makes its structures (the old backend's stay, for switching back).
    pub fn set_settings(&mut self, settings: RenderSettings) -> Result<()> {
        settings.validate()?;
        let backend = resolve(&self.gpu, settings.backend)?;
        crate::limits::check(&settings, &self.scene, backend.backend, &self.gpu.report().limits)?;
        // Everything that can fail before anything changes: the new tuning's pipelines are
        // made aside, and replace the old ones last.
        let retuned = if settings.tuning != self.settings.tuning {
            let tuning = DeviceTuning::choose(self.gpu.report(), settings.tuning);
            check_tuning(&settings, &tuning, self.gpu.report())?;
            Some(Pipelines::new(&self.gpu, &frame_passes(), backend.backend, &tuning)?)
        } else {
            check_tuning(&settings, self.tuning(), self.gpu.report())?;
            None
        };
        self.prepare_backend(backend.backend)?;
        if let Some(pipelines) = retuned {
            self.gpu.wait_idle()?; // the pipelines of frames in flight
            self.pipelines = pipelines;
        }
        let capacity_inputs =
            |s: &RenderSettings| (s.splat.paths, s.max_bounces, s.width, s.height, s.splat.list_capacity);
        let regrow = capacity_inputs(&settings) != capacity_inputs(&self.settings);
        if (settings.width, settings.height) != (self.settings.width, self.settings.height) {
            let pixels = |s: &RenderSettings| s.width as f64 * s.height as f64;
            self.resize_budget(pixels(&settings) / pixels(&self.settings));
        }
        if settings != self.settings {
            self.restart();
            // The frames before are another estimate: temporal reuse starts over.
            self.runner.invalidate_histories();
        }
        self.settings = settings;
        self.backend = backend;
        if regrow {
            self.list_capacity = self.default_list_capacity();
        }
        Ok(())
    }

    /// Replaces the tuning with one of the caller's, on the same device (the GPU report's
    /// sweeps: a driver may run out of something if every variant opened a device of its own).
    pub fn set_tuning(&mut self, tuning: DeviceTuning) -> Result<()> {
        check_tuning(&self.settings, &tuning, self.gpu.report())?;
        let pipelines = Pipelines::new(&self.gpu, &frame_passes(), self.backend.backend, &tuning)?;
        self.gpu.wait_idle()?; // the pipelines of frames in flight
        self.pipelines = pipelines;
        self.restart();
        self.runner.invalidate_histories();
        Ok(())
    }

    /// Changes one setting through a copy of the settings ([`Renderer::set_settings`]).
    pub fn update(&mut self, change: impl FnOnce(&mut RenderSettings)) -> Result<()> {
        let mut settings = self.settings.clone();
        change(&mut settings);
        self.set_settings(settings)
    }

    pub fn set_method(&mut self, method: Method) -> Result<()> {
        self.update(|s| s.method = method)
    }

    pub fn set_backend(&mut self, backend: BackendChoice) -> Result<()> {
        self.update(|s| s.backend = backend)
    }

    pub fn set_size(&mut self, width: u32, height: u32) -> Result<()> {
        self.update(|s| (s.width, s.height) = (width, height))
    }

    /// What the tonemap shows (window, PNG); does not restart accumulation.
    pub fn set_view_layer(&mut self, view: ViewLayer) {
        self.view = view;
    }

    /// A fixed exposure, or `None` for the automatic one.
    pub fn set_exposure(&mut self, exposure: Option<f32>) {
        self.exposure = exposure;
    }

    /// Whether every photon frame takes the next seed (fresh photons: the app, accumulation)
    /// or keeps `settings.seed` (a fixed frame: the CLI, tests).
    pub fn set_advance_seed(&mut self, advance: bool) {
        self.advance_seed = advance;
    }

    /// Whether frames accumulate while nothing changes, without end (the app while the view is
    /// still): photon frames, and reference frames of `spp` samples per batch, each at its own
    /// pixel jitter. A render accumulates `settings.frames` either way.
    pub fn set_progressive(&mut self, progressive: bool) {
        if progressive != self.accumulation.progressive {
            self.accumulation.progressive = progressive;
            self.restart();
        }
    }

    /// Frames a pixel's temporal history holds at most.
    pub fn set_reuse_history_frames(&mut self, frames: u32) {
        self.reuse.history_frames = frames.clamp(1, reuse::MAX_HISTORY_FRAMES);
    }

    /// A pixel's temporal history holds about `HISTORY_SECONDS` of frames at `frames_per_second`
    /// (two at least: the app sets it from the rate its frames come at, a sequence from its own).
    pub fn set_reuse_history_rate(&mut self, frames_per_second: f64) {
        let frames = (reuse::HISTORY_SECONDS * frames_per_second).round();
        self.set_reuse_history_frames(if frames.is_finite() { (frames as u32).max(2) } else { 2 });
    }

    /// Whether moving frames filter their own estimate spatially before the history weighs in
    /// (on by default; off only to measure what the filter does).
    pub fn set_spatial_reuse(&mut self, on: bool) {
        self.reuse.spatial = on;
    }

    /// Forgets the frames before: the next frame starts temporal reuse anew (a render from
    /// scratch).
    pub fn forget_history(&mut self) {
        self.runner.invalidate_histories();
    }

    /// Whether the image holds as much as one accumulation may: `MAX_FRAMES` frames, or a
    /// single reference's `MAX_SPP` samples. Further frames show it again, as when paused, so
    /// what it holds stays within what `render` accepts (the app's captures record it as a
    /// command). At 60 frames a second a still view gets there in 18 minutes.
    pub fn accumulation_full(&self) -> bool {
        accumulation_full(self.settings.method, self.accumulating(), self.accumulation.accumulated)
    }

    /// Whether the next frame adds to an accumulation of frames, each at its own pixel jitter
    /// (else it is the image): while progressive or when `frames` > 1. A reference frame is
    /// then a whole image of `spp` samples per batch; otherwise a reference's frames add
    /// samples to one image at the pixel centres.
    pub fn accumulating(&self) -> bool {
        self.accumulation.progressive || self.settings.frames > 1
    }

    /// While paused, frames show the last image again without rendering anything new.
    pub fn set_paused(&mut self, paused: bool) {
        self.accumulation.paused = paused;
    }

    pub fn paused(&self) -> bool {
        self.accumulation.paused
    }

    /// Reference samples each frame adds (the app: 1, so frames stay short).
    pub fn set_samples_per_frame(&mut self, samples: u32) {
        self.accumulation.samples_per_frame = samples.max(1);
    }
}

fn accumulation_full(method: Method, accumulating: bool, accumulated: u32) -> bool {
    match (accumulating, method) {
        (true, _) => accumulated >= crate::settings::MAX_FRAMES,
        (false, Method::Reference) => accumulated >= crate::settings::MAX_SPP,
        // A single photon frame is drawn anew every time.
        (false, _) => false,
    }
}

/// `tuning` is valid on the device, and its gather workgroup fits `settings`' view samples in
/// the device's workgroup count (`limits::check` counted them in 64-thread groups).
pub(super) fn check_tuning(
    settings: &RenderSettings,
    tuning: &DeviceTuning,
    report: &leakless_device::DeviceReport,
) -> Result<()> {
    tuning.validate(report)?;
    let groups = (settings.width as u64 * settings.height as u64).div_ceil(tuning.gather_workgroup as u64);
    let most = report.limits.max_compute_work_group_count[0] as u64;
    if settings.method.splats() && groups > most {
        return Err(crate::RenderError::Settings(format!(
            "--size {}x{}: the gather's {groups} workgroups of {} exceed the device's maxComputeWorkGroupCount ({most})",
            settings.width, settings.height, tuning.gather_workgroup
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::settings::{MAX_FRAMES, MAX_SPP};

    #[test]
    fn an_accumulation_stops_at_what_render_accepts() {
        assert!(!accumulation_full(Method::LeakLess, true, MAX_FRAMES - 1));
        assert!(accumulation_full(Method::LeakLess, true, MAX_FRAMES));
        assert!(accumulation_full(Method::Reference, true, MAX_FRAMES));
        // A reference that does not accumulate frames counts samples.
        assert!(!accumulation_full(Method::Reference, false, MAX_FRAMES));
        assert!(accumulation_full(Method::Reference, false, MAX_SPP));
        assert!(!accumulation_full(Method::Splat, false, u32::MAX));
    }
}
