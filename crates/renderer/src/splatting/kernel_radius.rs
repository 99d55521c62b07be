//! The gather radius that follows the photon count: the radius at which a kernel holds about
//! K photons, from the density of photons on the surfaces the view sees.
//!
//! A frame's gather counts the photons its kernels took (within the radius, facing the
//! sample): over its valid samples that is the mean photons a kernel, N. Photons a kernel grow
//! with the paths p and the disk's area, N ≈ ρ·p·r², ρ being the view's density (photons per
//! path and per unit of squared radius, averaged over the samples as the gather averages
//! them). One frame's N gives ρ, and the radius for K photons at p paths is √(K / (ρ·p)).
//! Fixing K rather than r keeps the gather's work per sample about K whatever the paths, so
//! more photons buy a sharper image rather than quadratically more candidates.

/// K, photons a kernel holds by default. Measured as error against time at K = 8 … 128 on the
/// shipped scenes at two sizes (docs/results.md, "Photons a kernel").
pub const DEFAULT_KERNEL_PHOTONS: f32 = 32.0;

/// The count-following radius stays within these multiples of the scene's fixed radius
/// (`auto_radius`, 5% of its bounding radius): below, a kernel would hold the photons of a
/// handful of pixels (a scene of few visible photons grows it up to 4×: beyond, its bias
/// would blur whole walls, and its list work grows with r² while its photons stay few).
pub const KERNEL_RADIUS_RANGE: (f32, f32) = (1.0 / 64.0, 4.0);

/// The view's photon density: photons a kernel holds per light path and per unit of squared
/// radius, averaged over the view's samples.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KernelDensity(f64);

impl KernelDensity {
    /// The density of a frame whose `samples` kernels of radius `radius` took `accepted`
    /// photons of `paths` light paths; `None` when it took none (no photon reaches the view:
    /// a sealed room, a light facing away), where no radius changes the image.
    pub fn measured(accepted: u64, samples: u32, paths: u32, radius: f32) -> Option<KernelDensity> {
        let area = radius as f64 * radius as f64;
        let per_kernel = accepted as f64 / samples.max(1) as f64;
        (accepted > 0 && paths > 0 && area > 0.0 && area.is_finite())
            .then(|| KernelDensity(per_kernel / (paths as f64 * area)))
    }

    /// Photons a kernel of `radius` holds at `paths` paths.
    pub fn photons_per_kernel(&self, paths: u32, radius: f32) -> f64 {
        self.0 * paths as f64 * radius as f64 * radius as f64
    }

    /// The radius at which a kernel holds `kernel_photons` photons of `paths` paths, within
    /// `KERNEL_RADIUS_RANGE` of `fixed_radius` (the scene's 5% radius).
    pub fn radius(&self, kernel_photons: f32, paths: u32, fixed_radius: f32) -> f32 {
        let r = (kernel_photons as f64 / (self.0 * paths.max(1) as f64)).sqrt() as f32;
        let (lo, hi) = KERNEL_RADIUS_RANGE;
        r.clamp(lo * fixed_radius, hi * fixed_radius)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A measured frame's own radius gives back its own count, and the radius for K falls as
    /// 1/√paths and grows as √K: N ∝ p·r².
    #[test]
    fn the_radius_holds_k_photons_at_any_paths() {
        // 40 photons a kernel over 1000 samples at radius 0.5 and 10k paths.
        let d = KernelDensity::measured(40_000, 1000, 10_000, 0.5).expect("photons seen");
        assert!((d.photons_per_kernel(10_000, 0.5) - 40.0).abs() < 1e-9);
        let fixed = 1.0;
        let r10 = d.radius(10.0, 10_000, fixed);
        assert!((r10 - 0.25).abs() < 1e-6, "a quarter of the photons, half the radius: {r10}");
        let r40 = d.radius(10.0, 40_000, fixed);
        assert!((r40 - 0.125).abs() < 1e-6, "4× the paths, half the radius: {r40}");
        for (k, paths) in [(8.0, 1024), (32.0, 80_000), (128.0, 5_000)] {
            let r = d.radius(k, paths, fixed);
            assert!((d.photons_per_kernel(paths, r) - k as f64).abs() < 1e-3 * k as f64, "K {k} at {paths}");
        }
    }

    /// No photon seen measures nothing; the radius never leaves its range of the fixed one.
    #[test]
    fn no_photons_measure_nothing_and_the_radius_stays_in_range() {
        assert_eq!(KernelDensity::measured(0, 1000, 10_000, 0.5), None);
        assert_eq!(KernelDensity::measured(10, 1000, 0, 0.5), None);
        assert_eq!(KernelDensity::measured(10, 1000, 10, 0.0), None);
        let sparse = KernelDensity::measured(1, 1_000_000, 1024, 0.1).unwrap();
        assert_eq!(sparse.radius(32.0, 1024, 2.0), 2.0 * KERNEL_RADIUS_RANGE.1);
        let dense = KernelDensity::measured(u64::MAX / 2, 1, 1, 1.0).unwrap();
        assert_eq!(dense.radius(32.0, 1 << 30, 2.0), 2.0 * KERNEL_RADIUS_RANGE.0);
    }
}
