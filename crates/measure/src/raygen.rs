//! Ray sets for tests and benchmarks: camera rays (coherent), hemisphere rays from surface
//! hits (incoherent), random rays through the scene. Deterministic for a seed.

use glam::{Vec2, Vec3};
use leakless_scene::{Camera, Scene};

use crate::raycast::offset_ray;
use leakless::gpu_types::{GpuRay, RayHit};

/// The seeded generator of test and benchmark rays (a PCG of rand_pcg): the same rays for a
/// seed on every run.
pub struct SeededRng(rand_pcg::Pcg64Mcg);

impl SeededRng {
    pub fn new(seed: u64) -> Self {
        SeededRng(rand_core::SeedableRng::seed_from_u64(seed))
    }

    pub fn next_u64(&mut self) -> u64 {
        rand_core::RngCore::next_u64(&mut self.0)
    }

    /// Uniform in [0, 1).
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }

    /// Uniform on the unit sphere.
    pub fn direction(&mut self) -> Vec3 {
        let z = 1.0 - 2.0 * self.next_f32();
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = 2.0 * std::f32::consts::PI * self.next_f32();
        Vec3::new(r * phi.cos(), r * phi.sin(), z)
    }
}

pub const FAR: f32 = 1e30;

/// One ray through the centre of every pixel, row by row from the top.
pub fn camera_rays(camera: &Camera, width: u32, height: u32) -> Vec<GpuRay> {
    let tan_half = (camera.yfov / 2.0).tan();
    let aspect = width as f32 / height as f32;
    let origin = camera.position();
    let m = camera.world_from_camera;
    (0..height)
        .flat_map(|y| (0..width).map(move |x| (x, y)))
        .map(|(x, y)| {
            let ndc =
                Vec2::new((x as f32 + 0.5) / width as f32 * 2.0 - 1.0, 1.0 - (y as f32 + 0.5) / height as f32 * 2.0);
            let local = Vec3::new(ndc.x * tan_half * aspect, ndc.y * tan_half, -1.0);
            let dir = m.transform_vector3(local).normalize();
            GpuRay { origin: origin.to_array(), tmin: 0.0, dir: dir.to_array(), tmax: FAR }
        })
        .collect()
}

/// The plane normal of triangle `t`, facing against `dir`.
pub fn facing_normal(scene: &Scene, t: usize, dir: Vec3) -> Vec3 {
    let v = |i: usize| Vec3::from(scene.vertices[3 * t + i].position);
    let n = (v(1) - v(0)).cross(v(2) - v(0)).normalize_or_zero();
    if n.dot(dir) > 0.0 {
        -n
    } else {
        n
    }
}

/// From every hit of `primary`, a ray into a uniformly random direction of the hemisphere on
/// the ray's side of the surface: incoherent secondary rays, starting on surfaces.
pub fn hemisphere_rays(scene: &Scene, primary: &[GpuRay], hits: &[RayHit], seed: u64) -> Vec<GpuRay> {
    let mut rng = SeededRng::new(seed);
    let scale = leakless::trace::scene_scale(scene);
    primary
        .iter()
        .zip(hits)
        .filter(|(_, h)| h.triangle != u32::MAX)
        .map(|(r, h)| {
            let d = Vec3::from(r.dir);
            let p = Vec3::from(r.origin) + h.t * d;
            let n = facing_normal(scene, h.triangle as usize, d);
            let mut dir = rng.direction();
            if dir.dot(n) < 0.0 {
                dir = -dir;
            }
            GpuRay { origin: offset_ray(p, n, scale).to_array(), tmin: 0.0, dir: dir.to_array(), tmax: FAR }
        })
        .collect()
}

/// `count` rays from random points of the scene's bounding box (slightly enlarged) in random
/// directions, each with a random finite or infinite extent.
pub fn random_rays(scene: &Scene, count: usize, seed: u64) -> Vec<GpuRay> {
    let b = scene.bounds();
    let (lo, size) = (b.min - 0.1 * b.extent(), 1.2 * b.extent());
    let mut rng = SeededRng::new(seed);
    (0..count)
        .map(|_| {
            let o = lo + size * Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
            let tmax = if rng.next_f32() < 0.5 { FAR } else { rng.next_f32() * b.diagonal() };
            GpuRay { origin: o.to_array(), tmin: 0.0, dir: rng.direction().to_array(), tmax }
        })
        .collect()
}
