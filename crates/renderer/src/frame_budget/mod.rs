//! The frame-time budget: how many light paths a moving frame traces so that it takes T ms
//! (`--frame-ms`). A pure function of the frame times measured before, so that it is tested
//! without a device; the renderer feeds it ([`crate::Renderer::set_frame_budget`]).
//!
//! A frame's time is modelled as a fixed part (the G-buffer, direct light, reuse, display:
//! what the pixels cost) and a part that follows the paths (tracing, ordering, splatting and
//! gathering photons: the passes of [`PHOTON_GROUPS`]; where the radius follows the photon
//! count, a sample's gather takes about K photons whatever the paths, and the gather joins the
//! fixed part), t = f + c·p. Each measured frame gives
//! one estimate of f and of c, from its passes' times where it has them and otherwise from the
//! split of the last frame that had them (its f and c, as shares of this frame's time at this
//! frame's paths); the mean of the last estimates (up to 16, less the highest and the lowest)
//! sets the next frame's paths, p = (T − f) / c. A lasting change (two frames in a row a
//! third or more off that mean, on the same side; one frame 1.3× over the target; three in a
//! row 1.15× over it, a cost that climbs) drops the older estimates, so that the budget follows
//! it within a few frames while a lone outlier under 1.3× the target moves it little. The
//! paths move on a ladder of steps 2^(1/8) apart and stay on their step while the estimate is
//! within ¾ of a step of it, so that noise does not make them wander, and the buffers sized by
//! the paths change only when the step does. The ladder passes through the starting paths (`--paths`): a budget that a frame of
//! them meets keeps them, where on a ladder from a fixed base the nearest step can be 4.5%
//! away, and its band's edge a step further. A change of render size carries the estimate to the new size
//! ([`FrameBudget::resize`]); the size it advises steps down after 3 frames and up after 12.

use std::collections::VecDeque;

use crate::passes::names::group;

mod dynamic;
pub use dynamic::{DynamicResolution, MIN_DYNAMIC_SCALE};

/// The pass groups whose time follows the number of light paths at a fixed radius. Where the
/// radius follows the photon count, the gather's work is about K photons a sample at any
/// paths, and it is not among them ([`photon_share`]).
pub const PHOTON_GROUPS: [&str; 5] =
    [group::PHOTONS, group::PHOTON_ORDER, group::SPLAT, group::CLEARANCE, group::GATHER];

/// The fewest paths a budgeted frame traces: below this a frame's indirect light is mostly
/// noise, and the fixed part of the frame dominates its time anyway.
pub const MIN_BUDGET_PATHS: u32 = 1024;

/// Frames whose estimates are averaged.
const WINDOW: usize = 16;

/// Frames in a row that mark a lasting change when each is off the average by more than
/// `SHIFT_FACTOR` on the same side.
const SHIFT_FRAMES: usize = 2;
const SHIFT_FACTOR: f64 = 1.3;

/// One frame this far over the target also marks a change: beyond a steady view's ±20% noise
/// on paths a ladder's step above the target's, so that only a change of cost (or a stall of
/// the machine) reaches it, and with a frame in flight the change shows a frame late already.
const OVER_FACTOR: f64 = 1.3;

/// `DRIFT_FRAMES` frames in a row each over the target by more than `DRIFT_FACTOR` mark a
/// change too: a cost that climbs a few percent a frame (a view turning towards costlier
/// pixels) never stands `SHIFT_FACTOR` off the average of the frames before it, and the
/// average lagged it by half its window, frames 1.2× the target for as long as the climb
/// lasted. A steady view's ±20% noise puts three frames in a row past 1.15× once in 500.
const DRIFT_FRAMES: usize = 3;
const DRIFT_FACTOR: f64 = 1.15;

/// Frames measured at a render size before the budget advises a smaller one, and before it
/// advises a larger one (the caller feeds only frames of the current size). Down at once, up
/// slowly, as engines do: a frame over its target is seen, one under it is not, and a size
/// that grows back on a few cheap frames (the view turned towards a wall) is over again when
/// the view turns back.
const RESOLUTION_DOWN_FRAMES: usize = 3;
const RESOLUTION_UP_FRAMES: usize = 12;

/// The most steps of `RESOLUTION_STEP` the budget advises down at once (0.84^8 ≈ ¼ along
/// each axis): a frame several times over its target gets there in one change.
const MAX_RESOLUTION_STEPS: f64 = 8.0;

/// Steps of the ladder per doubling of the paths (2^(1/8) ≈ 9% apart).
const STEPS_PER_DOUBLING: f64 = 8.0;

/// The most the paths change in one frame (a factor): with the median's delay, a larger jump
/// on a mis-measured frame would overshoot.
const MAX_STEP_FACTOR: f64 = 2.0;

/// The share of a frame taken to follow the paths before any frame has measured its passes.
const START_PHOTON_SHARE: f64 = 0.8;

/// Each step of dynamic resolution scales the render size along each axis by this (about 30%
/// fewer or more pixels a step).
pub const RESOLUTION_STEP: f64 = 0.84;

/// One measured frame: its time, and the share of it that followed the paths when its passes
/// were timed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameTime {
    pub ms: f64,
    pub paths: u32,
    pub photon_share: Option<f64>,
}

#[derive(Clone, Debug)]
pub struct FrameBudget {
    target_ms: f64,
    min_paths: u32,
    max_paths: u32,
    /// The ladder's step 0: the starting paths.
    ladder_base: f64,
    /// The paths of the next budgeted frame.
    paths: u32,
    /// The last timed frame's split of its time: (fixed ms, ms per path). A share measured at
    /// one count of paths is not the share at another.
    split: Option<(f64, f64)>,
    /// The split was measured at another render size (`resize`).
    split_stale: bool,
    /// A frame timed for the split is in flight (`timed_frame_submitted`): the frames
    /// submitted before it completes need not be timed too.
    timed_in_flight: bool,
    /// (fixed ms, ms per path) of the last frames.
    estimates: VecDeque<(f64, f64)>,
    /// The fewest paths miss the target by the estimate: the fixed part alone exceeds it.
    over: bool,
    /// The estimates of the fixed part and of a path's cost (ms) after the last frame.
    fixed_ms: f64,
    per_path_ms: f64,
    /// Frames measured since the last change of size (`resize`), and in all.
    measured: usize,
    frames: usize,
    /// Frames in a row over the target by more than `DRIFT_FACTOR`, and the last frame's time.
    drift_streak: usize,
    last_ms: f64,
}

impl FrameBudget {
    /// A budget of `target_ms` a frame, starting at `start_paths`, choosing within
    /// [`min_paths`, `max_paths`].
    pub fn new(target_ms: f64, start_paths: u32, min_paths: u32, max_paths: u32) -> FrameBudget {
        let max_paths = max_paths.max(1);
        let min_paths = min_paths.clamp(1, max_paths);
        let ladder_base = start_paths.clamp(min_paths, max_paths) as f64;
        FrameBudget {
            target_ms,
            min_paths,
            max_paths,
            ladder_base,
            paths: on_ladder(ladder_base, ladder_base, min_paths, max_paths),
            split: None,
            split_stale: false,
            timed_in_flight: false,
            estimates: VecDeque::with_capacity(WINDOW),
            over: false,
            fixed_ms: 0.0,
            per_path_ms: 0.0,
            measured: 0,
            frames: 0,
            drift_streak: 0,
            last_ms: 0.0,
        }
    }

    pub fn target_ms(&self) -> f64 {
        self.target_ms
    }

    /// Moves the target, keeping the estimates: the next measured frame chooses its paths for
    /// it (`bench motion --budgeted` holds a budget to the mean of a fixed run it renders
    /// beside, frame by frame).
    pub fn set_target_ms(&mut self, target_ms: f64) {
        if target_ms.is_finite() && target_ms > 0.0 {
            self.target_ms = target_ms;
        }
    }

    /// The paths the next budgeted frame traces.
    pub fn paths(&self) -> u32 {
        self.paths
    }

    /// Whether even the fewest paths miss the target: the frame's fixed part alone takes it.
    pub fn over_budget(&self) -> bool {
        self.over
    }

    /// What a frame of the fewest paths takes by the estimates (the mean of the last frames,
    /// not any one of them): what `over_budget` compares with the target.
    pub fn fewest_paths_ms(&self) -> f64 {
        self.fixed_ms + self.per_path_ms * self.min_paths as f64
    }

    /// Whether the next frame should have its passes timed, where a caller times them only now
    /// and then (the app on lavapipe): no timed frame was measured yet, or none since the last
    /// change of size. Before the first, a frame's time is split by `START_PHOTON_SHARE`, a
    /// guess (the atrium's first frames on lavapipe spend 15–30% of their time on the photons:
    /// the guess put the fixed part at a quarter of what it was until the app timed a frame, 22
    /// frames later); after a change of size, by the split carried from the old size.
    /// One such frame is asked for at a time: with frames in flight, those submitted while it
    /// runs would be timed for nothing.
    pub fn wants_timed_frame(&self) -> bool {
        (self.split.is_none() || self.split_stale) && !self.timed_in_flight
    }

    /// Whether a timed frame has given the split of a frame's time (at any size).
    pub fn knows_split(&self) -> bool {
        self.split.is_some()
    }

    /// The caller submitted a frame timed pass by pass for the split.
    pub fn timed_frame_submitted(&mut self) {
        self.timed_in_flight = true;
    }

    /// That frame completed, whether or not its passes gave a split: the next frame may be
    /// timed again if it did not.
    pub fn timed_frame_completed(&mut self) {
        self.timed_in_flight = false;
    }

    /// The estimate of the fixed part of a frame (ms): what the frame would take without paths.
    pub fn fixed_ms(&self) -> f64 {
        self.fixed_ms
    }

    /// Takes a budgeted frame's measured time; returns the paths of the next.
    pub fn observe(&mut self, frame: FrameTime) -> u32 {
        if !(frame.ms.is_finite() && frame.ms > 0.0 && frame.paths > 0) {
            return self.paths;
        }
        self.measured += 1;
        self.frames += 1;
        let p = frame.paths as f64;
        let drifting = frame.ms > DRIFT_FACTOR * self.target_ms;
        self.drift_streak = if drifting { self.drift_streak + 1 } else { 0 };
        self.last_ms = frame.ms;
        let share = match (self.take_split(frame), self.split) {
            (Some(share), _) => share,
            (None, Some((fixed, per_path))) => per_path * p / (fixed + per_path * p),
            (None, None) => START_PHOTON_SHARE,
        };
        let per_path = frame.ms * share / p;
        let fixed = frame.ms * (1.0 - share);
        if self.estimates.len() == WINDOW {
            self.estimates.pop_front();
        }
        self.estimates.push_back((fixed, per_path));
        self.forget_before_a_shift();
        // The first frame moves the paths as far as it asks: nothing was known before it, and
        // the frames that keep the starting paths while the step limit walks them down are
        // what a view's first second is made of.
        self.choose_paths(self.frames > 1);
        self.paths
    }

    /// Takes only the split of a frame whose time is not what the budgeted frames take: one
    /// submitted pass by pass among frames submitted at once (the frame timed for the split,
    /// the app's profiled frame), each pass its own submission and wait. On lavapipe such a
    /// frame of the Cornell box at 256×144 took 170–172 ms where the frames beside it took
    /// 149–150; as an estimate it cut 10 000 paths to 7040 for the frames after it.
    pub fn observe_split(&mut self, frame: FrameTime) {
        if frame.ms.is_finite() && frame.ms > 0.0 && frame.paths > 0 {
            self.take_split(frame);
        }
    }

    /// The frame's photon share, where its passes were timed, and the split it gives.
    fn take_split(&mut self, frame: FrameTime) -> Option<f64> {
        let share = frame.photon_share.filter(|s| s.is_finite())?.clamp(0.001, 1.0);
        self.split = Some((frame.ms * (1.0 - share), frame.ms * share / frame.paths as f64));
        self.split_stale = false;
        Some(share)
    }

    /// The next frame's paths from the estimates: at most `MAX_STEP_FACTOR` from the last
    /// frame's where `limit_step` (a measured frame; a change of size moves them as far as its
    /// carried estimate asks).
    fn choose_paths(&mut self, limit_step: bool) {
        let fixed = trimmed_mean(self.estimates.iter().map(|e| e.0));
        let per_path = trimmed_mean(self.estimates.iter().map(|e| e.1));
        (self.fixed_ms, self.per_path_ms) = (fixed, per_path);
        let room = self.target_ms - fixed;
        self.over = room < per_path * self.min_paths as f64;
        let mut wanted = room.max(0.0) / per_path;
        if limit_step {
            wanted = wanted.clamp(self.paths as f64 / MAX_STEP_FACTOR, self.paths as f64 * MAX_STEP_FACTOR);
        }
        // Stay on the current step while the estimate is within ¾ of a step either side of it.
        let steps = (wanted / self.paths as f64).log2() * STEPS_PER_DOUBLING;
        if steps.abs() > 0.75 {
            self.paths = on_ladder(wanted, self.ladder_base, self.min_paths, self.max_paths);
        }
    }
}

impl FrameBudget {
    /// The render size changed, by `pixels` (the new size's pixels over the old's), and with it
    /// the fixed part and the cost of a path's gather: the frames before measured another
    /// size. Their estimate, carried to the new size, becomes the only one, and the next
    /// frame's paths follow from it: the fixed part taken to follow the pixels, a path's cost
    /// to grow with them but not to shrink, so that the carried estimate errs towards fewer
    /// paths, which the frames after correct. Keeping the paths instead, a step up took the
    /// next frames to 1.5–1.8× the target on the atrium's flight. The last timed split's share
    /// of the frame stays (it follows the pixels in both parts): without it the next frames
    /// would be split by the starting guess.
    pub fn resize(&mut self, pixels: f64) {
        let carried = (!self.estimates.is_empty() && pixels.is_finite() && pixels > 0.0)
            .then(|| (self.fixed_ms * pixels, self.per_path_ms * pixels.max(1.0)));
        self.estimates.clear();
        self.over = false;
        self.measured = 0;
        self.split_stale = self.split.is_some();
        // A frame of the old size in flight says nothing of the new one.
        self.timed_in_flight = false;
        if let Some(estimate) = carried {
            self.estimates.push_back(estimate);
            self.choose_paths(false);
        }
    }

    /// The factor (along each axis) by which the estimates advise scaling the render size,
    /// dynamic resolution's (1: keep it), once `RESOLUTION_DOWN_FRAMES` frames (a step down; the
    /// budget's first frame alone may step down) or `RESOLUTION_UP_FRAMES` (a step up) have
    /// been measured since the last change of size.
    /// Where the fewest paths miss the target: down by as many `RESOLUTION_STEP`s as bring the
    /// fixed part, taken to follow the pixels, within 90% of the room they leave (at most
    /// `MAX_RESOLUTION_STEPS` at once). Where the frame, its fixed part grown by a step's
    /// pixels, would take at most 80% of the target at twice the fewest paths, and the last
    /// frame held the target within 10% (a frame over it is no time to add pixels): up one
    /// step. At a steady cost the two cannot alternate: a step down leaves a fixed part that a
    /// step up would grow back past the target.
    pub fn resolution_factor(&self) -> f64 {
        // The budget's first frame may step down at once (as its paths move at once).
        if self.measured < RESOLUTION_DOWN_FRAMES && self.frames != 1 {
            return 1.0;
        }
        let least = self.per_path_ms * self.min_paths as f64;
        let pixels_step = RESOLUTION_STEP * RESOLUTION_STEP;
        if self.over {
            let room = 0.9 * self.target_ms - least;
            let steps =
                if room > 0.0 { ((room / self.fixed_ms).ln() / pixels_step.ln()).ceil() } else { MAX_RESOLUTION_STEPS };
            RESOLUTION_STEP.powf(steps.clamp(1.0, MAX_RESOLUTION_STEPS))
        } else if self.measured >= RESOLUTION_UP_FRAMES
            && self.last_ms <= 1.1 * self.target_ms
            && self.fixed_ms / pixels_step + 2.0 * least < 0.8 * self.target_ms
        {
            1.0 / RESOLUTION_STEP
        } else {
            1.0
        }
    }

    /// Keeps only the last `SHIFT_FRAMES` estimates when each of them is off the earlier ones'
    /// average by more than `SHIFT_FACTOR`, all on the same side, or the last frame is over
    /// `OVER_FACTOR`; the last `DRIFT_FRAMES` when each of them was over `DRIFT_FACTOR`: the
    /// frame's cost changed.
    fn forget_before_a_shift(&mut self) {
        let n = self.estimates.len();
        if n < 2 * SHIFT_FRAMES {
            return;
        }
        if self.last_ms > OVER_FACTOR * self.target_ms {
            self.estimates.drain(..n - SHIFT_FRAMES);
            return;
        }
        // `n` holds more than `DRIFT_FRAMES` here (2 · `SHIFT_FRAMES` at least).
        if self.drift_streak >= DRIFT_FRAMES {
            self.estimates.drain(..n - DRIFT_FRAMES);
            return;
        }
        // Frames kept for being over the target are a high estimate of its cost: the frames
        // after them would stand below them by noise alone, so the average they are compared
        // with holds at least two more than those (five: a trimmed mean, which leaves out the
        // highest). At the start and after a change of size the test waits as long.
        if n < DRIFT_FRAMES + 2 * SHIFT_FRAMES {
            return;
        }
        let before = trimmed_mean(self.estimates.iter().take(n - SHIFT_FRAMES).map(|e| e.1));
        let recent: Vec<f64> = self.estimates.iter().skip(n - SHIFT_FRAMES).map(|e| e.1).collect();
        let above = recent.iter().all(|c| *c > before * SHIFT_FACTOR);
        let below = recent.iter().all(|c| *c * SHIFT_FACTOR < before);
        if above || below {
            self.estimates.drain(..n - SHIFT_FRAMES);
        }
    }
}

/// The ladder's step nearest `paths`: `base`·2^(k/8), rounded to 64 paths but for `base`
/// itself, within the bounds.
fn on_ladder(paths: f64, base: f64, min_paths: u32, max_paths: u32) -> u32 {
    let base = base.max(1.0);
    let k = ((paths.max(1.0) / base).log2() * STEPS_PER_DOUBLING).round();
    let stepped = if k == 0.0 {
        base.round()
    } else {
        ((base * (k / STEPS_PER_DOUBLING).exp2() / 64.0).round() * 64.0).max(64.0)
    };
    (stepped.min(u32::MAX as f64) as u32).clamp(min_paths, max_paths)
}

/// The mean without the highest and the lowest value (from five values on).
fn trimmed_mean(values: impl Iterator<Item = f64>) -> f64 {
    let mut v: Vec<f64> = values.collect();
    v.sort_by(f64::total_cmp);
    let kept = if v.len() >= 5 { &v[1..v.len() - 1] } else { &v[..] };
    kept.iter().sum::<f64>() / kept.len().max(1) as f64
}

/// The share of a frame's time spent in the passes that follow the paths ([`PHOTON_GROUPS`],
/// less the gather where `radius_follows_count`), from per-pass times (host times where the
/// passes were submitted alone, else GPU timestamps); `None` without them.
pub fn photon_share(timings: &[leakless_graph::PassTiming], radius_follows_count: bool) -> Option<f64> {
    let time = |t: &leakless_graph::PassTiming| t.wall_ms.unwrap_or(t.ms);
    let total: f64 = timings.iter().map(time).sum();
    if total.is_nan() || total <= 0.0 {
        return None;
    }
    let follows = |g: &str| PHOTON_GROUPS.contains(&g) && !(radius_follows_count && g == group::GATHER);
    let photons: f64 = timings.iter().filter(|t| follows(t.group)).map(time).sum();
    Some(photons / total)
}

#[cfg(test)]
mod tests;
