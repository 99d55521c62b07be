//! What the image holds of the frames since the last change: the accumulation's state, which
//! the next frame's plan (`plan.rs`) reads and the frame updates.

/// The accumulation of frames while nothing changes.
#[derive(Clone, Copy, Debug)]
pub(super) struct Accumulation {
    /// Photon frames accumulate while nothing changes, with no end (the app), besides the
    /// `settings.frames` a render asks for.
    pub progressive: bool,
    /// Frames only show the last image again (tonemap and overlay): the app's pause.
    pub paused: bool,
    /// Samples (reference) or photon frames accumulated since the last change.
    pub accumulated: u32,
    /// Photon batches in those frames.
    pub batches: u32,
    /// Reference samples each frame adds.
    pub samples_per_frame: u32,
    /// The image is an accumulation's mean (the last frame that rendered was progressive): a
    /// frame that renders nothing (paused, full) shows the mean layers again, not that frame's.
    pub image_is_mean: bool,
    /// The image's indirect light is temporal reuse's (the last frame that rendered ran it).
    pub image_is_reused: bool,
}

impl Default for Accumulation {
    fn default() -> Self {
        Accumulation {
            progressive: false,
            paused: false,
            accumulated: 0,
            batches: 0,
            samples_per_frame: 1,
            image_is_mean: false,
            image_is_reused: false,
        }
    }
}

impl Accumulation {
    /// Something changed: the image starts over.
    pub fn restart(&mut self) {
        (self.accumulated, self.batches) = (0, 0);
        (self.image_is_mean, self.image_is_reused) = (false, false);
    }
}
