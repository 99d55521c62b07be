//! Node animation: glTF `animations` whose channels drive a node's translation,
//! rotation or scale (glTF 2.0 §3.11 and Appendix C).
//!
//! [`load`] reads and validates every channel of every animation through the
//! bounds-checked accessor code; [`Rig`] is what a [`Scene`](crate::Scene) keeps to
//! evaluate the node hierarchy at any time: the nodes the loader placed (parents
//! before children), their rest transforms and the channels driving them. The loader
//! itself evaluates the rig at t = 0, so a scene's t = 0 data and a later
//! `Rig::world_at(0.0)` come from the same arithmetic.

use glam::{Mat4, Quat, Vec3, Vec4};
use gltf::json;
use json::accessor::{ComponentType, Type};
use json::animation::{Interpolation, Property};
use json::validation::Checked;

use crate::accessor::Data;
use crate::Aabb;

/// The node property a channel drives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Path {
    Translation,
    Rotation,
    Scale,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Interp {
    Step,
    Linear,
    CubicSpline,
}

/// One validated channel: strictly increasing finite key times and finite values.
#[derive(Clone, Debug)]
pub(crate) struct Channel {
    /// glTF node index after [`load`]; the rig slot once the rig owns it.
    pub target: usize,
    pub path: Path,
    interp: Interp,
    times: Vec<f32>,
    /// One value per key (STEP, LINEAR), or in-tangent, value, out-tangent per key
    /// (CUBICSPLINE). Translation and scale use xyz (w = 0); rotations are x, y, z,
    /// w, normalised per key except for CUBICSPLINE (whose result is normalised).
    values: Vec<Vec4>,
}

impl Channel {
    /// Time of the last key (seconds).
    pub fn end(&self) -> f32 {
        self.times.last().copied().unwrap_or(0.0)
    }

    /// Key times (seconds), strictly increasing.
    pub fn times(&self) -> &[f32] {
        &self.times
    }

    /// The channel's value at time `t`, clamped to the first key before it
    /// (and for a NaN `t`) and to the last key after it. A rotation comes out
    /// normalised. An interpolated value that overflows `f32` (only possible with
    /// values or tangents near `f32::MAX`) falls back to the key before `t`.
    pub fn sample(&self, t: f32) -> Vec4 {
        let n = self.times.len();
        let cubic = self.interp == Interp::CubicSpline;
        let key = |k: usize| self.values[if cubic { 3 * k + 1 } else { k }];
        #[allow(clippy::neg_cmp_op_on_partial_ord)] // NaN t clamps to the first key, on purpose
        if !(t > self.times[0]) {
            return key(0);
        }
        if t >= self.times[n - 1] {
            return key(n - 1);
        }
        // times[k] <= t < times[k + 1], k + 1 < n.
        let k = self.times.partition_point(|&x| x <= t) - 1;
        let (t0, t1) = (self.times[k], self.times[k + 1]);
        let dt = t1 - t0;
        let s = (t - t0) / dt;
        let s = if s.is_nan() { 0.0 } else { s.clamp(0.0, 1.0) };
        let rotation = self.path == Path::Rotation;
        let v = match self.interp {
            Interp::Step => return key(k),
            Interp::Linear if rotation => {
                Vec4::from(Quat::from_vec4(key(k)).slerp(Quat::from_vec4(key(k + 1)), s).normalize())
            }
            Interp::Linear => key(k).lerp(key(k + 1), s),
            Interp::CubicSpline => {
                // Appendix C: p(s) = (2s³ - 3s² + 1) v_k + td (s³ - 2s² + s) b_k
                //                   + (-2s³ + 3s²) v_k+1 + td (s³ - s²) a_k+1
                let (s2, s3) = (s * s, s * s * s);
                let v0 = self.values[3 * k + 1];
                let b0 = self.values[3 * k + 2];
                let a1 = self.values[3 * (k + 1)];
                let v1 = self.values[3 * (k + 1) + 1];
                let p = v0 * (2.0 * s3 - 3.0 * s2 + 1.0)
                    + b0 * (dt * (s3 - 2.0 * s2 + s))
                    + v1 * (-2.0 * s3 + 3.0 * s2)
                    + a1 * (dt * (s3 - s2));
                if rotation {
                    Vec4::from(unit_or_identity(Quat::from_vec4(p)))
                } else {
                    p
                }
            }
        };
        if v.is_finite() {
            v
        } else {
            key(k)
        }
    }
}

/// `q` normalised, or the identity when it has no direction (as for a node's own
/// rotation, see `load::local_matrix`).
fn unit_or_identity(q: Quat) -> Quat {
    // Scaled by the largest component first: a finite quaternion whose squared length
    // overflows (or underflows) still normalises.
    let m = Vec4::from(q).abs().max_element();
    if m.is_finite() && m > 0.0 {
        let u = (Quat::from_vec4(Vec4::from(q) / m)).normalize();
        if u.is_finite() {
            return u;
        }
    }
    Quat::IDENTITY
}

/// The largest key value a channel may hold (translations in metres, scales, tangents).
pub(crate) const MAX_KEY_MAGNITUDE: f32 = 1e15;

/// Why a channel (or its sampler) cannot be used.
pub(crate) struct ChannelError {
    /// `"0 'walk'"` or `"0"`.
    pub animation: String,
    pub channel: usize,
    pub message: String,
}

/// Every usable channel of every animation, in file order, plus the "ignored"
/// items for channels this loader does not model.
pub(crate) struct Loaded {
    pub channels: Vec<Channel>,
    pub ignored: Vec<String>,
}

/// Reads and validates the channels of all animations. A channel with a bad
/// sampler or target fails the whole load; `weights` channels and channels with a
/// path this loader does not know are left out (and reported as ignored).
pub(crate) fn load(root: &json::Root, data: &Data) -> Result<Loaded, ChannelError> {
    let mut channels = Vec::new();
    let (mut weights, mut unknown) = (0usize, 0usize);
    for (ai, anim) in root.animations.iter().enumerate() {
        let label = match &anim.name {
            Some(n) => format!("{ai} '{n}'"),
            None => ai.to_string(),
        };
        for (ci, ch) in anim.channels.iter().enumerate() {
            let err = |message: String| ChannelError { animation: label.clone(), channel: ci, message };
            let path = match ch.target.path {
                Checked::Valid(Property::Translation) => Path::Translation,
                Checked::Valid(Property::Rotation) => Path::Rotation,
                Checked::Valid(Property::Scale) => Path::Scale,
                Checked::Valid(Property::MorphTargetWeights) => {
                    weights += 1;
                    continue;
                }
                Checked::Invalid => {
                    unknown += 1;
                    continue;
                }
            };
            let node = ch.target.node.value();
            let Some(n) = root.nodes.get(node) else {
                return Err(err(format!("target node {node} does not exist ({} nodes)", root.nodes.len())));
            };
            if n.matrix.is_some() {
                return Err(err(format!(
                    "target node {node} has a matrix; glTF animates only nodes given by translation/rotation/scale"
                )));
            }
            let si = ch.sampler.value();
            let sampler = anim.samplers.get(si).ok_or_else(|| err(format!("sampler {si} does not exist")))?;
            let channel = read_sampler(data, sampler, node, path).map_err(|m| err(format!("sampler {si}: {m}")))?;
            channels.push(channel);
        }
    }
    let mut ignored = Vec::new();
    if weights > 0 {
        ignored.push("animated morph target weights".to_string());
    }
    if unknown > 0 {
        ignored.push("animation channels with unknown paths".to_string());
    }
    Ok(Loaded { channels, ignored })
}

fn read_sampler(data: &Data, sampler: &json::animation::Sampler, node: usize, path: Path) -> Result<Channel, String> {
    let interp = match sampler.interpolation {
        Checked::Valid(Interpolation::Step) => Interp::Step,
        Checked::Valid(Interpolation::Linear) => Interp::Linear,
        Checked::Valid(Interpolation::CubicSpline) => Interp::CubicSpline,
        Checked::Invalid => return Err("unknown interpolation".into()),
    };
    let input = sampler.input.value();
    let (ty, ct, _, count) = format(data, input).map_err(|e| format!("input: {e}"))?;
    if ty != Type::Scalar || ct != ComponentType::F32 {
        return Err(format!("input accessor {input} is {ty:?} of {ct:?}, not SCALAR of FLOAT"));
    }
    if count == 0 {
        return Err(format!("input accessor {input} has no keys"));
    }
    let times = data.floats(input, Type::Scalar).map_err(|e| format!("input: {e}"))?;
    if let Some(k) = times.iter().position(|t| !t.is_finite()) {
        return Err(format!("input time {k} is {}, not finite", times[k]));
    }
    if let Some(k) = times.windows(2).position(|w| w[1] <= w[0]) {
        return Err(format!(
            "input times are not strictly increasing (key {k} at {} s, key {} at {} s)",
            times[k],
            k + 1,
            times[k + 1]
        ));
    }
    let output = sampler.output.value();
    let (ty, ct, normalized, count) = format(data, output).map_err(|e| format!("output: {e}"))?;
    let (want, dims) = match path {
        Path::Translation | Path::Scale => (Type::Vec3, 3),
        Path::Rotation => (Type::Vec4, 4),
    };
    // glTF's accessor table: rotations may be normalized integers, the rest float.
    let component_ok = ct == ComponentType::F32
        || (path == Path::Rotation
            && normalized
            && matches!(ct, ComponentType::I8 | ComponentType::U8 | ComponentType::I16 | ComponentType::U16));
    if ty != want || !component_ok {
        let n = if normalized { "normalized " } else { "" };
        return Err(format!("output accessor {output} is {ty:?} of {n}{ct:?}, which a {path:?} channel cannot use"));
    }
    let per_key = if interp == Interp::CubicSpline { 3 } else { 1 };
    let expected = per_key * times.len() as u64;
    // Checked before reading, so that a huge count is not allocated for nothing.
    if count != expected {
        let why = if per_key == 3 { " (CUBICSPLINE: 3 per key)" } else { "" };
        return Err(format!(
            "output accessor {output} has {count} elements for {} keys, expected {expected}{why}",
            times.len()
        ));
    }
    let flat = data.floats(output, want).map_err(|e| format!("output: {e}"))?;
    if let Some(k) = flat.iter().position(|v| !v.is_finite()) {
        return Err(format!("output element {} has a non-finite component", k / dims));
    }
    // Beyond this, poses overflow f32 when keys are interpolated or transforms composed;
    // no scene the renderer can show moves that far (float positions lose all precision).
    if let Some(k) = flat.iter().position(|v| v.abs() > MAX_KEY_MAGNITUDE) {
        return Err(format!(
            "output element {} has a component of magnitude {:e}, beyond {MAX_KEY_MAGNITUDE:e}",
            k / dims,
            flat[k].abs()
        ));
    }
    let mut values: Vec<Vec4> = flat
        .chunks_exact(dims)
        .map(|c| if dims == 4 { Vec4::new(c[0], c[1], c[2], c[3]) } else { Vec4::new(c[0], c[1], c[2], 0.0) })
        .collect();
    if path == Path::Rotation && interp != Interp::CubicSpline {
        for v in &mut values {
            *v = Vec4::from(unit_or_identity(Quat::from_vec4(*v)));
        }
    }
    Ok(Channel { target: node, path, interp, times, values })
}

/// Type, component type, `normalized` and count of accessor `index`.
fn format(data: &Data, index: usize) -> Result<(Type, ComponentType, bool, u64), String> {
    let a = data.root.accessors.get(index).ok_or_else(|| format!("accessor {index} does not exist"))?;
    match (&a.type_, &a.component_type) {
        (Checked::Valid(t), Checked::Valid(c)) => Ok((*t, c.0, a.normalized, a.count.0)),
        _ => Err(format!("accessor {index} has an invalid type")),
    }
}

/// A node's rest translation, rotation (normalised, identity when unusable) and
/// scale: what its channels' un-animated properties keep.
pub(crate) fn rest_trs(node: &json::scene::Node) -> (Vec3, Quat, Vec3) {
    let t = Vec3::from(node.translation.unwrap_or([0.0; 3]));
    let s = Vec3::from(node.scale.unwrap_or([1.0; 3]));
    let q = node.rotation.as_ref().map_or(Quat::IDENTITY, |r| Quat::from_array(r.0));
    (t, unit_or_identity(q), s)
}

/// A node the loader placed.
#[derive(Clone, Debug)]
pub(crate) struct Slot {
    /// The parent's slot (always smaller than this one's).
    pub parent: Option<usize>,
    /// The local transform when no channel drives the node (the file's matrix or
    /// T·R·S, exactly as the static loader computes it).
    pub local: Mat4,
    /// Rest T, R, S of a node that channels drive.
    pub rest: (Vec3, Quat, Vec3),
    /// Indices into [`Rig::channels`] driving this node, in file order (a later
    /// channel on the same property wins).
    pub channels: Vec<usize>,
    /// A channel drives this node or one of its ancestors.
    pub animated: bool,
}

/// The placed node hierarchy and the channels that move it.
#[derive(Clone, Debug, Default)]
pub(crate) struct Rig {
    /// Placed nodes in the loader's depth-first pre-order (parents first).
    pub slots: Vec<Slot>,
    pub channels: Vec<Channel>,
    /// Animated light nodes: (index into `Scene::lights`, slot, light index in
    /// the file, its definition), to re-place them at any time.
    pub lights: Vec<(usize, usize, usize, json::extensions::scene::khr_lights_punctual::Light)>,
    /// The scene camera's node when it is animated: (slot, camera index, definition).
    pub camera: Option<(usize, usize, json::camera::Camera)>,
    /// `Scene::bounds` and `Scene::animated_bounds` of the scene a frozen scene
    /// was frozen from.
    pub frozen_bounds: Option<(Aabb, Aabb)>,
}

impl Rig {
    pub fn is_animated(&self) -> bool {
        !self.channels.is_empty()
    }

    /// Local transform of `slot` at time `t`.
    pub fn local_at(&self, slot: usize, t: f32) -> Mat4 {
        let s = &self.slots[slot];
        if s.channels.is_empty() {
            return s.local;
        }
        let (mut tr, mut rot, mut sc) = s.rest;
        for &c in &s.channels {
            let ch = &self.channels[c];
            let v = ch.sample(t);
            match ch.path {
                Path::Translation => tr = v.truncate(),
                Path::Rotation => rot = Quat::from_vec4(v),
                Path::Scale => sc = v.truncate(),
            }
        }
        Mat4::from_scale_rotation_translation(sc, rot, tr)
    }

    /// World transform of every slot at time `t`: the same products, in the same
    /// order, as the loader's node walk.
    pub fn world_at(&self, t: f32) -> Vec<Mat4> {
        let mut world: Vec<Mat4> = Vec::with_capacity(self.slots.len());
        for (i, s) in self.slots.iter().enumerate() {
            let parent = s.parent.map_or(Mat4::IDENTITY, |p| world[p]);
            world.push(parent * self.local_at(i, t));
        }
        world
    }

    /// The rig with every node's local transform fixed at its value at `t` and
    /// no channels: its `world_at` gives, for any time, exactly `self.world_at(t)`.
    pub fn frozen_at(&self, t: f32) -> Rig {
        let slots = (0..self.slots.len())
            .map(|i| Slot { local: self.local_at(i, t), channels: Vec::new(), ..self.slots[i].clone() })
            .collect();
        Rig {
            slots,
            channels: Vec::new(),
            lights: self.lights.clone(),
            camera: self.camera.clone(),
            frozen_bounds: self.frozen_bounds,
        }
    }

    /// Times at which [`crate::Scene::animated_bounds`] samples the animation:
    /// every key of every channel and three evenly spaced points between
    /// consecutive keys, at most [`MAX_BOUNDS_SAMPLES`] (evenly spaced over the
    /// keys' span beyond that).
    pub fn bounds_times(&self) -> Vec<f32> {
        let mut keys: Vec<f32> = self.channels.iter().flat_map(|c| c.times().iter().copied()).collect();
        keys.sort_by(f32::total_cmp);
        keys.dedup();
        let (Some(&first), Some(&last)) = (keys.first(), keys.last()) else {
            return Vec::new();
        };
        if keys.len() * 4 > MAX_BOUNDS_SAMPLES {
            let n = MAX_BOUNDS_SAMPLES - 1;
            return (0..=n).map(|i| first + (last - first) * (i as f32 / n as f32)).collect();
        }
        let mut times = vec![first];
        for w in keys.windows(2) {
            for j in 1..4 {
                times.push(w[0] + (w[1] - w[0]) * (j as f32 / 4.0));
            }
            times.push(w[1]);
        }
        times
    }
}

/// Cap on the number of times [`Rig::bounds_times`] returns.
pub(crate) const MAX_BOUNDS_SAMPLES: usize = 4096;

#[cfg(test)]
mod tests {
    use super::*;

    fn channel(path: Path, interp: Interp, times: &[f32], values: &[Vec4]) -> Channel {
        Channel { target: 0, path, interp, times: times.to_vec(), values: values.to_vec() }
    }

    #[test]
    fn clamps_and_interpolates() {
        let c = channel(Path::Translation, Interp::Linear, &[1.0, 3.0], &[Vec4::ZERO, Vec4::new(2.0, 4.0, 6.0, 0.0)]);
        assert_eq!(c.sample(f32::NAN), Vec4::ZERO);
        assert_eq!(c.sample(-5.0), Vec4::ZERO);
        assert_eq!(c.sample(2.0), Vec4::new(1.0, 2.0, 3.0, 0.0));
        assert_eq!(c.sample(9.0), Vec4::new(2.0, 4.0, 6.0, 0.0));
        let one = channel(Path::Scale, Interp::CubicSpline, &[0.5], &[Vec4::ONE, Vec4::splat(2.0), Vec4::ONE]);
        assert_eq!(one.sample(0.0), Vec4::splat(2.0));
        assert_eq!(one.sample(1.0), Vec4::splat(2.0));
    }

    #[test]
    fn overflowing_spline_falls_back_to_the_key() {
        let big = Vec4::splat(f32::MAX);
        let c =
            channel(Path::Translation, Interp::CubicSpline, &[0.0, 1e30], &[big, Vec4::ONE, big, big, Vec4::ONE, big]);
        assert_eq!(c.sample(0.5e30), Vec4::ONE);
    }

    #[test]
    fn bounds_times_subdivide_and_cap() {
        let rig = Rig {
            channels: vec![channel(Path::Scale, Interp::Step, &[0.0, 1.0], &[Vec4::ONE, Vec4::ONE])],
            ..Rig::default()
        };
        assert_eq!(rig.bounds_times(), vec![0.0, 0.25, 0.5, 0.75, 1.0]);
        let times: Vec<f32> = (0..5000).map(|i| i as f32).collect();
        let values = vec![Vec4::ONE; 5000];
        let rig = Rig { channels: vec![channel(Path::Scale, Interp::Step, &times, &values)], ..Rig::default() };
        let t = rig.bounds_times();
        assert_eq!((t.len(), t[0], *t.last().unwrap()), (MAX_BOUNDS_SAMPLES, 0.0, 4999.0));
    }
}
