//! How many batches a still view's frames grow to: as many as keep a frame within the
//! app's budget, measured on this device (docs/architecture.md §9).

use leakless::Method;

use super::Running;

/// A still view's frames grow only while they stay within this (fit_batches): 10 frames a
/// second keeps keys and the mouse answered at once.
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
    /// grow to, so that a frame stays within `STILL_FRAME_BUDGET_MS` and the app answers a key
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
                let per_batch = self.frame_ms / last.frame_batches.max(1) as f64 * self.radius_growth(last);
                self.batches_fitted = true;
                (STILL_FRAME_BUDGET_MS / per_batch).floor().clamp(1.0, self.batch_limit as f64) as u32
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
        let Some(measured) = last.splat.as_ref().map(|s| s.radius as f64).filter(|r| *r > 0.0) else {
            return 1.0; // the reference: its batches cost the same
        };
        let scene = self.renderer.scene();
        let single = self.renderer.settings().splat.radius.unwrap_or_else(|| leakless::splatting::auto_radius(scene));
        let largest = leakless::splatting::progressive_radius(single, 1) as f64;
        (largest / measured).powi(2).max(1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::interval_is_typical;

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
