//! The project's scenes and fixtures load to exactly the numbers `tools/gen-scenes`
//! put in them, checked against values computed by hand.

use std::path::PathBuf;

use glam::{Vec3, Vec4};
use leakless_scene::{LightKind, Scene};

fn repo(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..").join(rel)
}

fn load(rel: &str) -> Scene {
    Scene::load(&repo(rel)).unwrap_or_else(|e| panic!("{rel}: {e}"))
}

fn close(a: Vec3, b: Vec3, eps: f32) -> bool {
    (a - b).abs().max_element() <= eps
}

/// A number from the scene's raw `extras` JSON (flat `"key": number` pairs).
fn extra(scene: &Scene, key: &str) -> f32 {
    let json = scene.extras.as_deref().expect("scene has extras");
    let at = json.find(&format!("\"{key}\"")).unwrap_or_else(|| panic!("no {key} in {json}"));
    let rest = &json[at + key.len() + 2..];
    let rest = rest.trim_start().trim_start_matches(':').trim_start();
    let end = rest.find([',', '}']).unwrap_or(rest.len());
    rest[..end].trim().parse().unwrap()
}

/// Every triangle's winding agrees with its vertices' shading normals (the loader's
/// promise, also under mirroring transforms).
fn assert_winding_matches_normals(scene: &Scene) {
    for t in scene.vertices.chunks_exact(3) {
        let p: [Vec3; 3] = std::array::from_fn(|k| Vec3::from(t[k].position));
        let face = (p[1] - p[0]).cross(p[2] - p[0]);
        for v in t {
            assert!(face.dot(Vec3::from(v.normal)) > 0.0, "winding disagrees with normal in {t:?}");
        }
    }
}

#[test]
fn cornell_box_is_the_measured_box() {
    let s = load("scenes/cornell-box.gltf");
    assert_eq!(s.name, "cornell-box");
    // 5 walls (open front) and 2 blocks of 5 faces, 2 triangles per quad.
    assert_eq!(s.triangle_count(), 30);
    assert_eq!(s.triangle_material.len(), 30);
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);

    let colour = |name: &str| s.materials.iter().find(|m| m.name == name).unwrap().base_color;
    assert_eq!(colour("white"), Vec4::new(0.725, 0.71, 0.68, 1.0));
    assert_eq!(colour("red"), Vec4::new(0.63, 0.065, 0.05, 1.0));
    assert_eq!(colour("green"), Vec4::new(0.14, 0.45, 0.091, 1.0));
    let count = |name: &str| {
        let i = s.materials.iter().position(|m| m.name == name).unwrap() as u32;
        s.triangle_material.iter().filter(|&&m| m == i).count()
    };
    assert_eq!((count("white"), count("red"), count("green")), (26, 2, 2));
    // Red wall at x ≈ 0.556 (the camera's left), green at x = 0.
    for (t, &m) in s.vertices.chunks_exact(3).zip(&s.triangle_material) {
        let xs: [f32; 3] = std::array::from_fn(|k| t[k].position[0]);
        match s.materials[m as usize].name.as_str() {
            "red" => assert!(xs.iter().all(|&x| x > 0.549)),
            "green" => assert!(xs.iter().all(|&x| x == 0.0)),
            _ => {}
        }
    }

    let b = s.bounds();
    assert!(close(b.min, Vec3::ZERO, 1e-6), "{b:?}");
    assert!(close(b.max, Vec3::new(0.556, 0.5488, 0.5592), 1e-6), "{b:?}");

    // Normals face into the room / out of the blocks: every surface is seen from
    // inside the box, so each normal faces the point light unless a block is between.
    assert_winding_matches_normals(&s);
    for v in &s.vertices {
        let n = Vec3::from(v.normal);
        assert!((n.length() - 1.0).abs() < 1e-5);
    }
    let floor_up = s.vertices.iter().filter(|v| v.position[1] == 0.0 && v.normal[1] > 0.99).count();
    assert_eq!(floor_up, 6, "the floor's two triangles face up");

    assert_eq!(s.lights.len(), 1);
    let l = &s.lights[0];
    assert_eq!(l.kind, LightKind::Point);
    assert!(close(l.position, Vec3::new(0.278, 0.4488, 0.2795), 1e-6));
    assert_eq!(l.intensity, 0.3);
    assert_eq!(l.color, Vec3::ONE);

    let c = s.camera.as_ref().expect("cornell camera");
    assert!(close(c.position(), Vec3::new(0.278, 0.273, -0.8), 1e-6));
    assert!(close(c.forward(), Vec3::Z, 1e-6), "forward {}", c.forward());
    assert!(close(c.up(), Vec3::Y, 1e-6));
    // Camera right is world -X: the red wall (x ≈ 0.556) appears on the left.
    let right = c.world_from_camera.x_axis.truncate();
    assert!(close(right, Vec3::NEG_X, 1e-6), "right {right}");
    assert!((c.yfov.to_degrees() - 39.31).abs() < 0.01, "yfov {}", c.yfov.to_degrees());
    assert_eq!(c.zfar, None);
}

#[test]
fn sphere_wall_is_at_radius_from_the_light() {
    let s = load("scenes/sphere.gltf");
    let (r, rho, i) = (extra(&s, "radius"), extra(&s, "albedo"), extra(&s, "intensity"));
    assert_eq!((r, rho, i), (1.0, 0.5, 1.0));
    assert!(s.triangle_count() >= 2000, "{} triangles", s.triangle_count());
    assert_eq!(s.lights.len(), 1);
    let light = &s.lights[0];
    assert_eq!((light.kind, light.intensity), (LightKind::Point, i));
    assert_eq!(s.materials.len(), 1);
    assert_eq!(s.materials[0].base_color, Vec4::new(rho, rho, rho, 1.0));
    for v in &s.vertices {
        let p = Vec3::from(v.position);
        assert!((p.distance(light.position) - r).abs() < 1e-6, "vertex {p} off the sphere");
        // Smooth normals pointing inward, towards the light.
        assert!(Vec3::from(v.normal).dot((light.position - p) / r) > 0.999);
    }
    assert_winding_matches_normals(&s);
    let c = s.camera.as_ref().unwrap();
    assert!(c.position().distance(light.position) < 0.5 * r, "camera near the centre");
    let expected = extra(&s, "expected_direct_radiance");
    assert!((expected - rho * i / (std::f32::consts::PI * r * r)).abs() < 1e-6);
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
}

#[test]
fn floor_light_matches_its_analytic_setup() {
    let s = load("tests/scenes/floor-light.gltf");
    assert_eq!(s.triangle_count(), 2);
    assert!(close(s.bounds().min, Vec3::new(-10.0, 0.0, -10.0), 0.0));
    assert!(close(s.bounds().max, Vec3::new(10.0, 0.0, 10.0), 0.0));
    assert!(s.vertices.iter().all(|v| v.normal == [0.0, 1.0, 0.0]));
    assert_winding_matches_normals(&s);
    assert_eq!(s.materials[0].base_color.truncate(), Vec3::splat(extra(&s, "albedo")));
    let l = &s.lights[0];
    assert_eq!(l.position, Vec3::new(0.0, extra(&s, "light_height"), 0.0));
    assert_eq!(l.intensity, extra(&s, "intensity"));
    let c = s.camera.as_ref().unwrap();
    assert!(close(c.position(), Vec3::new(0.0, 2.0, 0.0), 1e-6));
    assert!(close(c.forward(), Vec3::NEG_Y, 1e-6), "looks straight down: {}", c.forward());
    let expected = extra(&s, "expected_radiance_below_light");
    assert!((expected - 0.8 * 2.0 / std::f32::consts::PI).abs() < 1e-6);
}

#[test]
fn textured_glb_hierarchy_texture_and_lights() {
    let s = load("tests/scenes/textured.glb");
    assert_eq!(s.triangle_count(), 4, "one quad under two nodes");
    // The file's animation ("slide") moves "child", so its quad is an instance,
    // after the static "mirrored child" quad; at t = 0 it sits at its rest pose.
    assert_eq!(s.instances.len(), 1);
    let i = &s.instances[0];
    assert_eq!((i.name.as_str(), i.first_triangle, i.triangle_count, s.static_triangle_count()), ("child", 2, 2, 2));
    // parent = T(1,2,3) · Ry(90°) · S(2,3,1); child = T(0,0,1); Ry(90°) maps
    // (x,y,z) to (z,y,-x). Quad corner (-0.5,-0.5,0) → (-0.5,-0.5,1) → S (-1,-1.5,1)
    // → R (1,-1.5,1) → T (2,0.5,4); and so on for the other corners.
    let child: Vec<Vec3> = s.vertices[6..12].iter().map(|v| Vec3::from(v.position)).collect();
    let expected =
        [(2.0, 0.5, 4.0), (2.0, 0.5, 2.0), (2.0, 3.5, 2.0), (2.0, 0.5, 4.0), (2.0, 3.5, 2.0), (2.0, 3.5, 4.0)];
    for (p, e) in child.iter().zip(expected) {
        assert!(close(*p, Vec3::from(e), 1e-5), "{p} != {e:?}");
    }
    // The normal (0,0,1) goes through the inverse transpose: R · S⁻¹ · n = +X.
    for v in &s.vertices {
        assert!(close(Vec3::from(v.normal), Vec3::X, 1e-6), "normal {:?}", v.normal);
    }
    assert_eq!(s.vertices[6].uv, [0.0, 1.0]);
    assert_eq!(s.vertices[8].uv, [1.0, 0.0]);
    // Mirrored child = T(0,0,-1) · S(-1,1,1): corner 0 → (0.5,-0.5,-1) → (1,-1.5,-1)
    // → (-1,-1.5,-1) → (0,0.5,2). Its winding is flipped back to match the normal.
    assert!(close(Vec3::from(s.vertices[0].position), Vec3::new(0.0, 0.5, 2.0), 1e-5));
    assert_winding_matches_normals(&s);

    assert_eq!(s.textures.len(), 1);
    let t = &s.textures[0];
    assert_eq!((t.width, t.height), (2, 2));
    assert_eq!(t.texels, vec![[255, 0, 0, 255], [0, 255, 0, 255], [0, 0, 255, 255], [255, 255, 255, 128]]);
    assert_eq!(t.bytes().len(), 16);
    assert_eq!(s.materials.len(), 1);
    let m = &s.materials[0];
    assert_eq!((m.name.as_str(), m.texture, m.alpha_cutoff), ("checker", Some(0), Some(0.25)));
    assert_eq!(m.base_color, Vec4::new(1.0, 0.5, 0.25, 1.0));

    assert_eq!(s.lights.len(), 2);
    let spot = s.lights.iter().find(|l| l.name == "spot").unwrap();
    assert_eq!(spot.kind, LightKind::Spot { inner_cone: 0.2, outer_cone: 0.6 });
    // Spot node T(0,1,0) under the parent: (1,2,3) + R·S·(0,1,0) = (1,5,3); it
    // shines along R·S·(0,0,-1) = R·(0,0,-1) = (-1,0,0).
    assert!(close(spot.position, Vec3::new(1.0, 5.0, 3.0), 1e-5), "{}", spot.position);
    assert!(close(spot.direction, Vec3::NEG_X, 1e-6), "{}", spot.direction);
    assert_eq!((spot.intensity, spot.range), (5.0, Some(20.0)));
    assert_eq!(spot.color, Vec3::new(1.0, 0.9, 0.8));
    let sun = s.lights.iter().find(|l| l.name == "sun").unwrap();
    assert_eq!(sun.kind, LightKind::Directional);
    // Rx(-45°) · (0,0,-1) = (0, -√½, -√½).
    let h = std::f32::consts::FRAC_1_SQRT_2;
    assert!(close(sun.direction, Vec3::new(0.0, -h, -h), 1e-6), "{}", sun.direction);
    assert_eq!((sun.intensity, sun.range), (3.0, None));

    assert_eq!(s.warnings, vec!["ignored: normal textures".to_string()]);
    assert!(s.camera.is_none());
}

#[test]
fn framing_camera_sees_all_bounds() {
    let s = load("tests/scenes/textured.glb");
    let c = s.camera_or_framing();
    let b = s.bounds();
    assert!(close(c.forward(), Vec3::NEG_Z, 1e-6));
    assert!(c.position().z > b.max.z, "camera on the +Z side");
    let (eye, centre) = (c.position(), b.center());
    assert!(close(Vec3::new(eye.x, eye.y, 0.0), Vec3::new(centre.x, centre.y, 0.0), 1e-6), "looks at the centre");
    assert!((c.yfov - 45f32.to_radians()).abs() < 1e-6);
    let view = c.view_from_world();
    let tan = (c.yfov * 0.5).tan();
    for corner in b.corners() {
        let p = view.transform_point3(corner);
        let depth = -p.z;
        assert!(depth > c.znear && c.zfar.is_none_or(|f| depth < f), "corner {corner} depth {depth}");
        // Square output (aspect 1): both half-angles are yfov / 2.
        assert!(p.x.abs() <= tan * depth && p.y.abs() <= tan * depth, "corner {corner} outside");
    }
    // A scene with a camera keeps it.
    let cornell = load("scenes/cornell-box.gltf");
    assert_eq!(Some(cornell.camera_or_framing()), cornell.camera);
}
