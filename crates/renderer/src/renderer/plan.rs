//! What the next frame renders, decided before anything is recorded: whether it renders at
//! all, whether it adds to an accumulation, which photon batches or reference samples it
//! traces, and what the image holds after it. A pure function of the renderer's state, so the
//! bookkeeping is unit-tested without a device; `frame.rs` only records what it says.

use crate::settings::Method;
use crate::splatting;

/// The renderer's state that the next frame's plan depends on.
#[derive(Clone, Copy, Debug)]
pub(super) struct PlanState {
    pub method: Method,
    /// Paused (the app): frames show the last image again.
    pub paused: bool,
    /// The accumulation holds all it may (`Renderer::accumulation_full`).
    pub full: bool,
    /// Frames add to an accumulation (`Renderer::accumulating`).
    pub accumulating: bool,
    /// Samples (reference) or photon frames accumulated since the last change.
    pub accumulated: u32,
    /// Photon batches in those frames.
    pub batches: u32,
    /// The most batches an accumulating frame grows to (`RenderSettings::max_batches`).
    pub max_batches: u32,
    /// Photon batches one frame may hold on this device (its photon buffer and node lists);
    /// `u32::MAX` when nothing limits them.
    pub batches_that_fit: u32,
    /// Reference samples per batch of an accumulation (`--spp`).
    pub spp: u32,
    /// Reference samples a frame adds outside an accumulation.
    pub samples_per_frame: u32,
}

/// What the next frame does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct FramePlan {
    /// Renders something new (else it shows the last image again: paused, or full).
    pub render: bool,
    /// The image holds nothing yet.
    pub first: bool,
    /// Adds to an accumulation of frames, each at its own radius, path offset and jitter.
    pub progressive: bool,
    /// Its index (0-based) in the accumulation; 0 is exactly the frame without one.
    pub index: u32,
    /// Its first photon batch (or reference batch).
    pub first_batch: u32,
    /// Batches it traces: of `paths` photon paths, or of `spp` reference samples per pixel.
    pub frame_batches: u32,
    /// Reference samples per pixel it traces (0 for other methods).
    pub samples: u32,
    /// Samples (reference) or frames (photons) in the image after it.
    pub accumulated: u32,
    /// Photon batches in the image after it (frames without photons count one).
    pub batches: u32,
}

/// The plan of the next frame from the renderer's state.
pub(super) fn plan(s: &PlanState) -> FramePlan {
    let render = !s.paused && !s.full;
    let first = s.accumulated == 0;
    let progressive = render && s.accumulating;
    let index = if progressive { s.accumulated } else { 0 };
    // Photon and reference frames grow alike, so the series compare methods that share their
    // per-frame work the same way.
    let first_batch = if progressive { s.batches } else { 0 };
    let frame_batches = if progressive && s.method.splats() {
        splatting::frame_batches(index, s.max_batches).min(s.batches_that_fit.max(1))
    } else if progressive && s.method == Method::Reference {
        splatting::frame_batches(index, s.max_batches)
    } else {
        1
    };
    // A reference frame of an accumulation is a whole image of `spp` samples per batch.
    let samples = match s.method {
        Method::Reference if progressive => s.spp.saturating_mul(frame_batches),
        Method::Reference => s.samples_per_frame,
        _ => 0,
    };
    let accumulated = match (render, s.method) {
        (false, _) => s.accumulated,
        (true, _) if progressive => s.accumulated + 1,
        (true, Method::Reference) => s.accumulated + samples,
        (true, _) => 1,
    };
    let batches = match (render, progressive) {
        (false, _) => s.batches,
        (true, true) => first_batch + frame_batches,
        (true, false) => 1,
    };
    FramePlan { render, first, progressive, index, first_batch, frame_batches, samples, accumulated, batches }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn still(method: Method) -> PlanState {
        PlanState {
            method,
            paused: false,
            full: false,
            accumulating: true,
            accumulated: 0,
            batches: 0,
            max_batches: 8,
            batches_that_fit: u32::MAX,
            spp: 4,
            samples_per_frame: 1,
        }
    }

    /// Runs `frames` plans, each continuing from the last, and returns them.
    fn run(mut state: PlanState, frames: usize) -> Vec<FramePlan> {
        (0..frames)
            .map(|_| {
                let p = plan(&state);
                (state.accumulated, state.batches) = (p.accumulated, p.batches);
                p
            })
            .collect()
    }

    #[test]
    fn an_accumulation_doubles_its_batches_and_continues_the_sequence() {
        let plans = run(still(Method::LeakLess), 6);
        let batches: Vec<u32> = plans.iter().map(|p| p.frame_batches).collect();
        assert_eq!(batches, [1, 2, 4, 8, 8, 8]);
        let first: Vec<u32> = plans.iter().map(|p| p.first_batch).collect();
        assert_eq!(first, [0, 1, 3, 7, 15, 23], "each frame starts where the last ended");
        assert!(plans.iter().enumerate().all(|(i, p)| p.index == i as u32 && p.accumulated == i as u32 + 1));
        assert!(plans[0].first && !plans[1].first);
        assert!(plans.iter().all(|p| p.render && p.progressive && p.samples == 0));
    }

    #[test]
    fn frames_hold_no_more_batches_than_fit() {
        let plans = run(PlanState { batches_that_fit: 3, ..still(Method::Splat) }, 4);
        assert_eq!(plans.iter().map(|p| p.frame_batches).collect::<Vec<_>>(), [1, 2, 3, 3]);
        let none_fit = plan(&PlanState { batches_that_fit: 0, ..still(Method::Splat) });
        assert_eq!(none_fit.frame_batches, 1, "at least one batch");
    }

    #[test]
    fn reference_frames_are_whole_images_of_spp_per_batch() {
        let plans = run(still(Method::Reference), 3);
        assert_eq!(plans.iter().map(|p| p.samples).collect::<Vec<_>>(), [4, 8, 16]);
        assert_eq!(plans.iter().map(|p| p.accumulated).collect::<Vec<_>>(), [1, 2, 3], "frames, not samples");
        // Outside an accumulation a reference adds samples to one image.
        let single = run(PlanState { accumulating: false, ..still(Method::Reference) }, 3);
        assert_eq!(single.iter().map(|p| p.accumulated).collect::<Vec<_>>(), [1, 2, 3]);
        assert!(single.iter().all(|p| p.samples == 1 && !p.progressive && p.frame_batches == 1));
    }

    #[test]
    fn a_paused_or_full_frame_renders_nothing_and_keeps_the_image() {
        let state = PlanState { accumulated: 5, batches: 15, ..still(Method::LeakLess) };
        for s in [PlanState { paused: true, ..state }, PlanState { full: true, ..state }] {
            let p = plan(&s);
            assert!(!p.render && !p.progressive);
            assert_eq!((p.accumulated, p.batches, p.index), (5, 15, 0));
        }
    }

    #[test]
    fn a_single_photon_frame_is_the_whole_image() {
        let plans = run(PlanState { accumulating: false, ..still(Method::LeakLess) }, 3);
        assert!(plans.iter().all(|p| p.render && !p.progressive && p.index == 0 && p.first_batch == 0));
        assert!(plans.iter().all(|p| p.frame_batches == 1 && p.accumulated == 1 && p.batches == 1));
    }
}
