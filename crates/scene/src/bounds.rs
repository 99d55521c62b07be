//! Axis-aligned bounds: the scene's extent drives the default camera, scale-aware
//! ray epsilons, Morton quantisation and the directional lights' emission disk.

use glam::Vec3;

/// An axis-aligned box. `min <= max` component-wise for any box built from points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: Vec3,
    pub max: Vec3,
}

impl Aabb {
    /// Bounds of `points`; a zero-size box at the origin when there are none, so
    /// that callers never see infinities.
    pub fn from_points(points: impl IntoIterator<Item = Vec3>) -> Aabb {
        let mut min = Vec3::splat(f32::INFINITY);
        let mut max = Vec3::splat(f32::NEG_INFINITY);
        for p in points {
            min = min.min(p);
            max = max.max(p);
        }
        if min.x > max.x {
            return Aabb { min: Vec3::ZERO, max: Vec3::ZERO };
        }
        Aabb { min, max }
    }

    pub fn center(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    /// Size along each axis (`max - min`).
    pub fn extent(&self) -> Vec3 {
        self.max - self.min
    }

    /// Length of the diagonal.
    pub fn diagonal(&self) -> f32 {
        self.extent().length()
    }

    /// Radius of the sphere around [`Aabb::center`] that encloses the box.
    pub fn bounding_radius(&self) -> f32 {
        self.diagonal() * 0.5
    }

    /// The eight corners (bit 0 picks x, bit 1 y, bit 2 z from `max`).
    pub fn corners(&self) -> [Vec3; 8] {
        std::array::from_fn(|i| {
            Vec3::new(
                if i & 1 != 0 { self.max.x } else { self.min.x },
                if i & 2 != 0 { self.max.y } else { self.min.y },
                if i & 4 != 0 { self.max.z } else { self.min.z },
            )
        })
    }

    pub fn contains(&self, p: Vec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }
}
