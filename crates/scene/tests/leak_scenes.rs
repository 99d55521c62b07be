//! The light-leak scenes (`scenes/two-rooms.gltf`, `doorway.gltf`, `atrium.gltf`) are built
//! the way their `extras` say: closed solids, the light on one side of a thin wall and the
//! camera on the other, checked with a small CPU ray caster (Möller–Trumbore in f64, edges
//! inclusive, so a segment through a shared edge or vertex counts as blocked).

use std::collections::HashMap;
use std::path::PathBuf;

use glam::{DVec3, Vec3};
use leakless_scene::{LightKind, Scene};

fn load(rel: &str) -> Scene {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..").join(rel);
    let s = Scene::load(&path).unwrap_or_else(|e| panic!("{rel}: {e}"));
    assert!(s.warnings.is_empty(), "{rel}: {:?}", s.warnings);
    s
}

/// The raw JSON text after `"key":` in the scene's extras.
fn extra_text<'a>(scene: &'a Scene, key: &str) -> &'a str {
    let json = scene.extras.as_deref().expect("scene has extras");
    let at = json.find(&format!("\"{key}\"")).unwrap_or_else(|| panic!("no {key} in {json}"));
    json[at + key.len() + 2..].trim_start().trim_start_matches(':').trim_start()
}

fn extra(scene: &Scene, key: &str) -> f64 {
    let rest = extra_text(scene, key);
    let end = rest.find([',', '}', '\n']).unwrap_or(rest.len());
    rest[..end].trim().parse().unwrap_or_else(|e| panic!("{key}: {e}"))
}

fn extra_vec3(scene: &Scene, key: &str) -> DVec3 {
    let rest = extra_text(scene, key);
    let body = rest.strip_prefix('[').unwrap_or_else(|| panic!("{key} is not an array"));
    let v: Vec<f64> = body[..body.find(']').unwrap()].split(',').map(|x| x.trim().parse().unwrap()).collect();
    assert_eq!(v.len(), 3, "{key}");
    DVec3::new(v[0], v[1], v[2])
}

fn triangles(s: &Scene) -> Vec<[DVec3; 3]> {
    s.vertices.chunks_exact(3).map(|t| std::array::from_fn(|k| Vec3::from(t[k].position).as_dvec3())).collect()
}

/// Parameter in (0, 1) of the first triangle the segment a→b crosses, if any. The ends are
/// excluded (1e-9 of the segment), edges and vertices included.
fn first_hit(tris: &[[DVec3; 3]], a: DVec3, b: DVec3) -> Option<f64> {
    let d = b - a;
    let mut best: Option<f64> = None;
    for [p0, p1, p2] in tris {
        let (e1, e2) = (*p1 - *p0, *p2 - *p0);
        let pv = d.cross(e2);
        let det = e1.dot(pv);
        if det.abs() < 1e-14 {
            continue; // parallel to the triangle's plane
        }
        let inv = 1.0 / det;
        let tv = a - *p0;
        let u = tv.dot(pv) * inv;
        let qv = tv.cross(e1);
        let v = d.dot(qv) * inv;
        let t = e2.dot(qv) * inv;
        let tol = 1e-9;
        if u >= -tol && v >= -tol && u + v <= 1.0 + tol && t > 1e-9 && t < 1.0 - 1e-9 {
            best = Some(best.map_or(t, |b: f64| b.min(t)));
        }
    }
    best
}

fn inside(p: DVec3, lo: DVec3, hi: DVec3) -> bool {
    p.cmpgt(lo).all() && p.cmplt(hi).all()
}

/// `n` points per axis strictly inside the box (cell centres of an n³ grid).
fn grid(lo: DVec3, hi: DVec3, n: [usize; 3]) -> Vec<DVec3> {
    let mut out = Vec::new();
    for i in 0..n[0] {
        for j in 0..n[1] {
            for k in 0..n[2] {
                let f = DVec3::new(
                    (i as f64 + 0.5) / n[0] as f64,
                    (j as f64 + 0.5) / n[1] as f64,
                    (k as f64 + 0.5) / n[2] as f64,
                );
                out.push(lo + (hi - lo) * f);
            }
        }
    }
    out
}

/// What every leak scene promises: a small scene of closed, outward-wound solids (each
/// directed edge matched by its reverse, so no cracks or T-junctions), unit normals that
/// agree with the winding, a 60° camera and at least one light.
fn check_common(s: &Scene, max_triangles: usize) {
    let n = s.triangle_count();
    assert!((12..=max_triangles).contains(&n), "{}: {n} triangles", s.name);
    let mut edges: HashMap<([u32; 3], [u32; 3]), i32> = HashMap::new();
    for t in s.vertices.chunks_exact(3) {
        let p: [Vec3; 3] = std::array::from_fn(|k| Vec3::from(t[k].position));
        let face = (p[1] - p[0]).cross(p[2] - p[0]);
        assert!(face.length() > 1e-8, "degenerate triangle {p:?}");
        for v in t {
            let nrm = Vec3::from(v.normal);
            assert!((nrm.length() - 1.0).abs() < 1e-5);
            assert!(face.normalize().dot(nrm) > 0.999, "winding disagrees with normal in {p:?}");
        }
        for k in 0..3 {
            let (a, b) = (p[k].to_array().map(f32::to_bits), p[(k + 1) % 3].to_array().map(f32::to_bits));
            // +1 for a→b, -1 for b→a, keyed by the ordered pair.
            if a < b {
                *edges.entry((a, b)).or_default() += 1;
            } else {
                *edges.entry((b, a)).or_default() -= 1;
            }
        }
    }
    let open: Vec<_> = edges.iter().filter(|(_, &c)| c != 0).collect();
    assert!(open.is_empty(), "{}: {} unmatched edges, e.g. {:?}", s.name, open.len(), open.first());
    let c = s.camera.as_ref().expect("camera");
    assert!((c.yfov.to_degrees() - 60.0).abs() < 1e-3, "yfov {}", c.yfov.to_degrees());
    assert!(!s.lights.is_empty());
}

/// The rooms: the partition's room-A face covers the whole cross-section of the shell, no
/// triangle but the shell's crosses the partition slab, the light is in room A and the
/// camera in room B, looking towards the partition.
fn check_rooms(s: &Scene) -> (Vec<[DVec3; 3]>, DVec3) {
    check_common(s, 300);
    let tris = triangles(s);
    let (a_lo, a_hi) = (extra_vec3(s, "lit_room_min"), extra_vec3(s, "lit_room_max"));
    let (b_lo, b_hi) = (extra_vec3(s, "dark_room_min"), extra_vec3(s, "dark_room_max"));
    let t = extra(s, "partition_thickness") / 2.0;
    assert_eq!(extra(s, "partition_thickness"), 0.02);
    assert_eq!(extra(s, "partition_x"), 0.0);
    assert!((a_hi.x + t).abs() < 1e-9 && (b_lo.x - t).abs() < 1e-9, "rooms end at the partition's faces");
    assert_eq!((a_lo.y, a_lo.z, a_hi.y, a_hi.z), (b_lo.y, b_lo.z, b_hi.y, b_hi.z), "rooms side by side");
    // Room sizes: about 3 m × 2.5 m × 3 m.
    for (lo, hi) in [(a_lo, a_hi), (b_lo, b_hi)] {
        let size = hi - lo;
        assert!((size - DVec3::new(3.0, 2.5, 3.0)).abs().max_element() < 1e-6, "room size {size}");
    }
    let eps = 1e-6;
    for tri in &tris {
        let (lo, hi) = (tri[0].min(tri[1]).min(tri[2]), tri[0].max(tri[1]).max(tri[2]));
        if lo.x < -t - eps && hi.x > t + eps {
            // Crossing the partition slab: only the shell may, outside the rooms' interior.
            let outside = hi.y <= a_lo.y + eps || lo.y >= a_hi.y - eps || hi.z <= a_lo.z + eps || lo.z >= a_hi.z - eps;
            assert!(outside, "triangle {tri:?} crosses the partition inside the rooms");
        }
        // Nothing reaches from one room's interior into the other's.
        let in_a = tri.iter().any(|&p| inside(p, a_lo, a_hi));
        let in_b = tri.iter().any(|&p| inside(p, b_lo, b_hi));
        assert!(!(in_a && in_b), "triangle {tri:?} spans both rooms");
    }
    // The partition (the triangles within its slab) reaches the shell's inner faces all round.
    let part: Vec<DVec3> =
        tris.iter().filter(|tri| tri.iter().all(|p| p.x.abs() <= t + eps)).flatten().copied().collect();
    let (p_lo, p_hi) = part.iter().fold((DVec3::MAX, DVec3::MIN), |(lo, hi), &p| (lo.min(p), hi.max(p)));
    assert!(p_lo.y <= a_lo.y && p_hi.y >= a_hi.y && p_lo.z <= a_lo.z && p_hi.z >= a_hi.z, "partition {p_lo}..{p_hi}");
    // Across every seam between the partition and the shell (floor, ceiling, side walls), from
    // 2 mm in front of the partition 1 mm off the shell in room A to the mirror point in room
    // B: blocked, except through the door.
    let has_door = s.extras.as_deref().unwrap().contains("\"door_min\"");
    let door = has_door.then(|| (extra_vec3(s, "door_min"), extra_vec3(s, "door_max")));
    let mut seams = 0;
    for f in 0..=100 {
        let (fy, fz) = (a_lo.y + (a_hi.y - a_lo.y) * f as f64 / 100.0, a_lo.z + (a_hi.z - a_lo.z) * f as f64 / 100.0);
        let (fy, fz) = (fy.clamp(a_lo.y + 1e-3, a_hi.y - 1e-3), fz.clamp(a_lo.z + 1e-3, a_hi.z - 1e-3));
        for (y, z) in [(a_lo.y + 1e-3, fz), (a_hi.y - 1e-3, fz), (fy, a_lo.z + 1e-3), (fy, a_hi.z - 1e-3)] {
            if let Some((d_lo, d_hi)) = door {
                if y < d_hi.y + 0.01 && z > d_lo.z - 0.01 && z < d_hi.z + 0.01 {
                    continue;
                }
            }
            let (pa, pb) = (DVec3::new(-t - 2e-3, y, z), DVec3::new(t + 2e-3, y, z));
            assert!(first_hit(&tris, pa, pb).is_some(), "open seam between the rooms at y {y}, z {z}");
            seams += 1;
        }
    }
    assert!(seams >= 300, "{seams} seam segments");
    assert_eq!(s.lights.len(), 1);
    let light = &s.lights[0];
    assert_eq!(light.kind, LightKind::Point);
    assert_eq!(light.intensity as f64, extra(s, "light_intensity_w_per_sr"));
    let lp = light.position.as_dvec3();
    assert!(inside(lp, a_lo + 0.3, a_hi - 0.3), "light {lp} well inside room A");
    let c = s.camera.as_ref().unwrap();
    assert!(inside(c.position().as_dvec3(), b_lo + 0.1, b_hi - 0.1), "camera {} in room B", c.position());
    assert!(c.forward().x < -0.5, "camera looks towards the partition: {}", c.forward());
    // Everything in room A is in the light's view (sanity check of the ray caster too).
    for p in grid(a_lo + 0.01, a_hi - 0.01, [6, 5, 6]) {
        assert_eq!(first_hit(&tris, lp, p), None, "room A point {p} hidden from the light");
    }
    (tris, lp)
}

/// Points of room B: a grid through the volume and points 1 mm off its floor, ceiling, side
/// walls and partition face near the partition, where splatting leaks.
fn room_b_points(s: &Scene) -> Vec<DVec3> {
    let (lo, hi) = (extra_vec3(s, "dark_room_min"), extra_vec3(s, "dark_room_max"));
    let off = 1e-3;
    let mut pts = grid(lo + off, hi - off, [8, 6, 8]);
    for d in [0.002, 0.05, 0.2] {
        let x = lo.x + d;
        for f in 0..=10 {
            let (fy, fz) = (lo.y + (hi.y - lo.y) * f as f64 / 10.0, lo.z + (hi.z - lo.z) * f as f64 / 10.0);
            let (fy, fz) = (fy.clamp(lo.y + off, hi.y - off), fz.clamp(lo.z + off, hi.z - off));
            pts.extend([
                DVec3::new(x, lo.y + off, fz),
                DVec3::new(x, hi.y - off, fz),
                DVec3::new(x, fy, lo.z + off),
                DVec3::new(x, fy, hi.z - off),
            ]);
        }
    }
    for p in grid(DVec3::new(lo.x + off, lo.y, lo.z), DVec3::new(lo.x + off, hi.y, hi.z), [1, 10, 12]) {
        pts.push(p);
    }
    pts
}

#[test]
fn two_rooms_are_sealed_from_each_other() {
    let s = load("scenes/two-rooms.gltf");
    let (tris, lp) = check_rooms(&s);
    assert_eq!(extra(&s, "expected_dark_room_radiance"), 0.0);
    let t = extra(&s, "partition_thickness") / 2.0;
    let pts = room_b_points(&s);
    assert!(pts.len() > 500);
    for p in pts {
        let hit = first_hit(&tris, lp, p).unwrap_or_else(|| panic!("light reaches room B at {p}"));
        // The first thing in the way is the partition's room-A face (or the shell at the
        // partition's foot, for points right at the floor, ceiling or side walls).
        let q = lp + (p - lp) * hit;
        assert!(q.x <= -t + 1e-6, "light to {p}: first hit {q} past the partition's room-A face");
    }
    // The partition's room-A face covers the rooms' whole cross-section (and more: it reaches
    // into the shell).
    let (lo, hi) = (extra_vec3(&s, "lit_room_min"), extra_vec3(&s, "lit_room_max"));
    let area: f64 = tris
        .iter()
        .filter(|tri| tri.iter().all(|p| (p.x + t).abs() < 1e-7))
        .map(|[a, b, c]| 0.5 * (*b - *a).cross(*c - *a).length())
        .sum();
    assert!(area >= (hi.y - lo.y) * (hi.z - lo.z) - 1e-6, "partition face area {area}");
    // Red on the partition's room-A face only, so that leaked light is visibly red.
    let red = s.materials.iter().position(|m| m.name == "red").unwrap() as u32;
    for (tri, &m) in tris.iter().zip(&s.triangle_material) {
        if m == red {
            assert!(tri.iter().all(|p| (p.x + t).abs() < 1e-7), "red triangle {tri:?} off the room-A face");
        }
    }
}

#[test]
fn doorway_lets_light_through_the_door_only() {
    let s = load("scenes/doorway.gltf");
    let (tris, lp) = check_rooms(&s);
    let (d_lo, d_hi) = (extra_vec3(&s, "door_min"), extra_vec3(&s, "door_max"));
    assert!(((d_hi.z - d_lo.z) - 0.8).abs() < 1e-9 && (d_hi.y - d_lo.y - 2.0).abs() < 1e-9, "door 0.8 m × 2 m");
    let (mut through, mut blocked) = (0, 0);
    for p in room_b_points(&s) {
        // Where the segment crosses the partition's mid-plane x = 0.
        let f = -lp.x / (p.x - lp.x);
        let q = lp + (p - lp) * f;
        let margin = 0.02;
        let in_door = q.y > d_lo.y + margin && q.y < d_hi.y - margin && q.z > d_lo.z + margin && q.z < d_hi.z - margin;
        let off_door = q.y > d_hi.y + margin || q.z < d_lo.z - margin || q.z > d_hi.z + margin;
        let hit = first_hit(&tris, lp, p);
        if in_door {
            assert_eq!(hit, None, "light to {p} through the door at {q} is blocked");
            through += 1;
        } else if off_door {
            assert!(hit.is_some(), "light reaches {p} through the wall at {q}");
            blocked += 1;
        }
    }
    assert!(through >= 20 && blocked >= 200, "through the door {through}, blocked {blocked}");
    // The camera sees the doorway: its centre is in front of the camera, inside the field of view.
    let c = s.camera.as_ref().unwrap();
    let to_door = ((d_lo + d_hi) * 0.5).as_vec3() - c.position();
    assert!(to_door.normalize().angle_between(c.forward()) < 0.5 * c.yfov, "door outside the view");
}

#[test]
fn atrium_camera_is_under_a_closed_slab_the_sun_cannot_cross() {
    let s = load("scenes/atrium.gltf");
    check_common(&s, 400);
    let tris = triangles(&s);
    let (slab_lo, slab_hi) = (extra_vec3(&s, "slab_min"), extra_vec3(&s, "slab_max"));
    let (y0, y1) = (extra(&s, "slab_bottom_y"), extra(&s, "slab_top_y"));
    assert_eq!((slab_lo.y, slab_hi.y), (y0, y1));
    assert!((y1 - y0 - extra(&s, "slab_thickness")).abs() < 1e-9 && y1 - y0 <= 0.2, "a thin slab");
    let (g_lo, g_hi) = (extra_vec3(&s, "ground_gallery_min"), extra_vec3(&s, "ground_gallery_max"));
    let top = extra(&s, "wall_height") + 1.0;

    // The camera is in the ground-floor gallery, under the slab, looking along it (mostly
    // along x) and up towards the wall just below the slab.
    let c = s.camera.as_ref().unwrap();
    let eye = c.position().as_dvec3();
    assert!(inside(eye, g_lo, g_hi) && eye.y < y0, "camera {eye} under the slab");
    let under = eye.x > slab_lo.x && eye.x < slab_hi.x && eye.z > slab_lo.z && eye.z < slab_hi.z;
    assert!(under, "camera {eye} outside the slab's footprint");
    assert!(c.forward().x.abs() > 0.8 && c.forward().y > 0.0, "camera forward {}", c.forward());

    // One sun, shining downwards, as the extras say.
    assert_eq!(s.lights.len(), 1);
    let sun = &s.lights[0];
    assert_eq!(sun.kind, LightKind::Directional);
    let d = sun.direction.as_dvec3();
    assert!(d.y < -0.5, "sun direction {d}");
    assert!((d - extra_vec3(&s, "sun_direction")).length() < 1e-6, "sun direction {d}");
    let elevation = (-d.y).asin().to_degrees();
    assert!((elevation - extra(&s, "sun_elevation_degrees")).abs() < 1e-4);

    // Closed above the camera's view region: straight up from anywhere in the gallery between
    // the back wall and the beam, from the camera's height, the first thing is the slab's
    // underside (no gap at the back wall, the side walls or anywhere in between).
    let beam_back = slab_hi.z - 0.5; // behind the piers and the beam
    let region =
        grid(DVec3::new(g_lo.x + 1e-3, eye.y, g_lo.z + 1e-3), DVec3::new(g_hi.x - 1e-3, eye.y, beam_back), [60, 1, 12]);
    for p in region {
        let up = DVec3::new(p.x, top, p.z);
        let hit = first_hit(&tris, p, up).unwrap_or_else(|| panic!("open sky above {p}"));
        let y = p.y + (top - p.y) * hit;
        assert!((y - y0).abs() < 1e-6, "straight up from {p}: first hit at y = {y}, not the slab's underside");
    }
    // ... also 2 mm from the back wall and from the side walls, where the slab meets them.
    let mut seam = Vec::new();
    for f in 0..=200 {
        let x = g_lo.x + 2e-3 + (g_hi.x - g_lo.x - 4e-3) * f as f64 / 200.0;
        let z = g_lo.z + 2e-3 + (beam_back - g_lo.z - 2e-3) * f as f64 / 200.0;
        seam.extend([
            DVec3::new(x, eye.y, g_lo.z + 2e-3),
            DVec3::new(g_lo.x + 2e-3, eye.y, z),
            DVec3::new(g_hi.x - 2e-3, eye.y, z),
        ]);
    }
    for p in seam {
        let hit = first_hit(&tris, p, DVec3::new(p.x, top, p.z)).unwrap_or_else(|| panic!("open sky above {p}"));
        assert!((p.y + (top - p.y) * hit - y0).abs() < 1e-6, "straight up from {p}: not the slab's underside");
    }
    // Straight up from the courtyard: open sky.
    let (y_lo, y_hi) = (extra_vec3(&s, "courtyard_min"), extra_vec3(&s, "courtyard_max"));
    for p in grid(y_lo + DVec3::new(0.5, 0.01, 0.5), DVec3::new(y_hi.x - 0.5, 0.02, y_hi.z - 0.5), [6, 1, 6]) {
        assert_eq!(first_hit(&tris, p, DVec3::new(p.x, top, p.z)), None, "courtyard point {p} roofed");
    }

    // No direct sun on the back wall below the slab; direct sun on most of it above.
    let toward_sun = -d * 40.0;
    let (sh_lo, sh_hi) = (extra_vec3(&s, "shadowed_back_wall_min"), extra_vec3(&s, "shadowed_back_wall_max"));
    let wall_off = DVec3::new(0.0, 0.0, 1e-3);
    for p in grid(sh_lo + wall_off, sh_hi + wall_off, [24, 12, 1]) {
        assert!(first_hit(&tris, p, p + toward_sun).is_some(), "sun reaches the shadowed wall at {p}");
    }
    // ... also right under the slab, 5 mm below it and 1 mm off the wall, along its whole length.
    for f in 0..=200 {
        let p = DVec3::new(sh_lo.x + (sh_hi.x - sh_lo.x) * f as f64 / 200.0, y0 - 5e-3, sh_lo.z + 1e-3);
        assert!(first_hit(&tris, p, p + toward_sun).is_some(), "sun reaches the wall right under the slab at {p}");
    }
    let (lit_lo, lit_hi) = (extra_vec3(&s, "sunlit_back_wall_min"), extra_vec3(&s, "sunlit_back_wall_max"));
    let lit = grid(lit_lo + wall_off, lit_hi + wall_off, [24, 12, 1]);
    let sunlit = lit.iter().filter(|&&p| first_hit(&tris, p, p + toward_sun).is_none()).count();
    assert!(sunlit as f64 >= 0.8 * lit.len() as f64, "{sunlit} of {} upper back wall points sunlit", lit.len());
    // Just above the slab (where the splatting radius reaches down through it) is sunlit.
    let just_above =
        grid(DVec3::new(-4.0, y1 + 0.05, lit_lo.z + 1e-3), DVec3::new(4.0, y1 + 0.3, lit_lo.z + 1e-3), [16, 3, 1]);
    assert!(
        just_above.iter().all(|&p| first_hit(&tris, p, p + toward_sun).is_none()),
        "upper wall near the slab shaded"
    );
}
