//! What moves between frames without a change of settings: the camera, the lights and the
//! scene's animation clock. Every change restarts accumulation.

use leakless_scene::{Camera, Light};

use super::Renderer;
use crate::error::{RenderError, Result};

impl Renderer {
    pub fn set_camera(&mut self, camera: Camera) {
        if camera != self.camera {
            self.camera = camera;
            self.restart();
        }
    }

    /// Replaces light `index` (its position, direction, intensity...).
    pub fn set_light(&mut self, index: usize, light: Light) -> Result<()> {
        let slot = self.lights.get_mut(index).ok_or_else(|| {
            RenderError::Settings(format!("light {index}: the scene has {} lights", self.scene.lights.len()))
        })?;
        *slot = light;
        self.restart();
        Ok(())
    }

    /// Plays the scene's animation to `t` seconds: animated instances, and the lights and
    /// camera on animated nodes, move there (a light or camera the user placed, and whose node
    /// does not move between the old time and `t`, stays where it was put). Anything that moved
    /// restarts accumulation.
    pub fn set_time(&mut self, t: f32) -> Result<()> {
        if !t.is_finite() {
            return Err(RenderError::Settings(format!("time {t}: must be a finite number of seconds")));
        }
        let old = self.pose.time;
        let mut moved = self.pose.set_time(&self.scene, &self.gpu_scene.bvh.bvh, t);
        if self.scene.is_animated() {
            let (before, after) = (self.scene.lights_at(old), self.scene.lights_at(t));
            for (i, (b, a)) in before.iter().zip(after).enumerate() {
                if *b != a {
                    self.lights[i] = a;
                    moved = true;
                }
            }
            if let (Some(b), Some(a)) = (self.scene.camera_at(old), self.scene.camera_at(t)) {
                if b != a {
                    self.camera = a;
                    moved = true;
                }
            }
        }
        if moved {
            self.restart();
        }
        Ok(())
    }

    /// The scene's clock (seconds).
    pub fn time(&self) -> f32 {
        self.pose.time
    }

    /// Host milliseconds of the last pose change (instance transforms, world vertices, the
    /// compute backend's top level); the GPU's part is the `instance vertices` and
    /// `tlas rebuild` passes of the frame that follows.
    pub fn pose_update_ms(&self) -> f64 {
        self.pose.update_ms
    }
}
