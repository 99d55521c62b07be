//! One iteration of the app's loop: the script's events, the camera, the overlay's UI, then
//! a frame acquired, rendered and presented.

use std::time::{Duration, Instant};

use ash::vk;
use leakless::{DisplayTarget, Scene};
use leakless_device::{PresentOutcome, SubmitSync, Swapchain};
use leakless_graph::Timing;

use super::camera::Motion;
use super::keys;
use super::panel::{self, PanelInfo, Sliders};
use super::refusal;
use super::script::{Event, Script};
use super::summary::Summary;
use super::{capture, Running, ViewArgs};

/// The time step of scripted runs: the same motion whatever the machine's speed.
const SCRIPT_DT: f32 = 1.0 / 30.0;

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
                    Event::Capture(path) => {
                        let why = capture::capture(self, scene, &path)?;
                        self.note_refusal(why);
                    }
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
            self.renderer.set_reuse_history_rate(1e3 / self.frame_ms.max(1.0));
        }
        self.last_shown = Some(now);
        // A frame that started an accumulation (every frame while anything moves) is what the
        // budget holds to its target.
        let moving = self.renderer.accumulated() == 1;
        summary.frame(moving);
        if let Some(report) = self.renderer.last_report() {
            if let Some(budget) = report.budget {
                let new = self.budget.is_none_or(|b| b != budget);
                self.budget = Some(budget);
                if new {
                    let s = self.renderer.settings();
                    summary.budgeted(budget, (s.width, s.height));
                }
                if new && !budget.warm_up {
                    self.follow_resolution(budget.resolution_factor as f32)?;
                }
            }
        }
        Ok(())
    }

    /// Rendered pixels per window pixel: the render scale, times dynamic resolution's share.
    pub(super) fn scale(&self) -> f32 {
        self.render_scale * self.dynamic.scale
    }

    /// Dynamic resolution: the render size scaled by `factor` as the frame budget advises
    /// ([`DynamicResolution`](leakless::frame_budget::DynamicResolution)).
    fn follow_resolution(&mut self, factor: f32) -> anyhow::Result<()> {
        if self.swapchain.is_none() {
            return Ok(());
        }
        let Some(wanted) = self.dynamic.follow(factor) else { return Ok(()) };
        let renderer = &mut self.renderer;
        refusal::fit_render_size(self.size, self.render_scale * wanted, |w, h| renderer.set_size(w, h))?;
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
        let scale = self.scale();
        let renderer = &mut self.renderer;
        let (size, why) = refusal::fit_render_size((e.width, e.height), scale, |w, h| renderer.set_size(w, h))?;
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
        let auto_radius = leakless::splatting::auto_radius(scene);
        let mut sliders = Sliders {
            radius: s.splat.radius.unwrap_or_else(|| r.single_frame_radius(s.splat.paths)),
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
            primary: r.primary(),
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
            reuse: s.reuse,
            light_moved: self.light_moved,
            playing: self.playing && scene.is_animated(),
            pose_update_ms: r.pose_update_ms(),
            budget: self.budget.as_ref(),
            dynamic_scale: self.dynamic.scale,
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
