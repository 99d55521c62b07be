//! `KHR_lights_punctual` lights in radiometric units.
//!
//! docs/architecture.md §4: point and spot intensities are radiant intensity (W/sr) and
//! directional intensity is irradiance (W/m²), taken as given, with no 683 lm/W
//! photometric factor, so a scene's numbers are the renderer's numbers and the
//! analytic tests can use them directly.

use glam::{Mat4, Vec3};
use gltf::json;
use json::extensions::scene::khr_lights_punctual as khr;

/// The kind of a punctual light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightKind {
    /// Emits uniformly in all directions from [`Light::position`].
    Point,
    /// A point light restricted to a cone around [`Light::direction`], with glTF's
    /// smooth falloff between the two half-angles (radians, as in the file;
    /// glTF defaults 0 and π/4).
    Spot { inner_cone: f32, outer_cone: f32 },
    /// Parallel light travelling along [`Light::direction`]; its position is
    /// meaningless.
    Directional,
}

/// A punctual light in world space.
#[derive(Clone, Debug, PartialEq)]
pub struct Light {
    pub name: String,
    pub kind: LightKind,
    /// World-space position of the light's node.
    pub position: Vec3,
    /// Unit world-space direction in which the light travels (the node's -Z axis);
    /// used by spot and directional lights.
    pub direction: Vec3,
    /// Linear RGB colour (glTF default white).
    pub color: Vec3,
    /// W/sr for point and spot lights, W/m² for directional lights.
    pub intensity: f32,
    /// Distance cut-off from the file, if any (point and spot lights only). The
    /// renderer may ignore it: punctual lights in this project fall off as 1/d².
    pub range: Option<f32>,
}

/// Builds the light of a node. `Err` carries the warning saying why the light is
/// skipped (values no renderer can use: the scene would be wrong, not just ugly).
pub(crate) fn from_json(index: usize, light: &khr::Light, world: Mat4) -> Result<Light, String> {
    let name = light.name.clone().unwrap_or_else(|| format!("light {index}"));
    let kind = match light.type_ {
        json::validation::Checked::Valid(khr::Type::Point) => LightKind::Point,
        json::validation::Checked::Valid(khr::Type::Directional) => LightKind::Directional,
        json::validation::Checked::Valid(khr::Type::Spot) => {
            let (inner_cone, outer_cone) = light
                .spot
                .as_ref()
                .map(|s| (s.inner_cone_angle, s.outer_cone_angle))
                .unwrap_or((0.0, std::f32::consts::FRAC_PI_4));
            LightKind::Spot { inner_cone, outer_cone }
        }
        json::validation::Checked::Invalid => return Err(format!("light '{name}' has an unknown type: skipped")),
    };
    if let LightKind::Spot { inner_cone, outer_cone } = kind {
        if !(inner_cone.is_finite() && outer_cone.is_finite() && outer_cone > 0.0) {
            return Err(format!("spot light '{name}' has invalid cone angles: skipped"));
        }
    }
    let color = Vec3::from(light.color);
    if !(color.is_finite() && color.min_element() >= 0.0) {
        return Err(format!("light '{name}' has an invalid colour: skipped"));
    }
    let intensity = light.intensity;
    if !(intensity.is_finite() && intensity >= 0.0) {
        return Err(format!("light '{name}' has an invalid intensity {intensity}: skipped"));
    }
    let position = world.transform_point3(Vec3::ZERO);
    let direction = world.transform_vector3(Vec3::NEG_Z).normalize_or_zero();
    if !position.is_finite() || direction == Vec3::ZERO {
        return Err(format!("light '{name}' has a degenerate node transform: skipped"));
    }
    let range = match kind {
        LightKind::Directional => None,
        _ => light.range.filter(|r| r.is_finite() && *r > 0.0),
    };
    Ok(Light { name, kind, position, direction, color, intensity, range })
}
