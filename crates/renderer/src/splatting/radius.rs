//! The gather radius of every photon batch: the single frame's, the shrinking sequence of an
//! accumulation (progressive photon mapping), the partial disks' growth and shrink, and how
//! many batches each frame of an accumulation traces.

/// The scene's fixed radius, 5% of its bounding radius: the first guess of the count-following
/// radius ([`super::KernelDensity`]) and the unit of its range.
pub fn auto_radius(scene: &crate::Scene) -> f32 {
    0.05 * scene.bounds().bounding_radius()
}

/// The exponent α of the radius reduction of progressive photon mapping (Knaus and Zwicker,
/// "Progressive Photon Mapping: A Probabilistic Approach", 2011): r²ᵢ₊₁ = r²ᵢ (i + α)/(i + 1).
/// Any α in (0, 1) makes the average of the frames converge; 2/3 is their choice, balancing
/// the variance that a shrinking radius adds against the bias it removes.
pub const PPM_ALPHA: f64 = 2.0 / 3.0;

/// How much larger than the single frame's radius the shrinking sequence of an accumulation
/// starts. Batch 0 is the single frame the app shows while the view moves, at the radius chosen
/// for one frame; the batches after it are averaged, so their noise matters less than their
/// bias, and a larger start trades the one for the other. Measured at equal wall time (docs/results.md,
/// "Converging while the view is still"): 2 lowers relMSE at 1 s and 10 s in the atrium, the
/// doorway and the Cornell box, and HDR-FLIP in the first two and the Cornell box at 10 s (at
/// 1 s it stays within a run's spread); 4, measured on the atrium with the single frame at 4×
/// too, lets the bias take over. With the partial-disk radius, 1.5 and 3 were measured again on
/// the atrium: both are worse in HDR-FLIP at 10 s (1.27×, 1.24× the path tracer's, against
/// 1.22×).
pub const ACCUMULATION_RADIUS_SCALE: f64 = 2.0;

/// The gather radius of photon batch `index` (0-based) of an accumulation whose single frame
/// has `radius` r: batch 0 has r exactly (the single frame), and batch i ≥ 1 follows the global
/// radius sequence of Knaus and Zwicker from s·r (s = `ACCUMULATION_RADIUS_SCALE`),
/// r²ᵢ = (s·r)² Πⱼ₌₁..ᵢ (j + α)/(j + 1), one radius per batch of `paths` paths for every pixel
/// (no batch has s·r itself: batch 1 is already shrunk once).
/// It needs no per-pixel state (unlike SPPM's per-pixel radius, which needs each pixel's photon
/// count), so each batch stays an independent estimate and the image is their plain average.
/// A frame of several batches gives all of them its first batch's radius: indexing by batches,
/// not frames, makes the radius follow the photons traced so far however frames group them (as
/// SPPM's follows each pixel's photon count).
pub fn progressive_radius(radius: f32, index: u32) -> f32 {
    if index == 0 {
        return radius; // exactly: a single frame is the frame without accumulation
    }
    let mut r2 = ACCUMULATION_RADIUS_SCALE * ACCUMULATION_RADIUS_SCALE;
    for i in 1..=index {
        r2 *= (i as f64 + PPM_ALPHA) / (i as f64 + 1.0);
    }
    (radius as f64 * r2.sqrt()) as f32
}

/// The least share of the frame's radius a partial disk shrinks to (visible_disk.comp): a
/// corner's quarter disk keeps half the radius. The gather's fixed point allows for the
/// kernel's peak there ([`crate::passes::gather::fixed_scale`]).
pub const MIN_RADIUS_SHARE: f32 = 0.5;

/// The largest share of the frame's radius a partial disk grows to in a single frame
/// (visible_disk.comp). Measured on the atrium's single frames at twice the default radius,
/// where bias dominates: −1.0% in the mean with 1.5, −4.5% with 2 (−0.4% with 1.5 since the
/// visible disk's probes stop at the tangent plane; the corner-bias target is 5%).
pub const MAX_RADIUS_SHARE: f32 = 1.5;

/// The exponent γ of a single frame's partial disks: r·min(m^γ, g) with γ = −1 grows a disk
/// of share m until it holds about a whole disk's photons (a half disk to 1.5r rather than
/// √2·r: a partial disk's share falls as it grows). Single frames at 10k paths, 96×72, seeds
/// 1–16, relMSE of the indirect layer against the whole disk's: Cornell box 1.11× with γ = 0,
/// 0.99× with −1; doorway 1.05× and 0.97×. γ = −0.5 left the Cornell box 2% worse.
pub const SINGLE_FRAME_RADIUS_EXPONENT: f32 = -1.0;

/// Batches over which the partial-disk shrink of an accumulation ramps in.
pub const PARTIAL_RADIUS_RAMP_BATCHES: f32 = 64.0;

/// The exponent γ of the partial-disk radius (r·clamp(m^γ, ½, g), visible_disk.comp) for a
/// frame whose first batch is `first_batch`: `SINGLE_FRAME_RADIUS_EXPONENT` (grow) for batch 0,
/// the single frame, whose error is its noise; then from 1/64 at batch 1 (whose radius is
/// already near twice the single frame's) linearly to 1 (shrink) at
/// `PARTIAL_RADIUS_RAMP_BATCHES`. A partial disk's bias is of first order in r, its noise grows
/// as the disk shrinks, and only the noise falls as batches add up, so the best shrink deepens
/// with the photons traced. Measured with the whole shrink from batch 1: the Cornell box's 16
/// one-batch frames got 12% worse in relMSE (0.01449 → 0.01621) while 239 atrium batches got
/// 19% better at the edges.
pub fn partial_radius_exponent(first_batch: u32) -> f32 {
    if first_batch == 0 {
        return SINGLE_FRAME_RADIUS_EXPONENT;
    }
    (first_batch as f32 / PARTIAL_RADIUS_RAMP_BATCHES).min(1.0)
}

/// The largest radius any sample of a frame at `radius` gathers within: grown partial disks
/// reach `MAX_RADIUS_SHARE`·r in a single frame (`first_batch` 0) when `partial` is on.
pub fn largest_gather_radius(radius: f32, first_batch: u32, partial: bool) -> f32 {
    if partial && partial_radius_exponent(first_batch) < 0.0 {
        MAX_RADIUS_SHARE * radius
    } else {
        radius
    }
}

/// Photon batches frame `index` (0-based) of an accumulation traces: 1, 2, 4, … up to
/// `max_batches`. Frame 0 is one batch, exactly the frame without accumulation; doubling
/// keeps the first second's frames short while the per-frame work soon weighs little.
pub fn frame_batches(index: u32, max_batches: u32) -> u32 {
    1u32.checked_shl(index).unwrap_or(u32::MAX).min(max_batches.max(1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_double_their_batches_up_to_the_most() {
        let batches: Vec<u32> = (0..6).map(|k| frame_batches(k, 8)).collect();
        assert_eq!(batches, [1, 2, 4, 8, 8, 8]);
        assert_eq!(frame_batches(40, 8), 8, "a shift past the word's width");
        assert_eq!(frame_batches(u32::MAX, 64), 64);
        assert_eq!((frame_batches(0, 1), frame_batches(5, 1)), (1, 1));
        assert_eq!(frame_batches(3, 0), 1, "at least one batch");
    }

    /// The single frame keeps the frame's radius (its partial disks grow from it, per sample);
    /// the accumulation's sequence starts from twice it and
    /// shrinks by Knaus and Zwicker's ratio, so r² falls as i^(α − 1) (its bias vanishes).
    #[test]
    fn the_accumulation_radius_starts_from_twice_the_single_frames_and_shrinks() {
        assert_eq!(progressive_radius(0.3, 0), 0.3);
        let r = |i| progressive_radius(1.0, i) as f64;
        let first = ACCUMULATION_RADIUS_SCALE * ((1.0 + PPM_ALPHA) / 2.0).sqrt();
        assert!((r(1) - first).abs() < 1e-6, "batch 1: {}", r(1));
        for i in 1..50u32 {
            let ratio = (r(i + 1) / r(i)).powi(2);
            let expected = (i as f64 + 1.0 + PPM_ALPHA) / (i as f64 + 2.0);
            assert!((ratio - expected).abs() < 1e-5, "batch {i}: r² shrinks by {ratio}, not {expected}");
        }
        // r²ᵢ ~ C i^(α − 1): doubling i far out scales r² by 2^(α − 1).
        let slope = (r(20000) / r(10000)).powi(2).log2();
        assert!((slope - (PPM_ALPHA - 1.0)).abs() < 1e-3, "r² falls as i^{slope}");
    }
}
