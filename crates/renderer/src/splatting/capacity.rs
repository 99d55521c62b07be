//! How many node-list entries a frame may use: the start, the growth after a frame that
//! dropped entries, and the batches a frame then holds.

use crate::passes::splat::SplatCounters;

/// Most node-list entries a frame may use: 2^27 entries, 1 GiB. Beyond it entries are
/// dropped and reported, so memory stays bounded whatever the radius and photon count.
pub const MAX_LIST_CAPACITY: u32 = 1 << 27;

/// Node-list entries to start with: a photon lands on the leaves within its radius (fewer
/// nodes with trivial accept); 16 per photon, at least one per pixel. A frame that needs more
/// grows the lists for the next frame ([`grown_batch_capacity`]).
pub fn default_list_capacity(photons: u32, pixels: u32) -> u32 {
    (photons as u64 * 16).max(pixels as u64).min(MAX_LIST_CAPACITY as u64) as u32
}

/// After a frame of `batches` batches that dropped list entries, the entries one batch needs
/// (what the frame tried to append, with a margin, shared by its batches), up to
/// `max_entries`; `None` when it dropped nothing or a batch may already use `max_entries`.
/// The renderer's capacity is per batch, so frames then hold only the batches the lists can
/// take ([`batches_the_lists_hold`]).
pub fn grown_batch_capacity(current: u32, batches: u32, counters: &SplatCounters, max_entries: u32) -> Option<u32> {
    if counters.entries_dropped == 0 || current >= max_entries {
        return None;
    }
    // `entries_used` counts every attempted append: exactly what the frame needed.
    let per_batch = (counters.entries_used as u64 * 5 / 4).div_ceil(batches.max(1) as u64);
    Some(per_batch.min(max_entries as u64) as u32)
}

/// Batches of `batch_capacity` list entries each that one frame's lists, at most `max_entries`,
/// hold (at least one): a frame of more would drop photons, since the lists cannot grow past
/// the device's largest buffer, so an accumulation's frames hold fewer batches instead.
pub fn batches_the_lists_hold(batch_capacity: u32, max_entries: u32) -> u32 {
    (max_entries / batch_capacity.max(1)).max(1)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dropped(used: u32, dropped: u32) -> SplatCounters {
        SplatCounters { entries_used: used, entries_dropped: dropped, ..Default::default() }
    }

    /// A frame of 8 batches that wanted 17.3M entries of lavapipe's 2^24 (the 640×480 Cornell
    /// box's fourth frame, before frames were held to what the lists take): each batch needs
    /// 2.7M with the margin, so frames hold 6 batches.
    #[test]
    fn lists_that_cannot_grow_further_hold_fewer_batches() {
        let max = 1 << 24;
        assert_eq!(grown_batch_capacity(1_000, 8, &dropped(17_300_000, 0), max), None, "nothing dropped");
        let grown = grown_batch_capacity(2_000_000, 8, &dropped(17_325_720, 548_504), max).expect("grows");
        assert_eq!(grown, 2_707_144);
        assert_eq!(batches_the_lists_hold(grown, max), 6);
        // One batch needing more than the device holds: capped, reported, and not grown again.
        let capped = grown_batch_capacity(1_000, 1, &dropped(40_000_000, 23_222_784), max).expect("grows");
        assert_eq!((capped, batches_the_lists_hold(capped, max)), (max, 1));
        assert_eq!(grown_batch_capacity(max, 1, &dropped(40_000_000, 23_222_784), max), None);
        assert_eq!(batches_the_lists_hold(0, max), max, "no division by zero");
    }
}
