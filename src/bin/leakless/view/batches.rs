//! How many batches a still view's frames grow to: as many as keep a frame within the
//! app's budget, measured on this device (docs/architecture.md §9).

use leakless::Method;

use super::Running;

/// A still view's frames grow only while they stay within this (fit_batches) when no frame
/// budget is set (`--frame-ms off`): 10 frames a second keeps keys and the mouse answered at
/// once. With a budget, its target.
const STILL_FRAME_BUDGET_MS: f64 = 100.0;
/// Frames before one is taken to measure the time of a batch.
const WARM_UP_FRAMES: u64 = 4;

/// Whether the host interval that ended at the start of tick `tick - 1` (the time of tick
/// `tick - 2`, which `frame_ms` holds when tick `tick` fits the batches) is a frame like the
/// others. A profiled tick (`tick % profile_every == 1`) submits each pass alone and waits,
/// so it is slower; the one after it finds the frames before already done and waits for
/// none, so it is faster. Neither measures a batch.
fn interval_is_typical(tick: u64, profile_every: u64) -> bool {
    let measured = tick.wrapping_sub(2);
    profile_every == 0 || !matches!(measured % profile_every, 1 | 2)
}

impl Running {
    /// How many batches (of photon paths, or of reference samples) a still view's frames may
    /// grow to, so that a frame stays within the frame budget (`STILL_FRAME_BUDGET_MS` without
    /// one) and the app answers a key
    /// at once. A frame of B batches is taken to cost B times the last frame's time per batch
    /// (an upper bound: the view samples' work is shared), with that time grown as the
    /// photon–sample pairs grow up to the accumulation's largest radius
    /// ([`Running::radius_growth`]). Fitted at the start of each accumulation, and once more
    /// when the first measurement of the method arrives (frames do not grow before it). On a
    /// GPU a batch takes milliseconds and frames grow to the limit; on lavapipe at the default
    /// size one photon batch already fills the budget and frames stay at one.
    pub(super) fn fit_batches(&mut self) -> anyhow::Result<()> {
        let fresh = self.renderer.accumulated() == 0;
        if !fresh && self.batches_fitted {
            return Ok(());
        }
        let s = self.renderer.settings();
        // The first frames (pipelines warming, lists growing) are slower than the rest.
        let settled =
            self.frame > WARM_UP_FRAMES && self.frame_ms > 0.0 && interval_is_typical(self.frame, self.profile_every);
        // A frame of the method now drawn: after a switch, the last one may be of another.
        let measured =
            self.renderer.last_report().filter(|r| settled && r.method == s.method && r.method != Method::Direct);
        let fit = match measured {
            Some(last) => {
                self.batches_fitted = true;
                let budget = self.renderer.frame_budget().map_or(STILL_FRAME_BUDGET_MS, |b| b.target_ms());
                // A moving frame's paths are the budget's: a still batch's cost scales to --paths.
                let paths = last
                    .splat
                    .as_ref()
                    .map_or(1.0, |sp| s.splat.paths as f64 * last.frame_batches as f64 / sp.paths.max(1) as f64);
                let growth = self.radius_growth(last) * paths;
                batches_within_budget(budget, self.frame_ms, last.frame_batches, growth, self.batch_limit)
            }
            None if fresh => {
                // Refit once a frame of this method has been measured (after a switch, none has).
                self.batches_fitted = false;
                1
            }
            None => return Ok(()),
        };
        if fit != s.max_batches {
            self.renderer.update(|s| s.max_batches = fit)?;
        }
        Ok(())
    }

    /// How much more a batch of a still view's accumulation may cost than the batch of `last`:
    /// its photon–sample pairs grow with the gather disk's area, and the accumulation's largest
    /// disk is its second batch's, twice the single frame's shrunk once
    /// (`splatting::progressive_radius`). (r₁ / r)², at least 1, applied to the whole batch:
    /// on the safe side, since the passes that do not gather do not grow. The frame measured is
    /// often the moving view's (radius r₀: 3.3×) or the last of a long accumulation (whose
    /// radius is smaller still).
    fn radius_growth(&self, last: &leakless::FrameReport) -> f64 {
        let Some(measured) = last.splat.as_ref().map(|s| s.radius) else {
            return 1.0; // the reference: its batches cost the same
        };
        let single = self.renderer.single_frame_radius(self.renderer.settings().splat.paths);
        pair_growth(measured, single)
    }
}

/// (r₁ / r)², at least 1: how much more a batch at the accumulation's largest radius r₁ (its
/// second batch's, from the single frame's radius `single`) costs than one at `measured`.
fn pair_growth(measured: f32, single: f32) -> f64 {
    if measured.is_nan() || measured <= 0.0 {
        return 1.0;
    }
    let largest = leakless::splatting::progressive_radius(single, 1) as f64;
    (largest / measured as f64).powi(2).max(1.0)
}

/// Batches a still frame may hold: as many as fit `budget_ms` at `frame_ms` for a frame of
/// `frame_batches`, each batch grown by `growth`; from 1 to `limit`.
fn batches_within_budget(budget_ms: f64, frame_ms: f64, frame_batches: u32, growth: f64, limit: u32) -> u32 {
    let per_batch = frame_ms / frame_batches.max(1) as f64 * growth;
    (budget_ms / per_batch).floor().clamp(1.0, limit as f64) as u32
}

#[cfg(test)]
mod tests {
    use super::{batches_within_budget, interval_is_typical, pair_growth, STILL_FRAME_BUDGET_MS};
    use leakless::splatting::{progressive_radius, ACCUMULATION_RADIUS_SCALE, PPM_ALPHA};

    #[test]
    fn a_still_frame_holds_the_batches_that_fit_at_the_largest_radius() {
        // Measured on the moving view's frame (the single frame's radius): the second batch's
        // disk is 2·√((1 + α)/2) times wider, so a batch costs 4·(1 + α)/2 = 3.33× as much.
        let moving = pair_growth(0.5, 0.5);
        let expected = ACCUMULATION_RADIUS_SCALE.powi(2) * (1.0 + PPM_ALPHA) / 2.0;
        assert!((moving - expected).abs() < 1e-5, "{moving} against {expected}");
        // Measured at the largest radius itself, or later (smaller): no growth below 1.
        assert!((pair_growth(progressive_radius(0.5, 1), 0.5) - 1.0).abs() < 1e-6);
        assert!(pair_growth(progressive_radius(0.5, 40), 0.5) > 1.0, "later batches are smaller");
        assert_eq!(pair_growth(0.0, 0.5), 1.0, "no radius measured");
        // 9 ms a batch at the single frame's radius: 30 ms at the largest, 3 in 100 ms, where
        // the unscaled time would have allowed 11.
        assert_eq!(batches_within_budget(STILL_FRAME_BUDGET_MS, 18.0, 2, moving, 64), 3);
        assert_eq!(batches_within_budget(STILL_FRAME_BUDGET_MS, 18.0, 2, 1.0, 64), 11);
        // At least one batch, at most the limit.
        assert_eq!(batches_within_budget(STILL_FRAME_BUDGET_MS, 500.0, 1, moving, 64), 1);
        assert_eq!(batches_within_budget(STILL_FRAME_BUDGET_MS, 0.5, 1, 1.0, 8), 8);
    }

    #[test]
    fn the_intervals_of_a_profiled_tick_and_the_one_after_it_do_not_measure_a_batch() {
        // Profiled ticks 1, 31, 61, …: their times reach fit_batches at ticks 3, 33, …, and the
        // times of the ticks after them at 4, 34, ….
        let skipped: Vec<u64> = (3..70).filter(|&t| !interval_is_typical(t, 30)).collect();
        assert_eq!(skipped, [3, 4, 33, 34, 63, 64]);
        // Without profiling (GPUs) every interval counts.
        assert!((0..100).all(|t| interval_is_typical(t, 0)));
    }
}
