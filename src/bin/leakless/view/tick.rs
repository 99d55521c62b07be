//! One iteration of the app's loop: the script's events, the camera, the overlay's UI, then
//! a frame acquired, rendered and presented. And what each key does.

use std::time::{Duration, Instant};

use ash::vk;
use leakless::{BackendChoice, DisplayTarget, Method, Scene};
use leakless_device::{PresentOutcome, SubmitSync, Swapchain};
use leakless_graph::Timing;
use winit::keyboard::KeyCode;

use super::camera::Motion;
use super::keys::{self, Action};
use super::panel::{self, PanelInfo, Sliders};
use super::refusal;
use super::script::{Event, Script};
use super::summary::Summary;
use super::{capture, Running, ViewArgs};

/// The time step of scripted runs: the same motion whatever the machine's speed.
const SCRIPT_DT: f32 = 1.0 / 30.0;
/// A still view's frames grow only while they stay within this (fit_batches): 10 frames a
/// second keeps keys and the mouse answered at once.
const STILL_FRAME_BUDGET_MS: f64 = 100.0;
/// Frames before one is taken to measure the time of a batch.
const WARM_UP_FRAMES: u64 = 4;

/// Whether the host interval that ended at the start of tick `tick - 1` (the time of tick
/// `tick - 2`, which `frame_ms` holds when tick `tick` fits the batches) is a frame like the
/// others. A profiled tick (`tick % profile_every == 1`) submits each pass alone and waits,
/// so it is slower; the one after it finds the frames before already done and waits for
/// none, so it is faster. Neither measures a batch.
fn interval_is_typical(tick: u64, profile_every: u64) -> bool {
    let measured = tick.wrapping_sub(2);
    profile_every == 0 || !matches!(measured % profile_every, 1 | 2)
}

impl Running {
    pub(super) fn resize(&mut self, width: u32, height: u32) {
        if width == 0 || height == 0 {
            self.minimized = true;
        } else {
            self.minimized = false;
            self.size = (width, height);
            self.recreate = true;
        }
    }

    /// One press of `code`. A change of settings the device cannot render or the settings
    /// refuse is not made, and the panel says why (`refusal`).
    pub(super) fn key(&mut self, code: KeyCode, scene: &Scene) -> anyhow::Result<()> {
        let Some(action) = keys::action(code) else { return Ok(()) };
        let r = &mut self.renderer;
        let change = match action {
            Action::Method(m) => r.set_method(m),
            Action::CycleLayer => {
                r.set_view_layer(r.view_layer().next());
                Ok(())
            }
            Action::RadiusDown | Action::RadiusUp => {
                let radius = r.settings().splat.radius.unwrap_or(0.05 * scene.bounds().bounding_radius());
                let radius = if action == Action::RadiusUp { radius * 1.25 } else { radius / 1.25 };
                r.update(|s| s.splat.radius = Some(radius))
            }
            Action::PathsDown => r.update(|s| s.splat.paths = (s.splat.paths / 2).max(1)),
            Action::PathsUp => {
                let paths = r.settings().splat.paths.saturating_mul(2);
                r.update(|s| s.splat.paths = paths)
            }
            Action::CapDown | Action::CapUp => {
                let cap = r.settings().splat.cap.unwrap_or(leakless::settings::DEFAULT_CAP);
                let cap = if action == Action::CapUp { cap + 5 } else { cap.saturating_sub(5).max(1) };
                r.update(|s| s.splat.cap = Some(cap))
            }
            Action::ToggleTrivialAccept => r.update(|s| s.splat.trivial_accept = !s.splat.trivial_accept),
            Action::SwitchBackend => {
                if r.gpu().capabilities().ray_query {
                    let next = match r.backend() {
                        leakless::Backend::RayQuery => BackendChoice::Compute,
                        leakless::Backend::Compute => BackendChoice::RayQuery,
                    };
                    r.set_backend(next)
                } else {
                    // What the device lacks, said as a limit is.
                    Err(leakless::RenderError::Limit("B: this device has no ray queries".into()))
                }
            }
            Action::MoveLight(d) => {
                let step = 0.02 * scene.bounds().bounding_radius();
                let mut light = r.lights()[0].clone();
                light.position += glam::Vec3::new(d[0] as f32, d[1] as f32, d[2] as f32) * step;
                r.set_light(0, light)?;
                self.light_moved = true;
                Ok(())
            }
            Action::FreezeSeed => {
                self.seed_frozen = !self.seed_frozen;
                r.set_advance_seed(!self.seed_frozen);
                r.set_progressive(!self.seed_frozen);
                Ok(())
            }
            Action::PlayAnimation => {
                self.playing = !self.playing;
                Ok(())
            }
            Action::Pause => {
                r.set_paused(!r.paused());
                Ok(())
            }
            Action::Capture => {
                let path = capture::next_path(&scene.name)?;
                capture::capture(self, scene, &path)?;
                Ok(())
            }
            Action::ResetCamera => {
                self.camera.reset();
                Ok(())
            }
            Action::Help => {
                self.show_help = !self.show_help;
                Ok(())
            }
            Action::ToggleOverlay => {
                self.show_overlay = !self.show_overlay;
                Ok(())
            }
        };
        self.settle(change)
    }

    /// Keeps the reason a change was refused for the panel (and says it once on stderr); a
    /// change made clears it.
    fn settle(&mut self, change: leakless::Result<()>) -> anyhow::Result<()> {
        let why = refusal::refused(change)?;
        if why.is_some() && why != self.refusal {
            eprintln!("not applied: {}", why.as_deref().unwrap_or_default());
        }
        self.refusal = why;
        Ok(())
    }

    /// One loop iteration.
    pub(super) fn tick(
        &mut self,
        scene: &Scene,
        script: Option<&mut Script>,
        summary: &mut Summary,
        args: &ViewArgs,
    ) -> anyhow::Result<()> {
        let scripted = script.is_some();
        if let Some(script) = script {
            for event in script.take(self.frame) {
                match event {
                    Event::Key(code) => {
                        if keys::motion(code).is_some() {
                            self.tapped.push(code);
                        } else {
                            self.key(code, scene)?;
                        }
                    }
                    Event::Drag(dx, dy) => self.camera.turn(dx, dy),
                    Event::Resize(w, h) => {
                        if w > 0 && h > 0 {
                            let _ = self.window.request_inner_size(winit::dpi::PhysicalSize::new(w, h));
                        }
                        // Handled now as the window's own event would be, so a script runs
                        // the same whether or not the window system honours the request.
                        self.resize(w, h);
                    }
                    Event::Capture(path) => capture::capture(self, scene, &path)?,
                    Event::Quit => self.quit = true,
                }
            }
        }
        self.frame += 1;
        if self.quit || args.exit_after.is_some_and(|n| summary.frames() >= n) {
            self.quit = true;
            return Ok(());
        }

        let now = Instant::now();
        let dt = match (scripted, self.last_shown) {
            (true, _) | (false, None) => SCRIPT_DT,
            (false, Some(last)) => (now - last).as_secs_f32().min(0.1),
        };
        let mut motion = Motion::default();
        for code in self.held.iter().chain(&self.tapped) {
            if let Some([x, y, z]) = keys::motion(*code) {
                motion.right += x;
                motion.up += y;
                motion.forward += z;
            }
        }
        self.tapped.clear();
        if self.playing && scene.is_animated() && !self.renderer.paused() {
            // The animation loops, holding its last pose for a second so that the image of
            // the end (a closed door) can converge a little before it starts again.
            let period = scene.duration() + 1.0;
            let t = (self.animation_clock + dt) % period;
            self.animation_clock = t;
            self.set_time(scene, t.min(scene.duration()))?;
        }
        self.camera.advance(motion, dt);
        let (dx, dy) = std::mem::take(&mut self.drag);
        self.camera.turn(dx, dy);
        self.renderer.set_camera(self.camera.camera());

        if self.minimized {
            // Nothing to show: no frame until the window is restored.
            std::thread::sleep(Duration::from_millis(10));
            return Ok(());
        }
        if self.recreate || self.swapchain.is_none() {
            self.recreate_swapchain(args)?;
        }
        self.run_overlay(scene)?;
        let profile = self.profile_every > 0 && self.frame % self.profile_every == 1;
        self.renderer.set_timing(if profile { Timing::PerPassSubmit } else { Timing::Timestamps });

        self.fit_batches()?;
        let slot = self.renderer.wait_for_slot()?;
        let swapchain = self.swapchain.as_ref().expect("made above");
        let Some(acquired) = swapchain.acquire(slot)? else {
            self.recreate = true;
            return Ok(());
        };
        let index = acquired.index;
        let sync = SubmitSync {
            wait: vec![(acquired.ready, vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT)],
            signal: vec![acquired.rendered],
        };
        let overlay: Option<&dyn leakless::Overlay> = self.show_overlay.then_some(&self.overlay);
        self.renderer.render_frame(Some(DisplayTarget { image: acquired.image, sync, overlay }))?;
        match swapchain.present(self.renderer.gpu(), index)? {
            PresentOutcome::Presented => {}
            PresentOutcome::Suboptimal | PresentOutcome::OutOfDate => self.recreate = true,
        }
        if let Some(last) = self.last_shown {
            self.frame_ms = (now - last).as_secs_f64() * 1e3;
        }
        self.last_shown = Some(now);
        summary.frame();
        Ok(())
    }

    /// How many batches (of photon paths, or of reference samples) a still view's frames may
    /// grow to, so that a frame stays within `STILL_FRAME_BUDGET_MS` and the app answers a key
    /// at once. A frame of B batches is taken to cost B times the last frame's time per batch
    /// (an upper bound: the view samples' work is shared). Fitted at the start of each
    /// accumulation, and once more when the first measurement of the method arrives (frames do
    /// not grow before it). On a GPU a batch takes milliseconds and frames grow to the limit;
    /// on lavapipe at the default size one photon batch already fills the budget and frames
    /// stay at one.
    fn fit_batches(&mut self) -> anyhow::Result<()> {
        let fresh = self.renderer.accumulated() == 0;
        if !fresh && self.batches_fitted {
            return Ok(());
        }
        let s = self.renderer.settings();
        // The first frames (pipelines warming, lists growing) are slower than the rest.
        let settled =
            self.frame > WARM_UP_FRAMES && self.frame_ms > 0.0 && interval_is_typical(self.frame, self.profile_every);
        // A frame of the method now drawn: after a switch, the last one may be of another.
        let measured =
            self.renderer.last_report().filter(|r| settled && r.method == s.method && r.method != Method::Direct);
        let fit = match measured {
            Some(last) => {
                let per_batch = self.frame_ms / last.frame_batches.max(1) as f64;
                self.batches_fitted = true;
                (STILL_FRAME_BUDGET_MS / per_batch).floor().clamp(1.0, self.batch_limit as f64) as u32
            }
            None if fresh => {
                // Refit once a frame of this method has been measured (after a switch, none has).
                self.batches_fitted = false;
                1
            }
            None => return Ok(()),
        };
        if fit != s.max_batches {
            self.renderer.update(|s| s.max_batches = fit)?;
        }
        Ok(())
    }

    /// Moves the scene to time `t`; an animated camera takes the fly camera with it.
    fn set_time(&mut self, scene: &Scene, t: f32) -> anyhow::Result<()> {
        let before = self.renderer.camera().clone();
        self.renderer.set_time(t)?;
        if *self.renderer.camera() != before {
            self.camera = super::camera::FlyCamera::new(scene, self.renderer.camera());
        }
        Ok(())
    }

    fn recreate_swapchain(&mut self, args: &ViewArgs) -> anyhow::Result<()> {
        // The old swapchain's semaphores may still be waited on by a present, which no fence
        // tracks: only an idle device (queue included) frees them.
        self.renderer.wait_idle()?;
        self.renderer.gpu().wait_idle()?;
        let extent = vk::Extent2D { width: self.size.0, height: self.size.1 };
        let old = self.swapchain.take();
        let mode =
            old.as_ref().map_or(leakless_device::PresentMode::parse(&args.present).unwrap_or_default(), |s| s.mode());
        let swapchain = Swapchain::new(self.renderer.gpu(), extent, mode, leakless::renderer::FRAMES_IN_FLIGHT, old)?;
        let e = swapchain.extent();
        if e.width == 0 || e.height == 0 {
            self.minimized = true;
            return Ok(());
        }
        let renderer = &mut self.renderer;
        let (size, why) =
            refusal::fit_render_size((e.width, e.height), self.render_scale, |w, h| renderer.set_size(w, h))?;
        // A window size applied is a change made: it clears an earlier refusal, as keys do.
        let why = why.map(|why| format!("render size held to {}×{} ({why})", size.0, size.1));
        if why.is_some() && why != self.refusal {
            eprintln!("{}", why.as_deref().unwrap_or_default());
        }
        self.refusal = why;
        self.renderer.prepare_display(swapchain.format())?;
        self.overlay.set_format(swapchain.format())?;
        self.swapchain = Some(swapchain);
        self.recreate = false;
        Ok(())
    }

    fn run_overlay(&mut self, scene: &Scene) -> anyhow::Result<()> {
        if !self.show_overlay {
            self.overlay.clear();
            return Ok(());
        }
        let r = &self.renderer;
        let s = r.settings();
        let auto_radius = 0.05 * scene.bounds().bounding_radius();
        let mut sliders = Sliders {
            radius: s.splat.radius.unwrap_or(auto_radius),
            radius_range: (auto_radius / 50.0, auto_radius * 50.0),
            paths: s.splat.paths,
            max_batches: self.batch_limit,
            cap: s.splat.cap.unwrap_or(leakless::settings::DEFAULT_CAP),
            time: r.time(),
            duration: scene.is_animated().then(|| scene.duration()),
        };
        let before = sliders;
        if let Some(report) = r.last_report() {
            // Per-pass submissions leave host times; on a GPU every frame's timestamps count.
            if self.profile_every == 0 || report.timings.iter().any(|t| t.wall_ms.is_some()) {
                self.timings = Some(report.timings.clone());
            }
        }
        let gpu = r.gpu().report();
        let timing_note = if self.profile_every > 0 {
            format!(
                "each pass submitted alone, every {} frames: this CPU device's timestamps do not bracket compute work",
                self.profile_every
            )
        } else {
            "GPU timestamps".into()
        };
        let info = PanelInfo {
            scene: &scene.name,
            device: &gpu.name,
            backend: r.backend().name(),
            backend_why: r.backend_why(),
            refusal: self.refusal.as_deref(),
            width: s.width,
            height: s.height,
            method: s.method,
            layer: r.view_layer(),
            frame_ms: self.frame_ms,
            report: r.last_report(),
            timings: self.timings.as_deref(),
            timing_note: &timing_note,
            paused: r.paused(),
            seed_frozen: self.seed_frozen,
            accumulating: r.accumulating(),
            accumulation_full: r.accumulation_full(),
            trivial_accept: s.splat.trivial_accept,
            light_moved: self.light_moved,
            playing: self.playing && scene.is_animated(),
            pose_update_ms: r.pose_update_ms(),
        };
        let mut help = self.show_help;
        self.overlay.run(&self.window, self.frame, |ctx| panel::show(ctx, &info, &mut sliders, &mut help))?;
        self.show_help = help;
        if sliders.time != before.time {
            self.animation_clock = sliders.time;
            self.set_time(scene, sliders.time)?;
        }
        self.batch_limit = sliders.max_batches;
        let changed = |s: &Sliders| (s.radius, s.paths, s.cap, s.max_batches);
        if changed(&sliders) != changed(&before) {
            let change = self.renderer.update(|s| {
                if sliders.radius != before.radius {
                    s.splat.radius = Some(sliders.radius);
                }
                s.splat.paths = sliders.paths;
                s.max_batches = sliders.max_batches;
                if sliders.cap != before.cap {
                    s.splat.cap = Some(sliders.cap);
                }
            });
            self.settle(change)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::interval_is_typical;

    #[test]
    fn the_intervals_of_a_profiled_tick_and_the_one_after_it_do_not_measure_a_batch() {
        // Profiled ticks 1, 31, 61, …: their times reach fit_batches at ticks 3, 33, …, and the
        // times of the ticks after them at 4, 34, ….
        let skipped: Vec<u64> = (3..70).filter(|&t| !interval_is_typical(t, 30)).collect();
        assert_eq!(skipped, [3, 4, 33, 34, 63, 64]);
        // Without profiling (GPUs) every interval counts.
        assert!((0..100).all(|t| interval_is_typical(t, 0)));
    }
}
