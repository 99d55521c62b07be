//! History images: a named ping-pong pair of pool images, the one a frame writes and the one
//! the frame that last asked for it wrote (kajiya's temporal resources, made a graph feature).
//! The pair knows whether its previous image holds anything: not before the first frame that
//! wrote it, not once it was made anew (a resize), not after [`GraphRunner::invalidate_histories`]
//! (a change of scene, method or settings the renderer says invalidates what it remembers).
//!
//! A frame that asks for a history must write its `current` image: the pair flips every time
//! it is asked for. Frames that do not ask leave it alone, so a history survives frames that
//! skip the pass keeping it (a paused view).
//!
//! [`GraphRunner::invalidate_histories`]: crate::GraphRunner::invalidate_histories

use crate::ImageHandle;

/// This frame's image of a history pair, and the frame before's.
#[derive(Debug)]
pub struct History {
    /// Written by this frame; next time the pair is asked for, it is `previous`.
    pub current: ImageHandle,
    /// What the last frame that asked for the pair wrote into it (undefined unless `valid`).
    pub previous: ImageHandle,
    /// `previous` holds that frame's image.
    pub valid: bool,
}

/// Which of a pair's two images the last frame wrote, if its content still counts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct PairState {
    written: Option<usize>,
}

impl PairState {
    /// The pair asked for by a new frame: which image (0 or 1) it writes, and whether the other
    /// is valid history. `remade`: either image was made anew for this frame.
    pub(crate) fn advance(&mut self, remade: bool) -> (usize, bool) {
        let current = self.written.map_or(0, |w| 1 - w);
        let valid = self.written.is_some() && !remade;
        self.written = Some(current);
        (current, valid)
    }

    /// Forgets the pair's content: the next frame gets no valid history.
    pub(crate) fn invalidate(&mut self) {
        self.written = None;
    }
}

/// The pool key of image `index` of the pair `name`.
pub(crate) fn pair_name(name: &str, index: usize) -> String {
    format!("{name} [{index}]")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pair_alternates_and_is_valid_from_its_second_frame() {
        let mut pair = PairState::default();
        assert_eq!(pair.advance(true), (0, false), "nothing written yet");
        assert_eq!(pair.advance(false), (1, true));
        assert_eq!(pair.advance(false), (0, true));
        assert_eq!(pair.advance(false), (1, true));
    }

    #[test]
    fn a_remade_image_or_an_invalidation_loses_the_history_once() {
        let mut pair = PairState::default();
        pair.advance(true);
        pair.advance(false);
        // A resize: both images are made anew, the previous one holds nothing.
        assert_eq!(pair.advance(true), (0, false));
        assert_eq!(pair.advance(false), (1, true));
        pair.invalidate();
        assert!(!pair.advance(false).1, "invalidated");
        assert!(pair.advance(false).1, "written again since");
    }
}
