//! What a key press does: the action applied to the renderer and the app, or refused (a
//! change the device cannot render or the settings refuse) with the reason kept for the panel.

use leakless::{BackendChoice, Scene};
use winit::keyboard::KeyCode;

use super::keys::{self, Action};
use super::refusal;
use super::{capture, Running};

impl Running {
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
                let radius = r.single_frame_radius(r.settings().splat.paths);
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
            Action::ToggleReuse => r.update(|s| s.reuse = !s.reuse),
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
            // Emissive geometry moves with its node's animation, not by key.
            Action::MoveLight(d) => match r.lights().first().cloned() {
                None => Err(leakless::RenderError::Settings("the scene has no punctual light to move".into())),
                Some(mut light) => {
                    let step = 0.02 * scene.bounds().bounding_radius();
                    light.position += glam::Vec3::new(d[0] as f32, d[1] as f32, d[2] as f32) * step;
                    r.set_light(0, light)?;
                    self.light_moved = true;
                    Ok(())
                }
            },
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
                let why = capture::capture(self, scene, &path)?;
                self.note_refusal(why);
                return Ok(());
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
    pub(super) fn settle(&mut self, change: leakless::Result<()>) -> anyhow::Result<()> {
        let why = refusal::refused(change)?;
        self.note_refusal(why);
        Ok(())
    }

    /// Keeps why the last action was not done (`None`: it was), saying a new reason once.
    pub(super) fn note_refusal(&mut self, why: Option<String>) {
        if why.is_some() && why != self.refusal {
            eprintln!("not applied: {}", why.as_deref().unwrap_or_default());
        }
        self.refusal = why;
    }
}
