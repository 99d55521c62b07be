//! The fly camera: an eye, a heading (yaw) and a pitch, moved by WASD/QE and turned by
//! dragging. Cameras are built with `Camera::look_at`, as `--camera` builds them, so a
//! capture's command line gives back exactly the view.

use glam::Vec3;
use leakless_scene::{Camera, Scene};

use crate::options::CameraSpec;

/// Radians per pixel of mouse drag.
const TURN_PER_PIXEL: f32 = 0.004;
/// Pitch stays short of straight up or down, where the view's up direction would flip.
const MAX_PITCH: f32 = 1.55;

#[derive(Clone, Debug)]
pub struct FlyCamera {
    start: CameraSpec,
    /// The view as it is now; `None` until the camera first moves (the start view is the
    /// scene's camera itself, roll included).
    spec: CameraSpec,
    yaw: f32,
    pitch: f32,
    moved: bool,
    /// Scene units per second.
    pub speed: f32,
    /// What `R` goes back to.
    start_speed: f32,
    clip: Camera,
}

/// Keys held this frame: -1, 0 or 1 along each of the camera's right, up and forward axes.
#[derive(Clone, Copy, Debug, Default)]
pub struct Motion {
    pub right: f32,
    pub up: f32,
    pub forward: f32,
}

impl FlyCamera {
    /// Starts at `start` (the scene's camera, or the framing `render` uses, or `--camera`).
    pub fn new(scene: &Scene, start: &Camera) -> FlyCamera {
        let eye = start.position();
        let forward = start.forward();
        let spec = CameraSpec { eye, target: eye + forward, up: start.up(), yfov_degrees: start.yfov.to_degrees() };
        let speed = 0.5 * scene.bounds().bounding_radius().max(1e-6);
        let (yaw, pitch) = angles(forward);
        FlyCamera {
            start: spec,
            spec,
            yaw,
            pitch,
            moved: false,
            speed,
            start_speed: speed,
            clip: scene.camera_or_framing(),
        }
    }

    pub fn reset(&mut self) {
        *self = FlyCamera { spec: self.start, moved: false, speed: self.start_speed, ..self.clone() };
        (self.yaw, self.pitch) = angles(self.start.target - self.start.eye);
    }

    /// Moves for `dt` seconds along `motion` (world up for Q/E).
    pub fn advance(&mut self, motion: Motion, dt: f32) {
        if motion.right == 0.0 && motion.up == 0.0 && motion.forward == 0.0 {
            return;
        }
        let forward = direction(self.yaw, self.pitch);
        let right = forward.cross(Vec3::Y).normalize_or_zero();
        let step = (right * motion.right + Vec3::Y * motion.up + forward * motion.forward) * self.speed * dt;
        self.settle();
        self.spec.eye += step;
        self.spec.target = self.spec.eye + forward;
    }

    /// Turns by a drag of `dx`, `dy` pixels (right and down).
    pub fn turn(&mut self, dx: f32, dy: f32) {
        if dx == 0.0 && dy == 0.0 {
            return;
        }
        self.settle();
        self.yaw -= dx * TURN_PER_PIXEL;
        self.pitch = (self.pitch - dy * TURN_PER_PIXEL).clamp(-MAX_PITCH, MAX_PITCH);
        self.spec.target = self.spec.eye + direction(self.yaw, self.pitch);
    }

    /// From the first move on, the view is level: up is the world's +Y.
    fn settle(&mut self) {
        if !self.moved {
            self.moved = true;
            self.spec.up = Vec3::Y;
        }
    }

    /// Scales the speed by `factor` per wheel notch.
    pub fn scale_speed(&mut self, notches: f32) {
        self.speed = (self.speed * 1.25f32.powf(notches)).clamp(1e-9, 1e12);
    }

    /// The view as `--camera` writes it.
    pub fn spec(&self) -> CameraSpec {
        self.spec
    }

    pub fn camera(&self) -> Camera {
        let s = &self.spec;
        Camera::look_at(s.eye, s.target, s.up, s.yfov_degrees.to_radians(), &self.clip)
            .unwrap_or_else(|| self.clip.clone())
    }
}

/// Unit direction of heading `yaw` (about +Y, from -Z) and `pitch`.
fn direction(yaw: f32, pitch: f32) -> Vec3 {
    Vec3::new(-yaw.sin() * pitch.cos(), pitch.sin(), -yaw.cos() * pitch.cos())
}

fn angles(forward: Vec3) -> (f32, f32) {
    let f = forward.normalize_or(Vec3::NEG_Z);
    ((-f.x).atan2(-f.z), f.y.clamp(-1.0, 1.0).asin().clamp(-MAX_PITCH, MAX_PITCH))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angles_invert_direction() {
        for (yaw, pitch) in [(0.0, 0.0), (1.0, 0.3), (-2.5, -1.2), (3.0, 1.5)] {
            let (y, p) = angles(direction(yaw, pitch));
            assert!((direction(y, p) - direction(yaw, pitch)).length() < 1e-5);
        }
    }
}
