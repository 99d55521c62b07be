//! The view: the file's first perspective camera or one framing the scene.
//!
//! Only `yfov` (and the clip distances) are kept: the aspect ratio follows the
//! output image (docs/architecture.md §4), so a file's `aspectRatio` is ignored.

use glam::{Mat4, Vec3, Vec4};
use gltf::json;

use crate::Aabb;

/// A pinhole camera. glTF convention: it looks down its local -Z with +Y up.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    /// Rigid transform (rotation + translation, no scale) from camera to world
    /// space. Node scale is removed at load time so that renderers can invert it
    /// cheaply and distances in camera space are world distances.
    pub world_from_camera: Mat4,
    /// Vertical field of view in radians.
    pub yfov: f32,
    pub znear: f32,
    /// `None` is an infinite far plane (glTF's default).
    pub zfar: Option<f32>,
}

impl Camera {
    /// World-space eye position.
    pub fn position(&self) -> Vec3 {
        self.world_from_camera.w_axis.truncate()
    }

    /// Unit viewing direction in world space (camera -Z).
    pub fn forward(&self) -> Vec3 {
        -self.world_from_camera.z_axis.truncate()
    }

    /// Unit up direction in world space (camera +Y).
    pub fn up(&self) -> Vec3 {
        self.world_from_camera.y_axis.truncate()
    }

    /// The view matrix (world to camera space).
    pub fn view_from_world(&self) -> Mat4 {
        self.world_from_camera.inverse()
    }

    /// A camera at `eye` looking at `target`, `up` as near its +Y as possible, with the
    /// clip distances of `clip` (`None` when the three points give no view direction or no
    /// up direction). The CLI's `--camera` and the app's fly camera both build cameras here,
    /// so the same four values give bit-identical views.
    pub fn look_at(eye: Vec3, target: Vec3, up: Vec3, yfov: f32, clip: &Camera) -> Option<Camera> {
        let back = (eye - target).normalize_or_zero();
        let right = up.cross(back).normalize_or_zero();
        if back == Vec3::ZERO || right == Vec3::ZERO || !eye.is_finite() || !(yfov > 0.0 && yfov < std::f32::consts::PI)
        {
            return None;
        }
        let up = back.cross(right);
        let world_from_camera = Mat4::from_cols(right.extend(0.0), up.extend(0.0), back.extend(0.0), eye.extend(1.0));
        Some(Camera { world_from_camera, yfov, znear: clip.znear, zfar: clip.zfar })
    }

    /// A camera on the +Z side of `bounds` looking at its centre along -Z, yfov 45°,
    /// far enough that the bounding sphere fits the vertical field of view (and so
    /// the horizontal one for any output at least as wide as it is tall).
    pub fn framing(bounds: &Aabb) -> Camera {
        let yfov = 45f32.to_radians();
        let radius = bounds.bounding_radius();
        // A zero or absurd box (all vertices in one point) still gets a usable view.
        let radius = if radius.is_finite() && radius > 0.0 { radius } else { 1.0 };
        let distance = radius / (yfov * 0.5).sin();
        let center = bounds.center();
        let center = if center.is_finite() { center } else { Vec3::ZERO };
        Camera {
            world_from_camera: Mat4::from_translation(center + Vec3::Z * distance),
            yfov,
            znear: 0.5 * (distance - radius),
            zfar: Some(2.0 * (distance + radius)),
        }
    }
}

/// Builds the camera of a node from its glTF camera object and world transform.
/// `Err` carries the warning saying why the camera is skipped.
pub(crate) fn from_json(index: usize, camera: &json::camera::Camera, world: Mat4) -> Result<Camera, String> {
    let label = match &camera.name {
        Some(name) => format!("camera {index} '{name}'"),
        None => format!("camera {index}"),
    };
    use json::camera::Type;
    let perspective = match (&camera.type_, &camera.perspective) {
        (json::validation::Checked::Valid(Type::Perspective), Some(p)) => p,
        (json::validation::Checked::Valid(Type::Orthographic), _) => {
            return Err(format!("{label} is orthographic: skipped"));
        }
        _ => return Err(format!("{label} has no perspective projection: skipped")),
    };
    let yfov = perspective.yfov;
    if !(yfov.is_finite() && yfov > 0.0 && yfov < std::f32::consts::PI) {
        return Err(format!("{label} has an invalid yfov {yfov}: skipped"));
    }
    let znear = perspective.znear;
    if !(znear.is_finite() && znear > 0.0) {
        return Err(format!("{label} has an invalid znear {znear}: skipped"));
    }
    let zfar = perspective.zfar.filter(|f| f.is_finite() && *f > znear);
    let world_from_camera = rigid(world).ok_or_else(|| format!("{label} has a degenerate node transform: skipped"))?;
    Ok(Camera { world_from_camera, yfov, znear, zfar })
}

/// Removes scale and shear from `m`, keeping its translation, its -Z (view) axis
/// exactly and its +Y (up) axis as closely as possible (Gram-Schmidt). A mirrored
/// node still yields a proper rotation: a mirrored image is never what a user wants.
fn rigid(m: Mat4) -> Option<Mat4> {
    let back = m.z_axis.truncate().normalize_or_zero();
    let y = m.y_axis.truncate();
    let up = (y - back * y.dot(back)).normalize_or_zero();
    let right = up.cross(back);
    let t = m.w_axis.truncate();
    if back == Vec3::ZERO || up == Vec3::ZERO || !t.is_finite() {
        return None;
    }
    Some(Mat4::from_cols(right.extend(0.0), up.extend(0.0), back.extend(0.0), Vec4::new(t.x, t.y, t.z, 1.0)))
}
