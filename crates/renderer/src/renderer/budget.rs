//! The frame-time budget in the renderer (`--frame-ms`): the frames that start an
//! accumulation (every frame while anything moves) trace the paths [`FrameBudget`] chooses
//! from the times of the frames before; the batches of a still view's accumulation keep
//! `--paths`. Off unless the caller sets it (the app does; `render --sequence` with
//! `--frame-ms`), so a render's images are those of its settings.

use std::collections::HashSet;
use std::time::Instant;

use leakless_graph::{CompletedFrame, Timing};

use super::{Pending, Renderer};
use crate::error::{RenderError, Result};
use crate::frame_budget::{photon_share, FrameBudget, FrameTime, MIN_BUDGET_PATHS};

/// The longest budget `--frame-ms` takes: ten seconds a frame is no longer real time.
pub const MAX_FRAME_MS: f64 = 10_000.0;

/// What the budget did for one frame, in its report (and `--stats`, `sequence.json`).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct BudgetReport {
    /// The target, ms.
    pub target_ms: f64,
    /// The frame's time as the budget measured it: GPU timestamps where the device tuning
    /// trusts them, else host time (see [`Renderer::budget_measure`]).
    pub measured_ms: f64,
    /// The paths the frame traced, and those the next budgeted frame will.
    pub paths: u32,
    pub next_paths: u32,
    /// Even the fewest paths miss the target: the frame's fixed part alone takes it.
    pub over_budget: bool,
    /// What a frame of the fewest paths takes by the budget's estimate (the last frames' mean).
    pub fewest_paths_ms: f64,
    /// The share of the frame's passes that followed the paths, where they were timed
    /// ([`photon_share`]).
    pub photon_share: Option<f64>,
    /// The budget's estimate of a frame's fixed part after this frame (ms).
    pub fixed_ms: f64,
    /// The factor along each axis by which the budget advises scaling the render size (1:
    /// keep it; [`FrameBudget::resolution_factor`]).
    pub resolution_factor: f64,
    /// The frame ran a pass no budgeted frame before it ran (the first frame; the first moving
    /// frame after it, whose reuse passes run for the first time): it compiled pipelines and
    /// made images, and the budget did not take its time for what frames cost.
    pub warm_up: bool,
    /// The frame was submitted pass by pass among frames submitted at once (timed for the
    /// budget's split, or the app's profiled frame): its passes gave the split, and its time,
    /// each pass a submission and a wait, was not taken for what frames cost
    /// ([`FrameBudget::observe_split`]).
    pub split_only: bool,
}

/// Who picks the paths of an accumulation's first frame.
enum FirstPaths {
    /// The frame budget, from the frames before.
    Budget(FrameBudget),
    /// A fixed count (`render --first-frame-paths`: what a capture of the app records).
    Fixed(u32),
}

pub(super) struct BudgetState {
    choice: FirstPaths,
    /// The paths of the frame that started the current accumulation: its later batches'
    /// paths follow them, so no path index is traced twice.
    pub first_paths: u32,
    /// When the host last saw a frame complete.
    last_completion: Option<Instant>,
    /// The passes the budgeted frames ran so far. A frame that runs one for the first time is
    /// not measured: every caller sets the budget before its first frame, which compiles each
    /// pipeline at its first use (lavapipe compiles then; 0.9–1.5 s on the atrium), and the
    /// first moving frame after it runs the reuse passes for the first time (a doorway walk's
    /// took 420–830 ms against 200 ms after, at 256×144). As the budget's first estimate such a
    /// frame moved the paths as far as it asked (10 000 → 1024 paths, and the size down at
    /// once); a pass first run later (another method) meets a window of estimates, whose
    /// trimmed mean would leave a lone slow frame out, but costs nothing to skip.
    passes_run: HashSet<String>,
    /// A budgeted frame was submitted: the first is the warm-up, whose pass times are its
    /// compilations, and is not timed for the budget's split.
    submitted: bool,
    /// A budgeted frame submitted at once completed: a frame submitted pass by pass after it
    /// is not one of the frames the budget holds.
    seen_at_once: bool,
}

impl Renderer {
    /// Holds moving frames to `target_ms` each by the light paths they trace (`None`: every
    /// frame traces `--paths`). Starts from `--paths`.
    pub fn set_frame_budget(&mut self, target_ms: Option<f64>) -> Result<()> {
        self.budget = match target_ms {
            None => None,
            Some(t) if !(t.is_finite() && t > 0.0 && t <= MAX_FRAME_MS) => {
                return Err(RenderError::Settings(format!("--frame-ms {t} must be within (0, {MAX_FRAME_MS}]")));
            }
            Some(t) => {
                let most = crate::limits::max_frame_paths(&self.gpu.report().limits, self.settings.max_bounces);
                let most = most.min(u32::MAX as u64) as u32;
                let controller = FrameBudget::new(t, self.settings.splat.paths, MIN_BUDGET_PATHS, most);
                let choice = FirstPaths::Budget(controller);
                Some(BudgetState {
                    choice,
                    first_paths: self.settings.splat.paths,
                    last_completion: None,
                    passes_run: HashSet::new(),
                    submitted: false,
                    seen_at_once: false,
                })
            }
        };
        Ok(())
    }

    /// Every accumulation's first frame traces `paths` light paths, its later batches
    /// `--paths` each: the frames of an app whose budget chose `paths` (its captures record
    /// it). Replaces a budget.
    pub fn set_first_frame_paths(&mut self, paths: u32) -> Result<()> {
        let most = crate::limits::max_frame_paths(&self.gpu.report().limits, self.settings.max_bounces);
        if paths == 0 || paths as u64 > most {
            return Err(RenderError::Settings(format!(
                "--first-frame-paths {paths} must be within [1, {most}] on this device"
            )));
        }
        self.budget = Some(BudgetState {
            choice: FirstPaths::Fixed(paths),
            first_paths: paths,
            last_completion: None,
            passes_run: HashSet::new(),
            submitted: false,
            seen_at_once: false,
        });
        Ok(())
    }

    /// The render size changed by `pixels` (new over old): the budget's estimates were made at
    /// the old one ([`FrameBudget::resize`]).
    pub(super) fn resize_budget(&mut self, pixels: f64) {
        if let Some(BudgetState { choice: FirstPaths::Budget(b), .. }) = &mut self.budget {
            b.resize(pixels);
        }
    }

    /// The host waited for work that is not a frame (a probe): the next frame's time starts
    /// now, not at the last frame's completion.
    pub(super) fn restart_budget_clock(&mut self) {
        if let Some(budget) = &mut self.budget {
            budget.last_completion = None;
        }
    }

    /// Moves the budget's target to `target_ms` (within `set_frame_budget`'s bounds), keeping
    /// what it measured; nothing without a budget.
    pub fn set_frame_budget_target(&mut self, target_ms: f64) -> Result<()> {
        if !(target_ms.is_finite() && target_ms > 0.0 && target_ms <= MAX_FRAME_MS) {
            return Err(RenderError::Settings(format!("--frame-ms {target_ms} must be within (0, {MAX_FRAME_MS}]")));
        }
        if let Some(BudgetState { choice: FirstPaths::Budget(b), .. }) = &mut self.budget {
            b.set_target_ms(target_ms);
        }
        Ok(())
    }

    /// The budget, when one is set.
    pub fn frame_budget(&self) -> Option<&FrameBudget> {
        match &self.budget.as_ref()?.choice {
            FirstPaths::Budget(b) => Some(b),
            FirstPaths::Fixed(_) => None,
        }
    }

    /// Whether a budgeted frame about to be submitted in one submission is to be timed pass by
    /// pass instead: the budget wants a timed frame ([`FrameBudget::wants_timed_frame`]), and
    /// the device's timestamps do not bracket the work (the tuning times per pass), so a frame
    /// submitted at once (the app's frames but one in 30, `render --timing timestamps`) has
    /// no pass times to split it by.
    pub(super) fn budget_wants_timed_frame(&self) -> bool {
        self.runner.timing() == Timing::Timestamps
            && self.tuning().timing == Timing::PerPassSubmit
            && self.budget.as_ref().is_some_and(|b| b.submitted)
            && self.frame_budget().is_some_and(FrameBudget::wants_timed_frame)
    }

    /// A frame timed for the budget never reported: the next may be timed instead.
    pub(super) fn budget_timed_frame_lost(&mut self) {
        if let Some(BudgetState { choice: FirstPaths::Budget(b), .. }) = &mut self.budget {
            b.timed_frame_completed();
        }
    }

    /// A budgeted frame was submitted, `timed` pass by pass for the budget
    /// (`budget_wants_timed_frame`).
    pub(super) fn budget_frame_submitted(&mut self, timed: bool) {
        let Some(budget) = &mut self.budget else { return };
        budget.submitted = true;
        if let (true, FirstPaths::Budget(b)) = (timed, &mut budget.choice) {
            b.timed_frame_submitted();
        }
    }

    /// The paths of the current accumulation's first frame, where a budget (or
    /// `set_first_frame_paths`) chose them.
    pub fn first_frame_paths(&self) -> Option<u32> {
        self.budget.as_ref().map(|b| b.first_paths)
    }

    /// The paths of a frame whose first batch is `first_batch`, of `frame_batches`: the
    /// budget's for a frame that starts an accumulation, else `None` (`--paths` a batch).
    pub(super) fn budget_paths(&mut self, first_batch: u32, frame_batches: u32) -> Option<u32> {
        let budget = self.budget.as_mut()?;
        if first_batch == 0 && frame_batches == 1 {
            budget.first_paths = match &budget.choice {
                FirstPaths::Budget(b) => b.paths(),
                FirstPaths::Fixed(p) => *p,
            };
            Some(budget.first_paths)
        } else {
            None
        }
    }

    /// The first path index of batch `first_batch` (of `batch_paths` paths) of the current
    /// accumulation: after the first batch's paths, which the budget may have chosen.
    pub(super) fn path_offset(&self, first_batch: u32, batch_paths: u32) -> u32 {
        match (&self.budget, first_batch) {
            (_, 0) => 0,
            (Some(b), i) => b.first_paths.wrapping_add((i - 1).wrapping_mul(batch_paths)),
            (None, i) => i.wrapping_mul(batch_paths),
        }
    }

    /// A budgeted frame completed: its time goes to the budget, which picks the next frame's
    /// paths. `None` for a frame the budget did not choose.
    pub(super) fn observe_budget(&mut self, pending: &Pending, done: &CompletedFrame) -> Option<BudgetReport> {
        let now = Instant::now();
        let measured_ms = self.budget_measure(pending, done, now);
        let budget = self.budget.as_mut()?;
        budget.last_completion = Some(now);
        let paths = pending.budget_paths?;
        // A frame of another render size (in flight when it changed) says nothing of this one.
        if pending.size != (self.settings.width, self.settings.height) {
            return None;
        }
        let mut warming_up = budget.passes_run.is_empty();
        for t in &done.timings {
            warming_up |= budget.passes_run.insert(t.name.clone());
        }
        let per_pass = done.timings.iter().any(|t| t.wall_ms.is_some());
        let split_only = per_pass && budget.seen_at_once && !warming_up;
        budget.seen_at_once |= !per_pass;
        let FirstPaths::Budget(controller) = &mut budget.choice else { return None };
        if pending.budget_timed {
            controller.timed_frame_completed();
        }
        // Timestamps measure passes only where the tuning trusts them; host times always.
        let timed = self.pipelines.tuning().timing == Timing::Timestamps || per_pass;
        // Below `--paths` the radius stays (kernel_radius.rs), and the gather follows the paths.
        let follows_count = self.settings.splat.radius.is_none() && paths >= self.settings.splat.paths;
        let share = if timed { photon_share(&done.timings, follows_count) } else { None };
        let frame = FrameTime { ms: measured_ms, paths, photon_share: share };
        // Before the first split, a frame without one waits for it rather than be split by a
        // guess: the renderer times the next budgeted frame (`budget_wants_timed_frame`), or
        // every frame is timed.
        let unsplit = share.is_none() && !controller.knows_split();
        let next_paths = if warming_up || unsplit {
            controller.paths()
        } else if split_only {
            controller.observe_split(frame);
            controller.paths()
        } else {
            controller.observe(frame)
        };
        Some(BudgetReport {
            target_ms: controller.target_ms(),
            measured_ms,
            paths,
            next_paths,
            over_budget: controller.over_budget(),
            fewest_paths_ms: controller.fewest_paths_ms(),
            photon_share: share,
            fixed_ms: controller.fixed_ms(),
            resolution_factor: controller.resolution_factor(),
            warm_up: warming_up,
            split_only,
        })
    }

    /// A frame's time: its GPU span where the device tuning times passes by timestamps (a
    /// GPU); on a device whose timestamps do not bracket the work (lavapipe), host time: the
    /// shorter of its submission-to-completion time (which includes waiting for the frame
    /// before it, when two are in flight) and the time since the host last saw a frame
    /// complete (which includes the host's own gaps, when frames run one at a time).
    fn budget_measure(&self, pending: &Pending, done: &CompletedFrame, now: Instant) -> f64 {
        if self.tuning().timing == Timing::Timestamps {
            return done.span_ms;
        }
        let since_submit = (now - pending.started).as_secs_f64() * 1e3;
        let since_last = self.budget.as_ref().and_then(|b| b.last_completion).map(|t| (now - t).as_secs_f64() * 1e3);
        since_last.map_or(since_submit, |l| l.min(since_submit))
    }
}
