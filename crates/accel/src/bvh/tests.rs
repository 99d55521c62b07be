//! The CPU traversal against brute force, watertightness on closed meshes, tree invariants,
//! bad input, and (ignored by default) the builder measurement.

use super::*;

/// Seeded PCG32 (rand_pcg): the same rays every run.
struct Rng(rand_pcg::Pcg32);

impl Rng {
    fn new(seed: u64) -> Self {
        Self(rand_core::SeedableRng::seed_from_u64(seed))
    }
    fn u32(&mut self) -> u32 {
        rand_core::RngCore::next_u32(&mut self.0)
    }
    /// Uniform in [0, 1).
    fn f32(&mut self) -> f32 {
        (self.u32() >> 8) as f32 / (1u32 << 24) as f32
    }
    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.f32()
    }
    fn point(&mut self, lo: f32, hi: f32) -> [f32; 3] {
        [self.range(lo, hi), self.range(lo, hi), self.range(lo, hi)]
    }
    /// Uniform on the unit sphere.
    fn direction(&mut self) -> [f32; 3] {
        let z = self.range(-1.0, 1.0);
        let phi = self.range(0.0, std::f32::consts::TAU);
        let r = (1.0 - z * z).max(0.0).sqrt();
        [r * phi.cos(), r * phi.sin(), z]
    }
}

fn add(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn sub(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn scale(a: [f32; 3], s: f32) -> [f32; 3] {
    a.map(|c| c * s)
}
fn lerp(a: [f32; 3], b: [f32; 3], s: f32) -> [f32; 3] {
    add(a, scale(sub(b, a), s))
}
fn normalize(a: [f32; 3]) -> [f32; 3] {
    scale(a, 1.0 / (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt())
}

/// `n` random triangles of assorted sizes in [-1, 1]³.
fn soup(n: usize, rng: &mut Rng) -> Vec<[f32; 3]> {
    let mut out = Vec::with_capacity(3 * n);
    for _ in 0..n {
        let c = rng.point(-1.0, 1.0);
        let size = 0.01 + 0.3 * rng.f32().powi(3);
        for _ in 0..3 {
            out.push(add(c, scale(rng.point(-1.0, 1.0), size)));
        }
    }
    out
}

/// An indexed closed mesh: positions and triangles. Flattening it makes shared vertices
/// bit-identical, as in a real mesh.
struct Mesh {
    positions: Vec<[f32; 3]>,
    triangles: Vec<[u32; 3]>,
}

impl Mesh {
    fn flat(&self) -> Vec<[f32; 3]> {
        self.triangles.iter().flatten().map(|&i| self.positions[i as usize]).collect()
    }
    fn edges(&self) -> Vec<(u32, u32)> {
        let mut edges: Vec<(u32, u32)> = self
            .triangles
            .iter()
            .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
            .map(|(a, b)| (a.min(b), a.max(b)))
            .collect();
        edges.sort_unstable();
        edges.dedup();
        edges
    }
}

/// Unit icosphere around `center`: an icosahedron subdivided `levels` times.
fn icosphere(levels: u32, center: [f32; 3], radius: f32) -> Mesh {
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let mut positions: Vec<[f32; 3]> = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .map(normalize)
    .to_vec();
    let mut triangles: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..levels {
        let mut midpoints = std::collections::HashMap::new();
        let mut mid = |a: u32, b: u32, positions: &mut Vec<[f32; 3]>| {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                positions.push(normalize(lerp(positions[a as usize], positions[b as usize], 0.5)));
                positions.len() as u32 - 1
            })
        };
        let mut next = Vec::with_capacity(triangles.len() * 4);
        for &[a, b, c] in &triangles {
            let (ab, bc, ca) = (mid(a, b, &mut positions), mid(b, c, &mut positions), mid(c, a, &mut positions));
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        triangles = next;
    }
    for p in &mut positions {
        *p = add(center, scale(*p, radius));
    }
    Mesh { positions, triangles }
}

/// The surface of the cube [-1, 1]³, each face an n×n grid of quads: axis-aligned faces put
/// triangle edges exactly on BVH box faces, the hardest case for a conservative box test.
fn grid_cube(n: u32) -> Mesh {
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    let mut index = std::collections::HashMap::new();
    let mut vertex = |p: [f32; 3], positions: &mut Vec<[f32; 3]>| {
        let key = p.map(f32::to_bits);
        *index.entry(key).or_insert_with(|| {
            positions.push(p);
            positions.len() as u32 - 1
        })
    };
    let coord = |i: u32| -1.0 + 2.0 * i as f32 / n as f32;
    for axis in 0..3 {
        for side in [-1.0f32, 1.0] {
            for i in 0..n {
                for j in 0..n {
                    let corner = |di: u32, dj: u32| {
                        let mut p = [0.0; 3];
                        p[axis] = side;
                        p[(axis + 1) % 3] = coord(i + di);
                        p[(axis + 2) % 3] = coord(j + dj);
                        p
                    };
                    let q = [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)].map(|p| vertex(p, &mut positions));
                    // Alternate the diagonal so that both orientations occur.
                    if (i + j) % 2 == 0 {
                        triangles.extend([[q[0], q[1], q[2]], [q[0], q[2], q[3]]]);
                    } else {
                        triangles.extend([[q[0], q[1], q[3]], [q[1], q[2], q[3]]]);
                    }
                }
            }
        }
    }
    Mesh { positions, triangles }
}

/// The closest (or any) hit by testing every triangle, with the same triangle test.
fn brute_force(positions: &[[f32; 3]], origin: [f32; 3], dir: [f32; 3], tmin: f32, tmax: f32) -> Option<Hit> {
    let ray = Ray::new(origin, dir);
    let mut best: Option<Hit> = None;
    for (i, v) in positions.chunks_exact(3).enumerate() {
        let t_max = best.map_or(tmax, |h| h.t);
        if let Some((t, [u, v])) = intersect_triangle(&ray, v[0], v[1], v[2], tmin, t_max) {
            best = Some(Hit { t, triangle: i as u32, u, v });
        }
    }
    best
}

/// Compares the BVH with brute force for one ray, closest and any hit.
fn check_ray(bvh: &Bvh, positions: &[[f32; 3]], origin: [f32; 3], dir: [f32; 3], tmin: f32, tmax: f32) {
    check_ray_with(bvh, positions, origin, dir, tmin, tmax, true);
}

/// [`check_ray`]; `check_point`: also check that t and the barycentrics name the same point
/// (not for rays whose hits are ill-conditioned in f32, e.g. 1-unit triangles 10⁷ units away,
/// where the edge functions are rounding noise for every f32 tracer, brute force included).
fn check_ray_with(
    bvh: &Bvh,
    positions: &[[f32; 3]],
    origin: [f32; 3],
    dir: [f32; 3],
    tmin: f32,
    tmax: f32,
    check_point: bool,
) {
    let expected = brute_force(positions, origin, dir, tmin, tmax);
    let closest = bvh.intersect(origin, dir, tmin, tmax, false);
    let any = bvh.intersect(origin, dir, tmin, tmax, true);
    let what = format!("ray {origin:?} + t {dir:?}, t in ({tmin}, {tmax})");
    match (expected, closest) {
        (None, None) => {}
        (Some(e), Some(c)) => {
            assert!((e.t - c.t).abs() <= 1e-5 * e.t.abs(), "{what}: t {} (BVH) vs {} (brute force)", c.t, e.t);
            // Ties (a shared edge or vertex) may name either triangle.
            if c.triangle != e.triangle {
                assert_eq!(c.t, e.t, "{what}: different triangles at different t");
            }
            let v = &positions[3 * c.triangle as usize..];
            let p = add(scale(v[0], 1.0 - c.u - c.v), add(scale(v[1], c.u), scale(v[2], c.v)));
            let q = add(origin, scale(dir, c.t));
            let err = sub(p, q).map(f32::abs).into_iter().fold(0.0, f32::max);
            assert!(!check_point || err < 1e-4, "{what}: barycentrics give {p:?}, t gives {q:?}");
        }
        (e, c) => panic!("{what}: BVH {c:?}, brute force {e:?}"),
    }
    assert_eq!(any.is_some(), expected.is_some(), "{what}: any-hit {any:?} vs brute force {expected:?}");
    if let Some(a) = any {
        assert!(a.t > tmin && a.t < tmax);
    }
}

/// Checks the tree: child boxes inside parents, triangles inside leaves, every finite input
/// triangle exactly once, depth bounded.
fn check_tree(bvh: &Bvh, positions: &[[f32; 3]]) {
    let inside = |outer: ([f32; 3], [f32; 3]), lo: [f32; 3], hi: [f32; 3]| {
        (0..3).all(|a| outer.0[a] <= lo[a] && hi[a] <= outer.1[a])
    };
    let mut seen = vec![0u32; positions.len() / 3];
    // (child, its box, its depth): a one-leaf tree is its root node's first child.
    let root_leaf = bvh.nodes.len() == 1 && ChildRef(bvh.nodes[0].child0).is_leaf();
    let root = if root_leaf { ChildRef(bvh.nodes[0].child0) } else { ChildRef::interior(0) };
    let mut stack = vec![(root, (bvh.bounds_min, bvh.bounds_max), 0u32)];
    let mut max_depth = 0;
    while let Some((node, bounds, depth)) = stack.pop() {
        if !node.is_leaf() {
            let n = &bvh.nodes[node.node() as usize];
            for c in 0..2 {
                let (lo, hi, child) = n.child(c);
                assert!(inside(bounds, lo, hi), "{child:?} pokes out of its parent {node:?}");
                stack.push((child, (lo, hi), depth + 1));
            }
        } else {
            max_depth = max_depth.max(depth);
            let range = node.triangles();
            for tri in &bvh.triangles[range.start as usize..range.end as usize] {
                for v in [tri.v0, tri.v1, tri.v2] {
                    assert!(inside(bounds, v, v), "triangle {} pokes out of leaf {node:?}", tri.triangle);
                }
                let original = &positions[3 * tri.triangle as usize..3 * tri.triangle as usize + 3];
                assert_eq!([tri.v0, tri.v1, tri.v2], [original[0], original[1], original[2]]);
                seen[tri.triangle as usize] += 1;
            }
        }
    }
    for (i, v) in positions.chunks_exact(3).enumerate() {
        let finite = v.iter().flatten().all(|c| c.is_finite());
        assert_eq!(seen[i], finite as u32, "triangle {i} appears {} times", seen[i]);
    }
    assert_eq!(bvh.triangles.len(), seen.iter().sum::<u32>() as usize, "leaves overlap or miss triangles");
    assert_eq!(max_depth, bvh.stats.max_depth);
    assert!(max_depth <= BVH_MAX_DEPTH);
    // The tree's nodes: its interior nodes and one more leaf than those (a one-leaf tree: 1).
    assert_eq!(bvh.stats.node_count as usize, if root_leaf { 1 } else { 2 * bvh.nodes.len() + 1 });
    assert_eq!(bvh.stats.bytes, 64 * bvh.nodes.len() + 40 * bvh.triangles.len());
}

#[test]
fn gpu_structs_have_the_std430_layout() {
    assert_eq!(std::mem::size_of::<BvhNode>(), 64);
    assert_eq!(std::mem::size_of::<BvhTriangle>(), 40);
    let offsets = |l: &RustLayout| l.members.iter().map(|m| (m.name, m.offset)).collect::<Vec<_>>();
    assert_eq!(
        offsets(&BVH_NODE_LAYOUT),
        [
            ("min0", 0),
            ("child0", 12),
            ("max0", 16),
            ("child1", 28),
            ("min1", 32),
            ("pad0", 44),
            ("max1", 48),
            ("pad1", 60)
        ]
    );
    assert_eq!(offsets(&BVH_TRIANGLE_LAYOUT), [("v0", 0), ("triangle", 12), ("v1", 16), ("v2", 28)]);
}

/// The shader's constants that must equal the Rust ones (reflection cannot see them).
#[test]
fn shader_constants_match() {
    let glsl = include_str!("../../../../shaders-glsl/trace_compute.glsl");
    let structs = include_str!("../../../../shaders-glsl/bvh.glsl");
    let clearance = include_str!("../../../../shaders-glsl/clearance_search.glsl");
    assert!(
        glsl.contains(&format!("#define BVH_STACK_SIZE {BVH_MAX_DEPTH}\n")),
        "trace_compute.glsl: BVH_STACK_SIZE must be {BVH_MAX_DEPTH} (BVH_MAX_DEPTH)"
    );
    assert!(
        clearance.contains(&format!("#define STACK_SIZE {BVH_MAX_DEPTH}\n")),
        "clearance_search.glsl: STACK_SIZE must be {BVH_MAX_DEPTH} (BVH_MAX_DEPTH)"
    );
    assert!(
        glsl.contains(&format!("const float BVH_ROBUST_FAR = {:?};", intersect::ROBUST_FAR)),
        "trace_compute.glsl: BVH_ROBUST_FAR must be {:?}",
        intersect::ROBUST_FAR
    );
    for decl in [
        "struct BvhNode {\n    vec3 min0;\n    uint child0;\n    vec3 max0;\n    uint child1;\n    vec3 min1;\n    uint pad0;\n    vec3 max1;\n    uint pad1;\n};",
        "struct BvhTriangle {\n    float v0[3];\n    uint triangle;\n    float v1[3];\n    float v2[3];\n};",
    ] {
        assert!(structs.contains(decl), "bvh.glsl lacks {decl}");
    }
}

/// The default build (PLOC) and the binned-SAH fallback, each checked for tree invariants.
fn builds(positions: &[[f32; 3]]) -> [Bvh; 2] {
    let builds =
        [Bvh::build_positions(positions).unwrap(), Bvh::build_binned(positions, builder::Params::DEFAULT).unwrap()];
    for bvh in &builds {
        check_tree(bvh, positions);
    }
    builds
}

#[test]
fn matches_brute_force_on_a_triangle_soup() {
    let mut rng = Rng::new(1);
    let positions = soup(3000, &mut rng);
    for bvh in builds(&positions) {
        for i in 0..10_000 {
            // Origins inside and around the soup; some finite segments, mostly open rays.
            let origin = rng.point(-1.5, 1.5);
            let dir = scale(rng.direction(), rng.range(0.1, 10.0));
            let (tmin, tmax) =
                if i % 4 == 0 { (rng.range(0.0, 0.2), rng.range(0.2, 1.0)) } else { (0.0, f32::INFINITY) };
            check_ray(&bvh, &positions, origin, dir, tmin, tmax);
        }
    }
}

#[test]
fn matches_brute_force_on_an_icosphere() {
    let mut rng = Rng::new(2);
    let positions = icosphere(4, [0.3, -0.2, 0.1], 1.0).flat();
    for bvh in builds(&positions) {
        assert_eq!(bvh.stats.triangle_count, 5120);
        for i in 0..10_000 {
            let origin = if i % 2 == 0 { rng.point(-0.4, 0.6) } else { rng.point(-3.0, 3.0) };
            check_ray(&bvh, &positions, origin, rng.direction(), 1e-4, 1e30);
        }
    }
}

/// Rays from inside a closed mesh aimed exactly at its vertices and at points on its edges
/// must hit, at t ≈ 1.
fn assert_watertight(mesh: &Mesh, inside: impl Fn(&mut Rng) -> [f32; 3], seed: u64) {
    let mut rng = Rng::new(seed);
    let mut targets: Vec<[f32; 3]> = mesh.positions.clone();
    for (a, b) in mesh.edges() {
        let (a, b) = (mesh.positions[a as usize], mesh.positions[b as usize]);
        targets.push(lerp(a, b, 0.5));
        targets.push(lerp(a, b, rng.f32()));
    }
    for bvh in builds(&mesh.flat()) {
        let mut rays = 0;
        for target in &targets {
            for _ in 0..4 {
                let origin = inside(&mut rng);
                let dir = sub(*target, origin);
                for any_hit in [false, true] {
                    let hit = bvh.intersect(origin, dir, 0.0, f32::INFINITY, any_hit);
                    let hit = hit.unwrap_or_else(|| panic!("ray from {origin:?} to {target:?} escaped"));
                    assert!((hit.t - 1.0).abs() < 1e-4, "ray from {origin:?} to {target:?} hit at t = {}", hit.t);
                    rays += 1;
                }
            }
        }
        assert!(rays > 1000);
    }
}

#[test]
fn watertight_icosphere() {
    let center = [0.25, -0.5, 0.125];
    let mesh = icosphere(3, center, 2.0);
    assert_watertight(&mesh, |rng| add(center, rng.point(-1.0, 1.0)), 3);
    // From the centre along the axes: direction components exactly 0 put the ray exactly in
    // box face planes (the NaN case of the slab test).
    for bvh in builds(&mesh.flat()) {
        for axis in 0..3 {
            for sign in [-1.0, 1.0] {
                let mut dir = [0.0; 3];
                dir[axis] = sign;
                let hit = bvh.intersect(center, dir, 0.0, f32::INFINITY, false);
                assert!(hit.is_some_and(|h| (h.t - 2.0).abs() < 1e-3), "axis ray {dir:?}: {hit:?}");
            }
        }
    }
}

#[test]
fn watertight_axis_aligned_cube() {
    let mesh = grid_cube(12);
    assert_watertight(&mesh, |rng| rng.point(-0.9, 0.9), 4);
    // From inner grid points along axes and diagonals: through grid vertices and edges, in
    // the planes of box faces.
    let dirs = [[0.0, 0.0, 1.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [1.0, 1.0, 0.0], [1.0, 1.0, 1.0]];
    for bvh in builds(&mesh.flat()) {
        for i in 1..12 {
            for j in 1..12 {
                let origin = [-1.0 + i as f32 / 6.0, -1.0 + j as f32 / 6.0, 0.0];
                for dir in dirs {
                    let hit = bvh.intersect(origin, dir, 0.0, f32::INFINITY, false);
                    assert!(hit.is_some(), "{origin:?} + t {dir:?} escaped");
                }
            }
        }
    }
}

#[test]
fn alpha_filter_sees_every_candidate() {
    let mut rng = Rng::new(5);
    let positions = soup(2000, &mut rng);
    let keep = |triangle: u32, [u, v]: [f32; 2]| triangle % 3 != 0 && u < 0.8 && v < 0.8;
    for bvh in builds(&positions) {
        for _ in 0..3000 {
            let (origin, dir) = (rng.point(-1.5, 1.5), rng.direction());
            let ray = Ray::new(origin, dir);
            let mut expected: Option<Hit> = None;
            for (i, v) in positions.chunks_exact(3).enumerate() {
                let t_max = expected.map_or(f32::INFINITY, |h| h.t);
                if let Some((t, [u, v])) = intersect_triangle(&ray, v[0], v[1], v[2], 0.0, t_max) {
                    if keep(i as u32, [u, v]) {
                        expected = Some(Hit { t, triangle: i as u32, u, v });
                    }
                }
            }
            let got =
                bvh.intersect_filtered(RayQuery { origin, dir, tmin: 0.0, tmax: f32::INFINITY, any_hit: false }, keep);
            assert_eq!(got.map(|h| h.t), expected.map(|h| h.t));
            let any =
                bvh.intersect_filtered(RayQuery { origin, dir, tmin: 0.0, tmax: f32::INFINITY, any_hit: true }, keep);
            assert_eq!(any.is_some(), expected.is_some());
            assert!(any.is_none_or(|h| keep(h.triangle, [h.u, h.v])));
        }
    }
}

#[test]
fn degenerate_and_non_finite_triangles_are_harmless() {
    let mut rng = Rng::new(6);
    let mut positions = soup(500, &mut rng);
    let p = [0.1, 0.2, 0.3];
    positions.extend([p, p, p]); // a point
    positions.extend([p, p, [0.5, 0.5, 0.5]]); // a segment with a repeated vertex
    positions.extend([[0.0; 3], [0.5; 3], [1.0; 3]]); // collinear
    positions.extend([[f32::NAN, 0.0, 0.0], [0.0; 3], [1.0, 0.0, 0.0]]);
    positions.extend([[0.0; 3], [f32::INFINITY, 1.0, 0.0], [1.0, 0.0, 0.0]]);
    for _ in 0..300 {
        positions.extend([p, p, p]); // many identical points: no SAH split possible
    }
    // Brute force over the finite triangles only: the others moved out of the way.
    let finite: Vec<[f32; 3]> = positions
        .chunks_exact(3)
        .flat_map(|v| if v.iter().flatten().all(|c| c.is_finite()) { v.to_vec() } else { vec![[1e30; 3]; 3] })
        .collect();
    for bvh in builds(&positions) {
        assert_eq!(bvh.stats.skipped, 2);
        for _ in 0..2000 {
            check_ray(&bvh, &finite, rng.point(-1.5, 1.5), rng.direction(), 0.0, f32::INFINITY);
        }
        // Rays straight at the degenerate ones.
        for dir in [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 1.0]] {
            check_ray(&bvh, &finite, sub(p, dir), dir, 0.0, f32::INFINITY);
        }
    }
}

#[test]
fn identical_triangles_and_deep_distributions_stay_within_the_stack() {
    // Exponentially spaced triangles: SAH peels one off per level and would go ~1000 deep,
    // and PLOC's Morton codes put nearly all of them in one cell.
    let mut positions = Vec::new();
    for i in 0..1000 {
        let x = (i as f32 / 10.0).exp2();
        positions.extend([[x, 0.0, 0.0], [x * 1.01, 1.0, 0.0], [x, 0.0, 1.0]]);
    }
    let mut rng = Rng::new(7);
    for bvh in builds(&positions) {
        println!("exponential spacing: {}, depth {}", bvh.stats.builder, bvh.stats.max_depth);
        for i in 0..1000 {
            let x = (rng.range(0.0, 100.0)).exp2();
            check_ray(&bvh, &positions, [x, 0.25, -1.0], [0.0, 0.0, 1.0], 0.0, f32::INFINITY);
            check_ray(&bvh, &positions, [-1.0, 0.3, 0.3], [1.0, rng.range(-1e-3, 1e-3), 0.0], 0.0, f32::INFINITY);
            if i % 10 == 0 {
                check_ray_with(&bvh, &positions, rng.point(-2.0, 2.0), rng.direction(), 0.0, f32::INFINITY, false);
            }
        }
    }
    // The same triangle 5000 times: centroids coincide (median splits by index in SAH).
    let same: Vec<[f32; 3]> = (0..5000).flat_map(|_| [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]).collect();
    for bvh in builds(&same) {
        check_ray(&bvh, &same, [0.25, 0.25, 1.0], [0.0, 0.0, -1.0], 0.0, f32::INFINITY);
    }
}

/// A tree too deep for the shader's stack is rebuilt with binned SAH.
#[test]
fn too_deep_ploc_trees_fall_back_to_binned_sah() {
    // Triangles at x = 2^i: each merge in PLOC's clustering takes the next one, a chain.
    let positions: Vec<[f32; 3]> = (0..120)
        .flat_map(|i| {
            let x = (i as f32).exp2();
            [[x, 0.0, 0.0], [x, 1.0, 0.0], [x, 0.0, 1.0]]
        })
        .collect();
    let ploc = Bvh::build_ploc(&positions, ploc::PARAMS).unwrap();
    let bvh = Bvh::build_positions(&positions).unwrap();
    check_tree(&bvh, &positions);
    if ploc.stats.max_depth > BVH_MAX_DEPTH {
        assert_eq!(bvh.stats.builder, BUILDER_SAH_FALLBACK);
    } else {
        panic!("PLOC made this chain only {} deep; the test needs a deeper one", ploc.stats.max_depth);
    }
}

#[test]
fn huge_coordinates_do_not_break_the_build() {
    let mut rng = Rng::new(8);
    let positions: Vec<[f32; 3]> = soup(200, &mut rng).into_iter().map(|p| scale(p, 1e37)).collect();
    for bvh in builds(&positions) {
        for _ in 0..200 {
            check_ray(&bvh, &positions, scale(rng.point(-1.0, 1.0), 1e37), rng.direction(), 0.0, f32::INFINITY);
        }
    }
}

#[test]
fn one_triangle_is_a_root_leaf() {
    let positions = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    for bvh in builds(&positions) {
        assert_eq!(bvh.nodes.len(), 1);
        assert_eq!(ChildRef(bvh.nodes[0].child0).triangles(), 0..1);
        assert!(bvh.nodes[0].min1[0] > bvh.nodes[0].max1[0], "its second child is empty");
        let (o, d) = ([0.25, 0.5, 1.0], [0.0, 0.0, -2.0]);
        let hit = bvh.intersect(o, d, 0.0, 10.0, false).unwrap();
        assert_eq!((hit.t, hit.triangle, hit.u, hit.v), (0.5, 0, 0.25, 0.5));
        assert!(bvh.intersect(o, d, 0.0, 0.5, false).is_none(), "t < tmax strictly");
        assert!(bvh.intersect(o, d, 0.5, 10.0, false).is_none(), "t > tmin strictly");
        assert!(bvh.intersect(o, [0.0, 0.0, 2.0], 0.0, 10.0, false).is_none(), "behind");
    }
}

#[test]
fn bad_input_is_an_error() {
    assert!(matches!(Bvh::build(&[]), Err(AccelError::Empty)));
    assert!(matches!(Bvh::build_positions(&[[0.0; 3]; 4]), Err(AccelError::NotTriangles(4))));
    let nan = [[f32::NAN; 3]; 6];
    assert!(matches!(Bvh::build_positions(&nan), Err(AccelError::NoFiniteTriangles(2))));
    for e in [AccelError::Empty, AccelError::NotTriangles(4), AccelError::NoFiniteTriangles(2)] {
        assert!(!e.to_string().contains('\n'));
    }
}

#[test]
fn bad_rays_miss_without_panicking() {
    let mut rng = Rng::new(9);
    let positions = soup(100, &mut rng);
    let bvh = Bvh::build_positions(&positions).unwrap();
    let nan = f32::NAN;
    for (origin, dir) in [
        ([0.0; 3], [0.0; 3]),
        ([nan; 3], [0.0, 0.0, 1.0]),
        ([0.0; 3], [nan, 0.0, 1.0]),
        ([0.0; 3], [f32::INFINITY, 0.0, 0.0]),
        ([f32::INFINITY; 3], [1.0, 0.0, 0.0]),
    ] {
        assert_eq!(bvh.intersect(origin, dir, 0.0, f32::INFINITY, false), None, "{origin:?} + t {dir:?}");
        assert_eq!(bvh.intersect(origin, dir, 0.0, f32::INFINITY, true), None);
    }
    assert_eq!(bvh.intersect([0.0; 3], [0.0, 0.0, 1.0], nan, nan, false), None);
}

#[test]
fn builds_from_scene_vertices() {
    let vertex = |p: [f32; 3]| Vertex { position: p, ..Default::default() };
    let vertices: Vec<Vertex> = icosphere(1, [0.0; 3], 1.0).flat().into_iter().map(vertex).collect();
    let bvh = Bvh::build(&vertices).unwrap();
    assert_eq!(bvh.stats.triangle_count, 80);
    assert!(bvh.intersect([0.0; 3], [0.3, 0.2, 0.1], 0.0, f32::INFINITY, true).is_some());
}

/// Builder measurement on two 200k-triangle procedural scenes (run in release:
/// `cargo test --release -p leakless-accel -- --ignored --nocapture measure`).
/// Work per ray (nodes visited, triangles tested) is counted by our traversal on every tree,
/// obvhs' ones flattened into our layout, with a stack deep enough for all of them.
#[test]
#[ignore]
fn measure() {
    for (scene, positions, lo, hi) in [
        ("mixed: terrain, spheres, 3.6k thin boxes", measurement_scene(), [-10.0, 0.05, -10.0], [10.0, 6.0, 10.0]),
        ("one bumpy torus", bumpy_torus(), [-3.0, -1.0, -3.0], [3.0, 1.0, 3.0]),
    ] {
        let mut rng = Rng::new(10);
        // Incoherent rays like photon paths and gathers, origins within the scene box.
        let rays: Vec<([f32; 3], [f32; 3])> =
            (0..100_000).map(|_| ([0, 1, 2].map(|a| rng.range(lo[a], hi[a])), rng.direction())).collect();
        let short = 0.1 * (0..3).map(|a| hi[a] - lo[a]).fold(0.0, f32::max);
        println!(
            "\n{scene}: {} triangles, {} rays (closest hit; any hit with tmax = {short})",
            positions.len() / 3,
            rays.len()
        );
        let report = |name: &str, bvh: &Bvh| {
            let (mut closest, mut any) = (TraversalCounts::default(), TraversalCounts::default());
            let start = Instant::now();
            for &(o, d) in &rays {
                bvh.traverse_with_stack::<64>(
                    RayQuery { origin: o, dir: d, tmin: 0.0, tmax: f32::INFINITY, any_hit: false },
                    |_, _| true,
                    &mut closest,
                );
            }
            let ns = start.elapsed().as_secs_f64() * 1e9 / rays.len() as f64;
            for &(o, d) in &rays {
                bvh.traverse_with_stack::<64>(
                    RayQuery { origin: o, dir: d, tmin: 0.0, tmax: short, any_hit: true },
                    |_, _| true,
                    &mut any,
                );
            }
            let n = rays.len() as f64;
            let s = &bvh.stats;
            println!(
                "  {name:<34} build {:6.1} ms  {:6} nodes  {:5.2} MB  depth {:2}  SAH {:6.1}  closest {:5.1} nodes + {:5.2} tris/ray ({:4.0} ns/ray CPU)  any {:5.1} + {:5.2}",
                s.build_ms,
                s.node_count,
                s.bytes as f64 / 1e6,
                s.max_depth,
                s.sah_cost,
                closest.nodes as f64 / n,
                closest.triangles as f64 / n,
                ns,
                any.nodes as f64 / n,
                any.triangles as f64 / n,
            );
        };
        for (max_leaf, bins) in [(4, 16), (4, 32), (4, 8), (2, 16), (8, 16)] {
            let bvh = Bvh::build_binned(&positions, builder::Params { max_leaf, bins }).unwrap();
            report(&format!("binned SAH, leaf <= {max_leaf}, {bins} bins"), &bvh);
        }
        {
            use ::obvhs::BvhBuildParams as P;
            for (name, params) in [
                ("fastest_build", P::fastest_build()),
                ("fast_build", P::fast_build()),
                ("medium_build", P::medium_build()),
                ("slow_build", P::slow_build()),
            ] {
                // Leaves of at most 4 and node cost = triangle cost, as ours.
                let like_ours =
                    P { max_prims_per_leaf: params.max_prims_per_leaf.min(4), collapse_traversal_cost: 1.0, ..params };
                report(&format!("obvhs {name}, leaf <= 4"), &Bvh::build_ploc(&positions, like_ours).unwrap());
                if name == "medium_build" {
                    report("obvhs medium_build as shipped", &Bvh::build_ploc(&positions, params).unwrap());
                }
            }
        }
    }
}

/// A 200k-triangle torus with bumps: one dense closed mesh, like a scanned model.
fn bumpy_torus() -> Vec<[f32; 3]> {
    let (n, m) = (500u32, 200u32);
    let p = |i: u32, j: u32| {
        let (a, b) = (std::f32::consts::TAU * i as f32 / n as f32, std::f32::consts::TAU * j as f32 / m as f32);
        let r = 0.5 + 0.05 * (7.0 * a).sin() * (5.0 * b).cos();
        [(2.0 + r * b.cos()) * a.cos(), r * b.sin(), (2.0 + r * b.cos()) * a.sin()]
    };
    let mut out = Vec::with_capacity(6 * (n * m) as usize);
    for i in 0..n {
        for j in 0..m {
            let (i1, j1) = ((i + 1) % n, (j + 1) % m);
            out.extend([p(i, j), p(i1, j), p(i1, j1), p(i, j), p(i1, j1), p(i, j1)]);
        }
    }
    out
}

/// ~200k triangles: a bumpy terrain, a field of icospheres and a few thousand random thin
/// boxes (walls, beams): dense and sparse regions and large and small triangles, as scenes have.
fn measurement_scene() -> Vec<[f32; 3]> {
    let mut rng = Rng::new(11);
    let mut out = Vec::new();
    let n = 200;
    let height = |x: f32, z: f32| 0.3 * (x * 0.7).sin() * (z * 0.5).cos() + 0.05 * (x * 5.0).sin();
    let grid = |i: u32| -10.0 + 20.0 * i as f32 / n as f32;
    for i in 0..n {
        for j in 0..n {
            let p = |di: u32, dj: u32| {
                let (x, z) = (grid(i + di), grid(j + dj));
                [x, height(x, z), z]
            };
            out.extend([p(0, 0), p(1, 0), p(1, 1), p(0, 0), p(1, 1), p(0, 1)]);
        }
    }
    for _ in 0..60 {
        let c = [rng.range(-9.0, 9.0), rng.range(0.5, 4.0), rng.range(-9.0, 9.0)];
        out.extend(icosphere(3, c, rng.range(0.1, 1.0)).flat()); // 1280 each
    }
    while out.len() < 3 * 200_000 {
        let c = [rng.range(-10.0, 10.0), rng.range(0.0, 5.0), rng.range(-10.0, 10.0)];
        let e = [rng.range(0.02, 3.0), rng.range(0.02, 2.0), rng.range(0.02, 0.1)];
        let e = if rng.f32() < 0.5 { e } else { [e[2], e[1], e[0]] };
        let cube = grid_cube(1);
        out.extend(cube.flat().into_iter().map(|p| [c[0] + p[0] * e[0], c[1] + p[1] * e[1], c[2] + p[2] * e[2]]));
    }
    out.truncate(3 * 200_000);
    out
}
