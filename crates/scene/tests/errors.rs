//! Bad input gives one clear error, never a panic.

use std::path::{Path, PathBuf};

use leakless_scene::{Scene, SceneError};
use rand_core::{RngCore, SeedableRng};

mod scratch;
use scratch::Scratch;

fn repo(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..").join(rel)
}

fn scratch(test: &str) -> Scratch {
    scratch::scratch("", test)
}

fn load_bytes(dir: &Path, name: &str, bytes: &[u8]) -> Result<Scene, SceneError> {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    Scene::load(&path)
}

/// Checks the error renders as one line and returns it.
fn one_line(e: &SceneError) -> String {
    let s = e.to_string();
    assert!(!s.contains('\n') && !s.is_empty(), "{s:?}");
    s
}

#[test]
fn missing_file_names_the_path() {
    let e = Scene::load(Path::new("no/such/scene.gltf")).unwrap_err();
    assert!(matches!(e, SceneError::NotFound { .. }), "{e:?}");
    assert!(one_line(&e).contains("no/such/scene.gltf"));
}

#[test]
fn directory_is_unreadable() {
    let e = Scene::load(&repo("tests/scenes")).unwrap_err();
    assert!(matches!(e, SceneError::Read { .. }), "{e:?}");
    one_line(&e);
}

#[test]
fn no_light_is_refused_with_advice() {
    let e = Scene::load(&repo("tests/scenes/no-light.gltf")).unwrap_err();
    assert!(matches!(e, SceneError::NoLight { .. }), "{e:?}");
    assert_eq!(one_line(&e), "scene no-light has no light: add a KHR_lights_punctual light or an emissive material");
}

#[test]
fn malformed_json_is_malformed() {
    let e = Scene::load(&repo("tests/scenes/malformed.gltf")).unwrap_err();
    assert!(matches!(e, SceneError::Malformed { .. }), "{e:?}");
    assert!(one_line(&e).contains("malformed.gltf"));
}

#[test]
fn truncated_glb_is_malformed() {
    let e = Scene::load(&repo("tests/scenes/truncated.glb")).unwrap_err();
    assert!(matches!(e, SceneError::Malformed { .. }), "{e:?}");
    one_line(&e);
}

#[test]
fn every_prefix_of_a_glb_fails_cleanly() {
    let glb = std::fs::read(repo("tests/scenes/textured.glb")).unwrap();
    let dir = scratch("prefix");
    for len in 0..glb.len() {
        let r = load_bytes(&dir, "cut.glb", &glb[..len]);
        assert!(r.is_err(), "a {len}-byte prefix loaded");
    }
    assert!(load_bytes(&dir, "whole.glb", &glb).is_ok());
}

#[test]
fn random_bytes_and_mutations_never_panic() {
    let dir = scratch("fuzz");
    // A seeded PCG (rand_pcg), so a failure reproduces.
    let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(0x9E37_79B9_7F4A_7C15);
    for n in [0usize, 1, 4, 12, 20, 100, 4096] {
        let bytes: Vec<u8> = (0..n).map(|_| rng.next_u64() as u8).collect();
        assert!(load_bytes(&dir, "random.gltf", &bytes).is_err());
        let mut glb = b"glTF".to_vec();
        glb.extend(&bytes);
        let _ = load_bytes(&dir, "random.glb", &glb);
    }
    // Mutations of valid files: any outcome but a panic. Half of them change only
    // digits, which keeps the JSON parseable and so reaches validation and the
    // loader with wrong indices, counts, offsets and enum values.
    // LEAKLESS_FUZZ_ITERATIONS=100000 runs a longer search locally.
    let iterations: usize = std::env::var("LEAKLESS_FUZZ_ITERATIONS").ok().and_then(|v| v.parse().ok()).unwrap_or(400);
    for name in ["tests/scenes/textured.glb", "tests/scenes/floor-light.gltf", "tests/scenes/no-light.gltf"] {
        let good = std::fs::read(repo(name)).unwrap();
        let digits: Vec<usize> = (0..good.len()).filter(|&i| good[i].is_ascii_digit()).collect();
        for k in 0..iterations {
            let mut bad = good.clone();
            for _ in 0..1 + rng.next_u64() % 3 {
                if k % 2 == 0 {
                    let at = digits[(rng.next_u64() % digits.len() as u64) as usize];
                    bad[at] = b'0' + (rng.next_u64() % 10) as u8;
                } else {
                    let at = (rng.next_u64() % bad.len() as u64) as usize;
                    bad[at] = rng.next_u64() as u8;
                }
            }
            if let Err(e) = load_bytes(&dir, "mutated.glb", &bad) {
                one_line(&e);
            }
        }
    }
}

/// A minimal scene: one triangle (positions in an external .bin), one point light.
/// `patch` edits the JSON text before it is written.
fn triangle_scene(dir: &Path, positions: [[f32; 3]; 3], patch: impl Fn(String) -> String) -> Result<Scene, SceneError> {
    let bin: Vec<u8> = positions.iter().flatten().flat_map(|f| f.to_le_bytes()).collect();
    std::fs::write(dir.join("tri.bin"), &bin).unwrap();
    let json = r#"{
 "asset": {"version": "2.0"},
 "extensionsUsed": ["KHR_lights_punctual"],
 "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point"}]}},
 "scene": 0,
 "scenes": [{"nodes": [0, 1]}],
 "nodes": [{"mesh": 0, "scale": [1, 1, 1]}, {"extensions": {"KHR_lights_punctual": {"light": 0}}, "translation": [0, 0, 1]}],
 "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
 "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}],
 "bufferViews": [{"buffer": 0, "byteLength": 36}],
 "buffers": [{"byteLength": 36, "uri": "tri.bin"}]
}"#;
    load_bytes(dir, "tri.gltf", patch(json.to_string()).as_bytes())
}

/// The start of node 0 in [`triangle_scene`]'s JSON, to splice things in.
const NODE0: &str = "\"nodes\": [{\"mesh\": 0,";

const TRI: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

#[test]
fn minimal_scene_loads_with_defaults() {
    let dir = scratch("minimal");
    let s = triangle_scene(&dir, TRI, |j| j).unwrap();
    assert_eq!(s.triangle_count(), 1);
    // No material in the file: the white 0.8 default.
    assert_eq!(s.materials.len(), 1);
    assert_eq!(s.materials[0].base_color, glam::Vec4::new(0.8, 0.8, 0.8, 1.0));
    // No normals: the flat face normal (counter-clockwise seen from +Z).
    assert!(s.vertices.iter().all(|v| v.normal == [0.0, 0.0, 1.0]));
    assert_eq!(s.lights[0].intensity, 1.0);
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
}

#[test]
fn missing_buffer_file_is_a_buffer_error() {
    let dir = scratch("nobin");
    let e = triangle_scene(&dir, TRI, |j| j.replace("\"tri.bin\"", "\"gone.bin\"")).unwrap_err();
    assert!(matches!(e, SceneError::Buffer { .. }), "{e:?}");
    assert!(one_line(&e).contains("gone.bin"));
}

#[test]
fn short_buffer_is_a_buffer_error() {
    let dir = scratch("short");
    let e = triangle_scene(&dir, TRI, |j| j.replace("\"byteLength\": 36, \"uri\"", "\"byteLength\": 48, \"uri\""))
        .unwrap_err();
    assert!(matches!(e, SceneError::Buffer { .. }), "{e:?}");
}

#[test]
fn accessor_past_its_view_is_a_buffer_error() {
    let dir = scratch("overrun");
    let e = triangle_scene(&dir, TRI, |j| j.replace("\"count\": 3", "\"count\": 4")).unwrap_err();
    assert!(matches!(e, SceneError::Buffer { .. }), "{e:?}");
    let e = triangle_scene(&dir, TRI, |j| j.replace("\"count\": 3", "\"count\": 0")).unwrap_err();
    assert!(matches!(e, SceneError::Malformed { .. } | SceneError::NoTriangles { .. }), "{e:?}");
}

#[test]
fn non_finite_positions_are_refused() {
    let dir = scratch("nonfinite");
    let nan = [[0.0, f32::NAN, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let e = triangle_scene(&dir, nan, |j| j).unwrap_err();
    assert!(matches!(e, SceneError::NonFinitePosition { .. }), "{e:?}");
    // Finite in the file, infinite after the node transform.
    let big = [[0.0, 0.0, 0.0], [3e38, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let e = triangle_scene(&dir, big, |j| j.replace("\"scale\": [1, 1, 1]", "\"scale\": [10, 1, 1]")).unwrap_err();
    assert!(matches!(e, SceneError::NonFinitePosition { .. }), "{e:?}");
}

#[test]
fn no_triangles_is_refused() {
    let dir = scratch("points");
    let e =
        triangle_scene(&dir, TRI, |j| j.replace("{\"POSITION\": 0}", "{\"POSITION\": 0}, \"mode\": 0")).unwrap_err();
    assert!(matches!(e, SceneError::NoTriangles { .. }), "{e:?}");
    assert_eq!(one_line(&e), "scene tri has no triangles");
}

#[test]
fn unsupported_required_extension_is_refused() {
    let dir = scratch("required");
    let e = triangle_scene(&dir, TRI, |j| {
        j.replace("\"extensionsUsed\"", "\"extensionsRequired\": [\"KHR_draco_mesh_compression\"], \"extensionsUsed\"")
    })
    .unwrap_err();
    assert!(matches!(e, SceneError::Unsupported { .. }), "{e:?}");
    assert!(one_line(&e).contains("KHR_draco_mesh_compression"));
    // A required material extension only changes looks: loaded, and reported.
    let s = triangle_scene(&dir, TRI, |j| {
        j.replace(
            "\"extensionsUsed\": [",
            "\"extensionsRequired\": [\"KHR_materials_unlit\"], \"extensionsUsed\": [\"KHR_materials_unlit\", ",
        )
    })
    .unwrap();
    assert_eq!(s.warnings, vec!["ignored: KHR_materials_unlit".to_string()]);
}

#[test]
fn hostile_structure_never_panics() {
    let dir = scratch("hostile");
    let cases: &[(&str, &str)] = &[
        // A node that is its own child (a cycle).
        ("\"scale\": [1, 1, 1]}", "\"scale\": [1, 1, 1], \"children\": [0]}"),
        // A perspective camera without its perspective object (gltf's own
        // `Camera::projection` unwraps it).
        (NODE0, "\"cameras\": [{\"type\": \"perspective\", \"orthographic\": {\"xmag\": 1, \"ymag\": 1, \"zfar\": 10, \"znear\": 0.1}}], \"nodes\": [{\"mesh\": 0, \"camera\": 0,"),
        // A dangling POSITION accessor (gltf-json's validation indexes it unchecked).
        ("\"POSITION\": 0", "\"POSITION\": 5"),
        // A dangling mesh.
        ("\"mesh\": 0", "\"mesh\": 3"),
        // A stride smaller than the element.
        ("\"byteLength\": 36}", "\"byteLength\": 36, \"byteStride\": 4}"),
        // Implicit (zero) data of absurd size.
        ("{\"bufferView\": 0, ", "{"),
        ("\"count\": 3", "\"count\": 1000000000000"),
        // An index accessor of the wrong type.
        ("{\"POSITION\": 0}", "{\"POSITION\": 0}, \"indices\": 0"),
        // A light index past the end.
        ("\"light\": 0", "\"light\": 7"),
        // No scene at all: every parentless node is used.
        ("\"scene\": 0,\n \"scenes\": [{\"nodes\": [0, 1]}],", ""),
        // A non-UTF-8 percent escape in the buffer URI.
        ("\"tri.bin\"", "\"%FF.bin\""),
    ];
    for (from, to) in cases {
        let r = triangle_scene(&dir, TRI, |j| {
            assert!(j.contains(from), "{from}");
            j.replace(from, to)
        });
        if let Err(e) = &r {
            one_line(e);
        }
    }
}

#[test]
fn cycle_is_broken_with_a_warning() {
    let dir = scratch("cycle");
    let s =
        triangle_scene(&dir, TRI, |j| j.replace("\"scale\": [1, 1, 1]}", "\"scale\": [1, 1, 1], \"children\": [0]}"))
            .unwrap();
    assert_eq!(s.triangle_count(), 1);
    assert!(s.warnings.iter().any(|w| w.contains("repeat a node")), "{:?}", s.warnings);
}

#[test]
fn no_scene_uses_root_nodes() {
    let dir = scratch("noscene");
    let s = triangle_scene(&dir, TRI, |j| j.replace("\"scene\": 0,\n \"scenes\": [{\"nodes\": [0, 1]}],", "")).unwrap();
    assert_eq!((s.triangle_count(), s.lights.len()), (1, 1));
}

#[test]
fn skipped_things_each_get_one_warning_line() {
    let dir = scratch("warnings");
    let s = triangle_scene(&dir, TRI, |j| {
        j.replace(
            NODE0,
            "\"cameras\": [{\"type\": \"orthographic\", \"orthographic\": {\"xmag\": 1, \"ymag\": 1, \"zfar\": 10, \"znear\": 0.1}}], \
             \"materials\": [{\"name\": \"glass\", \"alphaMode\": \"BLEND\", \"emissiveFactor\": [1, 1, 1]}], \
             \"nodes\": [{\"mesh\": 0, \"camera\": 0,",
        )
        .replace(
            "{\"attributes\": {\"POSITION\": 0}}",
            "{\"attributes\": {\"POSITION\": 0}, \"material\": 0}, {\"attributes\": {\"POSITION\": 0}, \"mode\": 1}",
        )
    })
    .unwrap();
    assert_eq!(s.triangle_count(), 1);
    assert!(s.camera.is_none());
    assert_eq!(s.camera_or_framing().yfov, 45f32.to_radians());
    assert_eq!(
        s.warnings,
        [
            "ignored: metalness",
            "alphaMode BLEND is rendered opaque: material 'glass'",
            "skipped primitives that are not triangles: 1 LINES",
            "camera 0 is orthographic: skipped",
        ]
    );
}

#[test]
fn alpha_mask_defaults_to_half() {
    let dir = scratch("mask");
    let s = triangle_scene(&dir, TRI, |j| {
        j.replace(NODE0, "\"materials\": [{\"alphaMode\": \"MASK\", \"pbrMetallicRoughness\": {\"metallicFactor\": 0}}], \"nodes\": [{\"mesh\": 0,")
            .replace("{\"POSITION\": 0}", "{\"POSITION\": 0}, \"material\": 0")
    })
    .unwrap();
    assert_eq!(s.materials.len(), 1, "the file's material is used, no default added");
    assert_eq!((s.materials[0].name.as_str(), s.materials[0].alpha_cutoff), ("material 0", Some(0.5)));
    assert_eq!(s.materials[0].base_color, glam::Vec4::ONE);
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
}

#[test]
fn emissive_materials_are_lights() {
    let dir = scratch("emissive");
    // No punctual light: the emissive triangle alone makes the scene lit.
    let s = triangle_scene(&dir, TRI, |j| {
        j.replace("\"extensionsUsed\": [\"KHR_lights_punctual\"],", "\"extensionsUsed\": [\"KHR_materials_emissive_strength\"],")
            .replace("\"extensions\": {\"KHR_lights_punctual\": {\"lights\": [{\"type\": \"point\"}]}},", "")
            .replace(", {\"extensions\": {\"KHR_lights_punctual\": {\"light\": 0}}, \"translation\": [0, 0, 1]}", "")
            .replace("\"scenes\": [{\"nodes\": [0, 1]}]", "\"scenes\": [{\"nodes\": [0]}]")
            .replace(
                NODE0,
                "\"materials\": [{\"pbrMetallicRoughness\": {\"metallicFactor\": 0}, \"emissiveFactor\": [1, 0.5, 0.25], \"doubleSided\": true, \
                 \"extensions\": {\"KHR_materials_emissive_strength\": {\"emissiveStrength\": 4}}}], \
                 \"nodes\": [{\"mesh\": 0,",
            )
            .replace("{\"attributes\": {\"POSITION\": 0}}", "{\"attributes\": {\"POSITION\": 0}, \"material\": 0}")
    })
    .unwrap();
    assert!(s.lights.is_empty());
    let m = &s.materials[s.triangle_material[0] as usize];
    assert_eq!(m.emission, glam::Vec3::new(4.0, 2.0, 1.0));
    assert!(m.double_sided && m.emits() && m.emission_texture.is_none());
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
}
