//! Dynamic resolution: the share of the render size, along each axis, that the frame budget's
//! advice ([`FrameBudget::resolution_factor`](super::FrameBudget::resolution_factor)) leads
//! to. The app and `render --sequence` follow it alike.

/// The smallest share of the render size dynamic resolution goes down to, along each axis (a
/// sixteenth of the pixels).
pub const MIN_DYNAMIC_SCALE: f32 = 0.25;

/// The share of the render size a frame renders at, and whether it may go below 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DynamicResolution {
    pub scale: f32,
    pub enabled: bool,
}

impl DynamicResolution {
    /// The whole size; below it only when `enabled` (`--dynamic-resolution`).
    pub fn new(enabled: bool) -> Self {
        DynamicResolution { scale: 1.0, enabled }
    }

    /// Follows a measured frame's advice `factor`: the new share when it changes, within
    /// [`MIN_DYNAMIC_SCALE`] and 1 (and 1 when not `enabled`).
    pub fn follow(&mut self, factor: f32) -> Option<f32> {
        if factor == 1.0 || (factor < 1.0 && !self.enabled) {
            return None;
        }
        let wanted = (self.scale * factor).clamp(MIN_DYNAMIC_SCALE, 1.0);
        if wanted == self.scale {
            return None;
        }
        self.scale = wanted;
        Some(wanted)
    }

    /// A size of `full` pixels at this share (at least one pixel a side).
    pub fn size(&self, full: (u32, u32)) -> (u32, u32) {
        let scaled = |v: u32| ((v as f32 * self.scale).round() as u32).max(1);
        (scaled(full.0), scaled(full.1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Down by the advice, never below the floor, back up to the whole size and no further;
    /// without `enabled`, never down.
    #[test]
    fn the_share_follows_the_advice_within_its_bounds() {
        let mut d = DynamicResolution::new(true);
        assert_eq!(d.follow(1.0), None);
        assert_eq!(d.follow(0.5), Some(0.5));
        assert_eq!(d.size((320, 240)), (160, 120));
        assert_eq!(d.follow(0.1), Some(MIN_DYNAMIC_SCALE));
        assert_eq!(d.follow(0.5), None, "at the floor");
        assert_eq!(d.follow(8.0), Some(1.0));
        assert_eq!(d.follow(2.0), None, "at the whole size");
        let mut off = DynamicResolution::new(false);
        assert_eq!(off.follow(0.5), None);
        assert_eq!(off.size((320, 240)), (320, 240));
    }
}
