//! Node animation: sampling (STEP, LINEAR, CUBICSPLINE, clamping), instances, lights
//! and camera on animated nodes, `frozen_at`, and one-line errors for bad channels.
//!
//! The glTF files are built here (JSON plus a base64 data-URI buffer), so that every
//! expected value is an analytic function of numbers in the test.

use std::f32::consts::FRAC_1_SQRT_2;
use std::path::PathBuf;

use glam::{Mat4, Quat, Vec3};
use leakless_scene::{LightKind, Scene, SceneError, Vertex};
use serde_json::{json, Value};

mod scratch;

// ---------------------------------------------------------------------------------
// Building files.

/// A document under construction: one buffer, its views and accessors.
#[derive(Default)]
struct Doc {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Doc {
    /// Appends `bytes` as a buffer view (4-byte aligned) and returns its index.
    fn view(&mut self, bytes: &[u8]) -> usize {
        while self.bin.len() % 4 != 0 {
            self.bin.push(0);
        }
        self.views.push(json!({"buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len()}));
        self.bin.extend_from_slice(bytes);
        self.views.len() - 1
    }

    fn accessor(&mut self, a: Value) -> usize {
        self.accessors.push(a);
        self.accessors.len() - 1
    }

    /// A float accessor of type `ty` over `xs` (with min/max when SCALAR, as glTF
    /// requires of animation inputs).
    fn floats(&mut self, xs: &[f32], ty: &str) -> usize {
        let dims = match ty {
            "SCALAR" => 1,
            "VEC2" => 2,
            "VEC3" => 3,
            _ => 4,
        };
        let bytes: Vec<u8> = xs.iter().flat_map(|x| x.to_le_bytes()).collect();
        let view = self.view(&bytes);
        let mut a = json!({"bufferView": view, "componentType": 5126, "count": xs.len() / dims, "type": ty});
        if ty == "SCALAR" && !xs.is_empty() {
            let min = xs.iter().copied().fold(f32::INFINITY, f32::min);
            let max = xs.iter().copied().fold(f32::NEG_INFINITY, f32::max);
            if min.is_finite() && max.is_finite() {
                a["min"] = json!([min]);
                a["max"] = json!([max]);
            }
        }
        self.accessor(a)
    }

    /// Normalized (or not) signed shorts as VEC4.
    fn shorts(&mut self, xs: &[i16], normalized: bool) -> usize {
        let bytes: Vec<u8> = xs.iter().flat_map(|x| x.to_le_bytes()).collect();
        let view = self.view(&bytes);
        self.accessor(json!({"bufferView": view, "componentType": 5122, "normalized": normalized,
                             "count": xs.len() / 4, "type": "VEC4"}))
    }

    /// Mesh 0: a unit quad in the XY plane facing +Z (two triangles, with normals
    /// and texture coordinates). Call first, so that it is mesh 0.
    fn quad_mesh(&mut self) -> Value {
        let p = [-0.5, -0.5, 0.0, 0.5, -0.5, 0.0, 0.5, 0.5, 0.0, -0.5, -0.5, 0.0, 0.5, 0.5, 0.0, -0.5, 0.5, 0.0];
        let pos = self.floats(&p, "VEC3");
        self.accessors[pos]["min"] = json!([-0.5, -0.5, 0.0]);
        self.accessors[pos]["max"] = json!([0.5, 0.5, 0.0]);
        let nrm = self.floats(&[0.0, 0.0, 1.0].repeat(6), "VEC3");
        let uv = self.floats(&[0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0], "VEC2");
        json!([{"name": "quad", "primitives": [{"attributes": {"POSITION": pos, "NORMAL": nrm, "TEXCOORD_0": uv}}]}])
    }

    /// The glTF text: `root` plus asset, buffer, views and accessors, and a point
    /// light definition (light 0) unless `root` has its own.
    fn finish(self, mut root: Value) -> String {
        root["asset"] = json!({"version": "2.0"});
        root["buffers"] = json!([{"byteLength": self.bin.len(),
                                  "uri": format!("data:application/octet-stream;base64,{}", base64::encode(&self.bin))}]);
        root["bufferViews"] = Value::Array(self.views);
        root["accessors"] = Value::Array(self.accessors);
        if root.get("extensions").is_none() {
            root["extensions"] = json!({"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 1}]}});
        }
        root["extensionsUsed"] = json!(["KHR_lights_punctual"]);
        root.to_string()
    }
}

/// A static light node (light 0), out of the way.
fn light_node() -> Value {
    json!({"name": "lamp", "translation": [0, 0, 5], "extensions": {"KHR_lights_punctual": {"light": 0}}})
}

fn sampler(input: usize, output: usize, interpolation: &str) -> Value {
    json!({"input": input, "output": output, "interpolation": interpolation})
}

fn channel(sampler: usize, node: usize, path: &str) -> Value {
    json!({"sampler": sampler, "target": {"node": node, "path": path}})
}

fn try_load(test: &str, gltf: &str) -> Result<Scene, SceneError> {
    let dir = scratch::scratch("anim-", test);
    let path = dir.join(format!("{test}.gltf"));
    std::fs::write(&path, gltf).unwrap();
    Scene::load(&path)
}

fn load(test: &str, gltf: &str) -> Scene {
    try_load(test, gltf).unwrap_or_else(|e| panic!("{test}: {e}"))
}

fn repo(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..").join(rel)
}

/// One node "mover" (mesh 0, rest translation `rest`) driven by one channel on
/// `path`, plus the static light; returns the scene.
fn one_channel(test: &str, path: &str, interpolation: &str, times: &[f32], values: &[f32], rest: [f32; 3]) -> Scene {
    let mut d = Doc::default();
    let meshes = d.quad_mesh();
    let ty = if path == "rotation" { "VEC4" } else { "VEC3" };
    let (input, output) = (d.floats(times, "SCALAR"), d.floats(values, ty));
    let gltf = d.finish(json!({
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"name": "mover", "mesh": 0, "translation": rest}, light_node()],
        "meshes": meshes,
        "animations": [{"name": "anim", "samplers": [sampler(input, output, interpolation)],
                        "channels": [channel(0, 0, path)]}],
    }));
    load(test, &gltf)
}

fn close(a: Vec3, b: Vec3, eps: f32) -> bool {
    (a - b).abs().max_element() <= eps
}

fn translation(m: &Mat4) -> Vec3 {
    m.w_axis.truncate()
}

/// Vertices compared bit for bit.
fn bits(v: &[Vertex]) -> Vec<u32> {
    v.iter().flat_map(|v| v.position.iter().chain(&v.normal).chain(&v.uv).map(|x| x.to_bits())).collect()
}

// ---------------------------------------------------------------------------------
// Sampling.

/// The renderer may hand scenes to other threads; the animation data must not
/// change that.
const _: () = {
    const fn send_sync<T: Send + Sync>() {}
    send_sync::<Scene>();
};

#[test]
fn linear_translation_is_linear_between_keys() {
    let s = one_channel("linear", "translation", "LINEAR", &[0.0, 2.0], &[0.0, 0.0, 0.0, 4.0, 2.0, -6.0], [9.0; 3]);
    assert!(s.is_animated());
    assert_eq!(s.duration(), 2.0);
    assert_eq!(s.instances.len(), 1);
    assert_eq!(s.static_triangle_count(), 0);
    let i = &s.instances[0];
    assert_eq!((i.name.as_str(), i.first_triangle, i.triangle_count, i.local_vertices.len()), ("mover", 0, 2, 6));
    assert_eq!(i.local_vertices[2].position, [0.5, 0.5, 0.0], "mesh space, as in the file");
    assert_eq!(translation(&s.instance_transforms(1.0)[0]), Vec3::new(2.0, 1.0, -3.0));
    assert_eq!(translation(&s.instance_transforms(0.5)[0]), Vec3::new(1.0, 0.5, -1.5));
    // The channel replaces the rest translation (9,9,9) from t = 0 on.
    assert_eq!(translation(&s.instance_transforms(0.0)[0]), Vec3::ZERO);
    assert_eq!(s.vertices[2].position, [0.5, 0.5, 0.0]);
}

#[test]
fn samplers_clamp_before_the_first_and_after_the_last_key() {
    // Keys at 1 s and 3 s: before 1 s the first value holds (also at t = 0, which
    // is what `vertices` shows), after 3 s the last.
    let s = one_channel("clamp", "translation", "LINEAR", &[1.0, 3.0], &[1.0, 0.0, 0.0, 3.0, 0.0, 0.0], [0.0; 3]);
    assert_eq!(s.duration(), 3.0);
    for (t, x) in [(-10.0, 1.0), (0.0, 1.0), (1.0, 1.0), (2.0, 2.0), (3.0, 3.0), (100.0, 3.0), (f32::NAN, 1.0)] {
        assert_eq!(translation(&s.instance_transforms(t)[0]), Vec3::new(x, 0.0, 0.0), "t = {t}");
    }
    assert_eq!(s.vertices[0].position, [0.5, -0.5, 0.0], "t = 0 pose: first key");
    // One key: constant.
    let s = one_channel("single", "scale", "STEP", &[0.5], &[2.0, 2.0, 2.0], [0.0; 3]);
    for t in [0.0, 0.5, 7.0] {
        assert_eq!(s.instance_transforms(t)[0], Mat4::from_scale(Vec3::splat(2.0)), "t = {t}");
    }
}

#[test]
fn step_holds_each_value_until_the_next_key() {
    let values = [1.0, 1.0, 1.0, 2.0, 2.0, 2.0, 3.0, 3.0, 3.0];
    let s = one_channel("step", "scale", "STEP", &[0.0, 1.0, 2.0], &values, [0.0; 3]);
    for (t, k) in [(0.0, 1.0), (0.5, 1.0), (0.999, 1.0), (1.0, 2.0), (1.5, 2.0), (1.999, 2.0), (2.0, 3.0), (5.0, 3.0)] {
        assert_eq!(s.instance_transforms(t)[0], Mat4::from_scale(Vec3::splat(k)), "t = {t}");
    }
}

/// Hermite basis at `s` over an interval of length `dt` (glTF Appendix C), in f64.
fn hermite(v0: f64, b0: f64, v1: f64, a1: f64, s: f64, dt: f64) -> f64 {
    let (s2, s3) = (s * s, s * s * s);
    (2.0 * s3 - 3.0 * s2 + 1.0) * v0 + dt * (s3 - 2.0 * s2 + s) * b0 + (-2.0 * s3 + 3.0 * s2) * v1 + dt * (s3 - s2) * a1
}

#[test]
fn cubic_spline_follows_the_hermite_formula() {
    // Keys at 1 s and 3 s (dt = 2), each (in-tangent, value, out-tangent).
    let (a0, v0, b0) = ([9.0, 9.0, 9.0], [0.0, 1.0, -1.0], [2.0, -1.0, 0.5]);
    let (a1, v1, b1) = ([-3.0, 0.5, 1.0], [4.0, 2.0, 1.0], [9.0, 9.0, 9.0]);
    let values: Vec<f32> = [a0, v0, b0, a1, v1, b1].concat();
    let s = one_channel("cubic", "translation", "CUBICSPLINE", &[1.0, 3.0], &values, [0.0; 3]);
    for t in [1.5f32, 2.0, 2.7] {
        let u = (f64::from(t) - 1.0) / 2.0;
        let e = Vec3::from_array(std::array::from_fn(|c| {
            hermite(v0[c].into(), b0[c].into(), v1[c].into(), a1[c].into(), u, 2.0) as f32
        }));
        let got = translation(&s.instance_transforms(t)[0]);
        assert!(close(got, e, 1e-5), "t = {t}: {got} != {e}");
    }
    // The tangents matter: at t = 1.5 the straight line would be (1, 1.25, -0.5).
    assert!(!close(translation(&s.instance_transforms(1.5)[0]), Vec3::new(1.0, 1.25, -0.5), 0.1));
    // At and beyond the keys: the values, never the tangents.
    assert_eq!(translation(&s.instance_transforms(1.0)[0]), Vec3::from(v0));
    assert_eq!(translation(&s.instance_transforms(0.0)[0]), Vec3::from(v0));
    assert_eq!(translation(&s.instance_transforms(3.0)[0]), Vec3::from(v1));
    assert_eq!(translation(&s.instance_transforms(9.0)[0]), Vec3::from(v1));

    // A CUBICSPLINE rotation is normalised: identity to 90° about Y, zero tangents,
    // stays a rotation (unit axes) half way.
    let h = FRAC_1_SQRT_2;
    let q: Vec<f32> = [[0.0; 4], [0.0, 0.0, 0.0, 1.0], [0.0; 4], [0.0; 4], [0.0, h, 0.0, h], [0.0; 4]].concat();
    let s = one_channel("cubic-rot", "rotation", "CUBICSPLINE", &[0.0, 1.0], &q, [0.0; 3]);
    let m = s.instance_transforms(0.5)[0];
    for axis in [m.x_axis, m.y_axis, m.z_axis] {
        assert!((axis.truncate().length() - 1.0).abs() < 1e-6, "{m}");
    }
    // Symmetric weights (1/2 each): the normalised sum is the 45° rotation.
    assert!(close(m.transform_vector3(Vec3::X), Vec3::new(h, 0.0, -h), 1e-6), "{m}");
}

#[test]
fn linear_rotation_slerps_90_degrees_about_y_to_45_at_half_time() {
    let h = FRAC_1_SQRT_2;
    let q = [0.0, 0.0, 0.0, 1.0, 0.0, h, 0.0, h];
    let s = one_channel("slerp", "rotation", "LINEAR", &[0.0, 1.0], &q, [0.0; 3]);
    let m = s.instance_transforms(0.5)[0];
    // Ry(45°) maps +X to (cos 45°, 0, -sin 45°).
    assert!(close(m.transform_vector3(Vec3::X), Vec3::new(h, 0.0, -h), 1e-6), "{m}");
    let (_, r, _) = m.to_scale_rotation_translation();
    assert!(r.angle_between(Quat::from_rotation_y(45f32.to_radians())) < 1e-3, "{r}");
    // A quarter of the way: 22.5°, as slerp (not a normalised lerp) has it.
    let m = s.instance_transforms(0.25)[0];
    let a = 22.5f32.to_radians();
    assert!(close(m.transform_vector3(Vec3::X), Vec3::new(a.cos(), 0.0, -a.sin()), 1e-6), "{m}");

    // The same keys as normalized shorts.
    let mut d = Doc::default();
    let meshes = d.quad_mesh();
    let input = d.floats(&[0.0, 1.0], "SCALAR");
    let qi: Vec<i16> = q.iter().map(|x| (x * 32767.0).round() as i16).collect();
    let output = d.shorts(&qi, true);
    let gltf = d.finish(json!({
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0}, light_node()],
        "meshes": meshes,
        "animations": [{"samplers": [sampler(input, output, "LINEAR")], "channels": [channel(0, 0, "rotation")]}],
    }));
    let s = load("slerp-i16", &gltf);
    assert_eq!(s.instances[0].name, "quad", "an unnamed node is named after its mesh");
    let m = s.instance_transforms(0.5)[0];
    assert!(close(m.transform_vector3(Vec3::X), Vec3::new(h, 0.0, -h), 1e-4), "{m}");
}

// ---------------------------------------------------------------------------------
// The model: instances, static triangles, lights, camera, freezing, bounds.

/// Nodes: 0 static quad at x = -3; 1 "arm" (no mesh) translated by a channel, with
/// child 2 "hand" (mesh, rest translation (0,1,0)), whose child 3 "finger" (mesh) has
/// its own scale channel that mirrors it on the way; 4 the light; 5 an animated
/// camera, child of nothing; 6 a second static quad, after the animated ones in
/// the walk.
fn rig_gltf() -> String {
    let mut d = Doc::default();
    let meshes = d.quad_mesh();
    let t = d.floats(&[0.0, 1.0, 2.0], "SCALAR");
    let arm = d.floats(&[0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 2.0, 2.0, 0.0], "VEC3");
    let finger = d.floats(&[1.0, 1.0, 1.0, -1.0, 1.0, 1.0, -2.0, 0.5, 1.0], "VEC3");
    let h = FRAC_1_SQRT_2;
    let yaw = d.floats(&[0.0, 0.0, 0.0, 1.0, 0.0, h, 0.0, h], "VEC4");
    let lamp = d.floats(&[0.0, 1.0, 0.0, 4.0, 1.0, 0.0], "VEC3");
    let t2 = d.floats(&[0.0, 2.0], "SCALAR");
    d.finish(json!({
        "scenes": [{"nodes": [0, 1, 4, 5, 6]}],
        "nodes": [
            {"name": "static", "mesh": 0, "translation": [-3, 0, 0]},
            {"name": "arm", "children": [2]},
            {"name": "hand", "mesh": 0, "translation": [0, 1, 0], "children": [3]},
            {"name": "finger", "mesh": 0, "translation": [0, 0, 1]},
            {"name": "lamp", "translation": [0, 1, 0], "extensions": {"KHR_lights_punctual": {"light": 0}},
             "children": [7]},
            {"name": "eye", "camera": 0, "translation": [0, 1, 10]},
            {"name": "static 2", "mesh": 0, "translation": [3, 0, 0], "scale": [1, 2, 1]},
            {"name": "sun", "extensions": {"KHR_lights_punctual": {"light": 1}}},
        ],
        "meshes": meshes,
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"name": "point", "type": "point", "intensity": 3},
            {"name": "sun", "type": "directional", "intensity": 2},
        ]}},
        "animations": [
            {"name": "arm", "samplers": [sampler(t, arm, "LINEAR"), sampler(t, finger, "LINEAR")],
             "channels": [channel(0, 1, "translation"), channel(1, 3, "scale")]},
            // A second animation on the same clock: the lamp (and the sun under it)
            // and the camera.
            {"name": "lamp and eye", "samplers": [sampler(t2, lamp, "LINEAR"), sampler(t2, yaw, "LINEAR")],
             "channels": [channel(0, 4, "translation"), channel(1, 4, "rotation"), channel(1, 5, "rotation")]},
        ],
    }))
}

#[test]
fn animated_parent_makes_its_mesh_descendants_instances() {
    let s = load("rig", &rig_gltf());
    assert_eq!(s.duration(), 2.0, "all animations share one clock");
    let names: Vec<&str> = s.instances.iter().map(|i| i.name.as_str()).collect();
    assert_eq!(names, ["hand", "finger"]);
    // Static triangles first, in walk order: "static" then "static 2".
    assert_eq!(s.static_triangle_count(), 4);
    assert_eq!(s.triangle_count(), 8);
    assert_eq!((s.instances[0].first_triangle, s.instances[1].first_triangle), (4, 6));
    assert_eq!(s.instances[1].triangles(), 6..8);
    assert_eq!(s.triangle_material.len(), 8);
    assert_eq!(s.vertices[0].position, [-3.5, -0.5, 0.0]);
    assert_eq!(s.vertices[6].position, [2.5, -1.0, 0.0]);
    // Static geometry never moves: the same at any time.
    for t in [0.0, 1.3, 5.0] {
        let f = s.frozen_at(t);
        assert_eq!(bits(&f.vertices[..12]), bits(&s.vertices[..12]));
    }
    // hand = arm(t) · T(0,1,0); finger = hand · T(0,0,1) · S(t).
    let m = s.instance_transforms(0.5);
    assert!(close(translation(&m[0]), Vec3::new(1.0, 1.0, 0.0), 1e-6));
    assert!(close(m[1].transform_point3(Vec3::new(0.5, 0.5, 0.0)), Vec3::new(1.0, 1.5, 1.0), 1e-6));
    let m = s.instance_transforms(1.5);
    assert!(close(translation(&m[0]), Vec3::new(2.0, 2.0, 0.0), 1e-6));
    // S(1.5) = (-1.5, 0.75, 1): (0.5, 0.5, 0) → (-0.75, 0.375, 0) → + (2, 2, 1).
    assert!(close(m[1].transform_point3(Vec3::new(0.5, 0.5, 0.0)), Vec3::new(1.25, 2.375, 1.0), 1e-6), "{}", m[1]);
    // t = 0 vertices are the instances placed by the public function.
    let m0 = s.instance_transforms(0.0);
    for (i, inst) in s.instances.iter().enumerate() {
        let r = inst.triangles();
        assert_eq!(bits(&s.vertices[r.start * 3..r.end * 3]), bits(&s.instance_world_vertices(i, &m0[i])));
    }
}

/// A moving part is never a coplanar neighbour of another part: a quad that an animation moves,
/// placed at t = 0 edge to edge with a static quad in the same plane, keeps only its own
/// diagonal linked, as does the static one; without the animation the shared edge links them.
#[test]
fn coplanar_neighbours_stay_within_a_rigid_part() {
    let links = |animated: bool| {
        let mut d = Doc::default();
        let meshes = d.quad_mesh();
        let (input, output) = (d.floats(&[0.0, 1.0], "SCALAR"), d.floats(&[0.0, 0.0, 0.0, 0.0, 0.0, 1.0], "VEC3"));
        let mut root = json!({
            "scenes": [{"nodes": [0, 1, 2]}],
            "nodes": [{"name": "mover", "mesh": 0}, {"name": "wall", "mesh": 0, "translation": [1.0, 0.0, 0.0]}, light_node()],
            "meshes": meshes,
        });
        if animated {
            root["animations"] =
                json!([{"samplers": [sampler(input, output, "LINEAR")], "channels": [channel(0, 0, "translation")]}]);
        }
        let s = load(if animated { "coplanar_moving" } else { "coplanar_static" }, &d.finish(root));
        assert_eq!(s.triangle_count(), 4);
        assert_eq!(s.static_triangle_count(), if animated { 2 } else { 4 });
        // The two quads share the edge x = 0.5 (at t = 0).
        let on_edge = |t: usize| s.vertices[3 * t..3 * t + 3].iter().filter(|v| v.position[0] == 0.5).count();
        assert_eq!((0..4).map(on_edge).sum::<usize>(), 6);
        let neighbours = s.coplanar_neighbours();
        (0..4)
            .map(|t| neighbours[t].iter().copied().filter(|&n| n != leakless_scene::NO_NEIGHBOUR).count())
            .collect::<Vec<_>>()
    };
    assert_eq!(links(true), [1, 1, 1, 1], "each triangle only its quad-mate");
    // In walk order, the mover's triangles then the wall's; the first and last hold the edge.
    assert_eq!(links(false), [2, 1, 1, 2], "and the shared edge when nothing moves");
}

#[test]
fn mirroring_keys_keep_winding_and_normals_agreeing() {
    let s = load("mirror", &rig_gltf());
    // (At 0.5 s the finger's x scale passes through 0: no winding there.)
    for t in [0.0, 0.25, 0.75, 1.0, 1.5, 2.0] {
        let m = s.instance_transforms(t)[1];
        let v = s.instance_world_vertices(1, &m);
        for tri in v.chunks_exact(3) {
            let p: Vec<Vec3> = tri.iter().map(|v| Vec3::from(v.position)).collect();
            let face = (p[1] - p[0]).cross(p[2] - p[0]);
            for v in tri {
                let n = Vec3::from(v.normal);
                assert!((n.length() - 1.0).abs() < 1e-6);
                assert!(face.dot(n) > 0.0, "t = {t}: winding disagrees with normal {n} (det {})", m.determinant());
            }
        }
    }
    // From 0.5 s on the finger is mirrored (scale x < 0): its second and third
    // vertices are swapped relative to the mesh.
    let m = s.instance_transforms(1.0)[1];
    assert!(m.determinant() < 0.0);
    let v = s.instance_world_vertices(1, &m);
    let local = &s.instances[1].local_vertices;
    assert_eq!((v[1].uv, v[2].uv), (local[2].uv, local[1].uv));
}

#[test]
fn lights_and_camera_follow_their_nodes() {
    let s = load("lamp", &rig_gltf());
    assert_eq!(s.lights_at(0.0), s.lights);
    assert_eq!(s.camera_at(0.0), s.camera);
    let h = FRAC_1_SQRT_2;
    let at = |t: f32| {
        let l = s.lights_at(t);
        assert_eq!(l.len(), 2);
        let point = l.iter().find(|l| l.name == "point").unwrap().clone();
        let sun = l.iter().find(|l| l.name == "sun").unwrap().clone();
        assert_eq!((point.kind, sun.kind), (LightKind::Point, LightKind::Directional));
        (point, sun)
    };
    let (point, sun) = at(1.0);
    assert!(close(point.position, Vec3::new(2.0, 1.0, 0.0), 1e-6), "{}", point.position);
    // The sun is a child of the lamp: it turns with it (45° about Y at 1 s).
    let a = 45f32.to_radians();
    assert!(close(sun.direction, Vec3::new(-a.sin(), 0.0, -a.cos()), 1e-6), "{}", sun.direction);
    let (point, sun) = at(3.0);
    assert!(close(point.position, Vec3::new(4.0, 1.0, 0.0), 1e-6));
    assert!(close(sun.direction, Vec3::NEG_X, 1e-6), "{}", sun.direction);
    assert_eq!(sun.intensity, 2.0, "only placement changes");

    // The camera turns 90° about +Y over 2 s: its forward goes from -Z to -X.
    let c0 = s.camera.clone().unwrap();
    assert!(close(c0.forward(), Vec3::NEG_Z, 1e-6));
    let c = s.camera_at(1.0).unwrap();
    assert!(close(c.forward(), Vec3::new(-h, 0.0, -h), 1e-6), "{}", c.forward());
    assert!(close(c.position(), Vec3::new(0.0, 1.0, 10.0), 1e-6));
    assert_eq!((c.yfov, c.znear, c.zfar), (c0.yfov, c0.znear, c0.zfar));
    assert!(close(s.camera_at(2.0).unwrap().forward(), Vec3::NEG_X, 1e-6));
}

#[test]
fn frozen_at_is_the_animation_played_to_that_time_bit_for_bit() {
    let s = load("frozen", &rig_gltf());
    let f0 = s.frozen_at(0.0);
    assert_eq!(bits(&f0.vertices), bits(&s.vertices), "the load path places instances with the public function");
    for t in [0.0, 0.25, 0.5, 1.0, 1.7, 2.0, 9.0] {
        let f = s.frozen_at(t);
        assert!(!f.is_animated());
        assert_eq!(f.duration(), 0.0);
        assert_eq!(f.instances.len(), s.instances.len());
        assert_eq!(f.static_triangle_count(), s.static_triangle_count());
        assert_eq!(f.triangle_material, s.triangle_material);
        let m = s.instance_transforms(t);
        assert_eq!(f.instance_transforms(0.0), m, "t = {t}: frozen transforms");
        assert_eq!(f.instance_transforms(123.0), m, "t = {t}: frozen at any time");
        for (i, inst) in f.instances.iter().enumerate() {
            assert_eq!(
                (inst.first_triangle, inst.triangle_count),
                (s.instances[i].first_triangle, s.instances[i].triangle_count)
            );
            assert_eq!(bits(&inst.local_vertices), bits(&s.instances[i].local_vertices));
            let r = inst.triangles();
            let played = s.instance_world_vertices(i, &m[i]);
            assert_eq!(bits(&f.vertices[r.start * 3..r.end * 3]), bits(&played), "t = {t}, instance {i}");
            assert_eq!(bits(&f.instance_world_vertices(i, &f.instance_transforms(0.0)[i])), bits(&played));
        }
        assert_eq!(f.lights, s.lights_at(t));
        assert_eq!(f.lights_at(0.0), f.lights);
        assert_eq!(f.camera, s.camera_at(t));
        assert_eq!(f.camera_at(5.0), f.camera);
        // What is derived from the bounds must not depend on how t was reached.
        assert_eq!((f.bounds(), f.animated_bounds()), (s.bounds(), s.animated_bounds()));
        assert_eq!(bits(&f.frozen_at(0.0).vertices), bits(&f.vertices), "freezing again changes nothing");
    }
}

#[test]
fn animated_bounds_cover_the_motion() {
    let s = one_channel("bounds", "translation", "LINEAR", &[0.0, 1.0], &[0.0, 0.0, 0.0, 10.0, 0.0, 0.0], [0.0; 3]);
    let b = s.bounds();
    assert_eq!((b.min.x, b.max.x), (-0.5, 0.5), "bounds are the t = 0 pose");
    let a = s.animated_bounds();
    assert_eq!((a.min.x, a.max.x), (-0.5, 10.5));
    assert_eq!((a.min.y, a.max.y), (-0.5, 0.5));
    let s = load("bounds-rig", &rig_gltf());
    let a = s.animated_bounds();
    for t in [0.0, 0.3, 1.0, 1.5, 2.0] {
        for v in &s.frozen_at(t).vertices {
            assert!(a.contains(Vec3::from(v.position)), "t = {t}: {:?} outside {a:?}", v.position);
        }
    }
}

#[test]
fn scenes_without_animation_are_unchanged() {
    for rel in ["scenes/cornell-box.gltf", "tests/scenes/spot-sun.gltf"] {
        let s = Scene::load(&repo(rel)).unwrap();
        assert!(!s.is_animated() && s.instances.is_empty(), "{rel}");
        assert_eq!(s.duration(), 0.0);
        assert_eq!(s.static_triangle_count(), s.triangle_count());
        assert!(s.instance_transforms(1.0).is_empty());
        assert_eq!(s.lights_at(3.0), s.lights);
        assert_eq!(s.camera_at(3.0), s.camera);
        assert_eq!(s.animated_bounds(), s.bounds());
        let f = s.frozen_at(2.0);
        assert_eq!(bits(&f.vertices), bits(&s.vertices));
        assert_eq!((f.lights, f.camera, f.warnings), (s.lights.clone(), s.camera.clone(), s.warnings.clone()));
    }
    // An animation that moves only a light leaves every triangle static, in the
    // same order and bit for bit as without it.
    let scene = |animated: bool| {
        let mut d = Doc::default();
        let meshes = d.quad_mesh();
        let t = d.floats(&[0.0, 1.0], "SCALAR");
        let v = d.floats(&[0.0, 0.0, 5.0, 1.0, 0.0, 5.0], "VEC3");
        let mut root = json!({
            "scenes": [{"nodes": [0, 1, 2]}],
            "nodes": [
                {"mesh": 0, "rotation": [0.0, 0.38268343, 0.0, 0.9238795], "scale": [1, -2, 1]},
                light_node(),
                {"mesh": 0, "translation": [0, 0, -1]},
            ],
            "meshes": meshes,
        });
        if animated {
            root["animations"] =
                json!([{"samplers": [sampler(t, v, "LINEAR")], "channels": [channel(0, 1, "translation")]}]);
        }
        load(if animated { "light-only" } else { "light-only-static" }, &d.finish(root))
    };
    let (a, b) = (scene(true), scene(false));
    assert!(a.is_animated() && a.instances.is_empty() && !b.is_animated());
    assert_eq!(bits(&a.vertices), bits(&b.vertices));
    assert_eq!(a.lights, b.lights);
    assert_eq!(a.warnings, b.warnings);
    assert!(close(a.lights_at(0.5)[0].position, Vec3::new(0.5, 0.0, 5.0), 1e-6));
}

#[test]
fn skins_morph_targets_and_weights_stay_ignored() {
    let mut d = Doc::default();
    let mut meshes = d.quad_mesh();
    let displacement = d.floats(&[0.0, 0.0, 1.0].repeat(6), "VEC3");
    let pos = meshes[0]["primitives"][0]["attributes"]["POSITION"].clone();
    meshes.as_array_mut().unwrap().push(json!({"primitives": [{"attributes": {"POSITION": pos},
        "targets": [{"POSITION": displacement}]}], "weights": [0.0]}));
    let t = d.floats(&[0.0, 1.0], "SCALAR");
    let w = d.floats(&[0.0, 1.0], "SCALAR");
    let gltf = d.finish(json!({
        "scenes": [{"nodes": [0, 1, 2]}],
        "nodes": [{"mesh": 1}, light_node(), {"name": "joint"}],
        "skins": [{"joints": [2]}],
        "meshes": meshes,
        "animations": [{"samplers": [sampler(t, w, "LINEAR")],
                        "channels": [channel(0, 0, "weights"), channel(0, 2, "no such path")]}],
    }));
    let s = load("ignored", &gltf);
    let line = &s.warnings[0];
    for item in ["1 skin", "morph targets", "animated morph target weights", "animation channels with unknown paths"] {
        assert!(line.starts_with("ignored: ") && line.contains(item), "{item}: {line}");
    }
    assert!(!line.contains("animation,") && !line.contains("1 animation"), "{line}");
    assert!(!s.is_animated() && s.instances.is_empty(), "nothing left to play");
    assert_eq!(s.duration(), 0.0);
}

// ---------------------------------------------------------------------------------
// Errors.

/// Accessors of the file `channel_error` builds: the quad's are 0 to 2.
const INPUT: usize = 3;
const OUTPUT: usize = 4;

/// Loads a one-channel file whose sampler/channel JSON is altered by `edit`, and
/// returns the error's single line (after checking it is one).
fn channel_error(test: &str, edit: impl FnOnce(&mut Doc, &mut Value)) -> (SceneError, String) {
    let mut d = Doc::default();
    let meshes = d.quad_mesh();
    let input = d.floats(&[0.0, 1.0, 2.0], "SCALAR");
    let output = d.floats(&[1.0; 9], "VEC3");
    assert_eq!((input, output), (INPUT, OUTPUT));
    let mut root = json!({
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"name": "mover", "mesh": 0}, light_node(), {"name": "fixed", "matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]}],
        "meshes": meshes,
        "animations": [
            {"name": "fine", "samplers": [sampler(input, output, "LINEAR")], "channels": [channel(0, 0, "scale")]},
            {"name": "bad", "samplers": [sampler(input, output, "LINEAR")],
             "channels": [channel(0, 0, "translation"), channel(0, 0, "scale")]},
        ],
    });
    edit(&mut d, &mut root);
    let e = match try_load(test, &d.finish(root)) {
        Ok(_) => panic!("{test}: loaded"),
        Err(e) => e,
    };
    let line = e.to_string();
    assert!(!line.is_empty() && !line.contains('\n'), "{line:?}");
    assert!(line.contains(&format!("{test}.gltf")), "names the file: {line}");
    (e, line)
}

/// The second channel of animation 1 ('bad').
fn bad(root: &mut Value) -> &mut Value {
    &mut root["animations"][1]
}

#[test]
fn bad_channels_are_one_line_errors() {
    let expect_animation = |e: &SceneError, line: &str, what: &str| {
        assert!(matches!(e, SceneError::Animation { .. }), "{e:?}");
        assert!(line.contains("animation 1 'bad', channel 1: "), "names animation and channel: {line}");
        assert!(line.contains(what), "{what}: {line}");
    };

    let (e, l) = channel_error("non-increasing", |d, r| {
        let input = d.floats(&[0.0, 1.0, 1.0], "SCALAR");
        bad(r)["samplers"] = json!([sampler(INPUT, OUTPUT, "LINEAR"), {"input": input, "output": OUTPUT}]);
        bad(r)["channels"][1]["sampler"] = json!(1);
    });
    expect_animation(&e, &l, "not strictly increasing (key 1 at 1 s, key 2 at 1 s)");

    let (e, l) = channel_error("decreasing", |d, r| {
        let input = d.floats(&[0.0, 2.0, 1.0], "SCALAR");
        bad(r)["samplers"] = json!([sampler(INPUT, OUTPUT, "LINEAR"), {"input": input, "output": OUTPUT}]);
        bad(r)["channels"][1]["sampler"] = json!(1);
    });
    expect_animation(&e, &l, "not strictly increasing");

    let (e, l) = channel_error("nan-time", |d, r| {
        let input = d.floats(&[0.0, f32::NAN, 2.0], "SCALAR");
        d.accessors[input]["min"] = json!([0.0]);
        d.accessors[input]["max"] = json!([2.0]);
        bad(r)["samplers"] = json!([sampler(INPUT, OUTPUT, "LINEAR"), {"input": input, "output": OUTPUT}]);
        bad(r)["channels"][1]["sampler"] = json!(1);
    });
    expect_animation(&e, &l, "input time 1 is NaN, not finite");

    let (e, l) = channel_error("short-output", |d, r| {
        let output = d.floats(&[0.0; 6], "VEC3");
        bad(r)["samplers"] = json!([sampler(INPUT, OUTPUT, "LINEAR"), sampler(INPUT, output, "LINEAR")]);
        bad(r)["channels"][1]["sampler"] = json!(1);
    });
    expect_animation(&e, &l, "has 2 elements for 3 keys, expected 3");

    let (e, l) = channel_error("cubic-count", |_, r| {
        bad(r)["samplers"] = json!([sampler(INPUT, OUTPUT, "LINEAR"), sampler(INPUT, OUTPUT, "CUBICSPLINE")]);
        bad(r)["channels"][1]["sampler"] = json!(1);
    });
    expect_animation(&e, &l, "expected 9 (CUBICSPLINE: 3 per key)");

    let (e, l) = channel_error("missing-node", |_, r| bad(r)["channels"][1]["target"]["node"] = json!(7));
    expect_animation(&e, &l, "target node 7 does not exist (3 nodes)");

    let (e, l) = channel_error("matrix-node", |_, r| bad(r)["channels"][1]["target"]["node"] = json!(2));
    expect_animation(&e, &l, "target node 2 has a matrix");

    let (e, l) = channel_error("vec4-translation", |d, r| {
        let output = d.floats(&[0.0; 12], "VEC4");
        bad(r)["samplers"] = json!([sampler(INPUT, OUTPUT, "LINEAR"), sampler(INPUT, output, "LINEAR")]);
        bad(r)["channels"][1]["sampler"] = json!(1);
    });
    expect_animation(&e, &l, "which a Scale channel cannot use");

    let (e, l) = channel_error("raw-short-rotation", |d, r| {
        let output = d.shorts(&[0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1], false);
        bad(r)["samplers"] = json!([sampler(INPUT, OUTPUT, "LINEAR"), sampler(INPUT, output, "LINEAR")]);
        bad(r)["channels"][1] = channel(1, 0, "rotation");
    });
    expect_animation(&e, &l, "is Vec4 of I16, which a Rotation channel cannot use");

    let (e, l) = channel_error("output-past-buffer", |d, r| {
        let view = d.view(&[0u8; 8]);
        let output = d.accessor(json!({"bufferView": view, "componentType": 5126, "count": 3, "type": "VEC3"}));
        bad(r)["samplers"] = json!([sampler(INPUT, OUTPUT, "LINEAR"), sampler(INPUT, output, "LINEAR")]);
        bad(r)["channels"][1]["sampler"] = json!(1);
    });
    expect_animation(&e, &l, "overrun view");

    let (e, l) = channel_error("non-finite-output", |d, r| {
        let output = d.floats(&[0.0, 0.0, 0.0, 1.0, f32::INFINITY, 0.0, 0.0, 0.0, 0.0], "VEC3");
        bad(r)["samplers"] = json!([sampler(INPUT, OUTPUT, "LINEAR"), sampler(INPUT, output, "LINEAR")]);
        bad(r)["channels"][1]["sampler"] = json!(1);
    });
    expect_animation(&e, &l, "output element 1 has a non-finite component");

    // Dangling sampler indices are caught by glTF validation (one line too).
    let (e, l) = channel_error("missing-sampler", |_, r| bad(r)["channels"][1]["sampler"] = json!(5));
    assert!(matches!(e, SceneError::Malformed { .. }), "{e:?}");
    assert!(l.contains("animations[1].channels[1].sampler"), "{l}");
    let (e, _) = channel_error("bad-interpolation", |_, r| bad(r)["samplers"][0]["interpolation"] = json!("SMOOTH"));
    assert!(matches!(e, SceneError::Malformed { .. }), "{e:?}");
}

// ---------------------------------------------------------------------------------
// The repository's animated scenes.

fn extra(s: &Scene, key: &str) -> Value {
    let extras: Value = serde_json::from_str(s.extras.as_deref().expect("scene extras")).unwrap();
    extras[key].clone()
}

fn vec3(v: &Value) -> Vec3 {
    Vec3::from_array(std::array::from_fn(|i| v[i].as_f64().unwrap() as f32))
}

#[test]
fn moving_light_walks_through_the_doorway() {
    let s = Scene::load(&repo("scenes/moving-light.gltf")).unwrap();
    assert!(s.is_animated() && s.instances.is_empty(), "only the light moves");
    assert!(!s.warnings.iter().any(|w| w.contains("animation")), "{:?}", s.warnings);
    let times = extra(&s, "light_times");
    let positions = extra(&s, "light_positions");
    for (t, p) in times.as_array().unwrap().iter().zip(positions.as_array().unwrap()) {
        let t = t.as_f64().unwrap() as f32;
        let l = &s.lights_at(t)[0];
        assert!(close(l.position, vec3(p), 1e-5), "t = {t}: {} != {p}", l.position);
    }
    assert_eq!(s.duration(), times[times.as_array().unwrap().len() - 1].as_f64().unwrap() as f32);
    // At t = 0 it is doorway.gltf.
    let same = extra(&s, "same_at_time_0");
    let d = Scene::load(&repo(same.as_str().unwrap())).unwrap();
    assert_eq!(bits(&s.vertices), bits(&d.vertices));
    assert_eq!((s.lights_at(0.0), s.camera.clone()), (d.lights.clone(), d.camera.clone()));
}

#[test]
fn door_swings_shut_and_stays_shut() {
    let s = Scene::load(&repo("scenes/door.gltf")).unwrap();
    assert!(s.is_animated());
    let names: Vec<&str> = s.instances.iter().map(|i| i.name.as_str()).collect();
    assert_eq!(names, ["door leaf", "door handle", "door bolt"]);
    let closed = extra(&s, "closed_time").as_f64().unwrap() as f32;
    let hinge = vec3(&extra(&s, "hinge"));
    // Closed: the leaf's rotation is the identity, so its transform is the hinge
    // translation, and stays so.
    for t in [closed, closed + 1.0, 100.0] {
        let m = s.instance_transforms(t)[0];
        assert!(m.abs_diff_eq(Mat4::from_translation(hinge), 1e-6), "t = {t}: {m}");
    }
    // Open at t = 0: -90° about +Y.
    let m = s.instance_transforms(0.0)[0];
    assert!(close(m.transform_vector3(Vec3::X), Vec3::Z, 1e-6), "{m}");
    // Closed, the leaf lies in `leaf_closed_min/max`.
    let (lo, hi) = (vec3(&extra(&s, "leaf_closed_min")), vec3(&extra(&s, "leaf_closed_max")));
    let f = s.frozen_at(closed);
    let leaf = s.instances[0].triangles();
    for v in &f.vertices[leaf.start * 3..leaf.end * 3] {
        let p = Vec3::from(v.position);
        assert!(p.cmpge(lo - 1e-5).all() && p.cmple(hi + 1e-5).all(), "{p} outside {lo}..{hi}");
    }
    let a = s.animated_bounds();
    for t in [0.0, 0.5, 1.0, 1.7, closed] {
        for v in &s.frozen_at(t).vertices {
            assert!(a.contains(Vec3::from(v.position)), "t = {t}");
        }
    }
}
