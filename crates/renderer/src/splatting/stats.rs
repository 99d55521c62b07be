//! What one frame of splatting counted, from the counters its passes leave.

use serde::Serialize;

use super::SplatFrame;
use crate::passes::gather::GatherCounters;
use crate::passes::photons::PhotonCounters;
use crate::passes::splat::SplatCounters;

/// What one frame of splatting counted (after it completed).
#[derive(Clone, Debug, Default, Serialize)]
pub struct SplatStats {
    pub paths: u32,
    pub radius: f32,
    pub branching: u32,
    pub trivial_accept: bool,
    pub photons_stored: u32,
    pub photons_dropped: u32,
    /// Closest-hit rays the photon pass traced.
    pub photon_rays: u32,
    pub list_entries: u32,
    pub list_entries_dropped: u32,
    pub list_capacity: u32,
    pub nodes_visited: u32,
    /// Photons some node list took: the only ones the gather can reach, and the only ones
    /// whose clearance is searched for (the others are out of view or face no sample).
    pub photons_listed: u32,
    /// Photons the gather examined.
    pub candidate_tests: u64,
    /// The most photons one view sample examined: where a GPU's gather waits for its longest
    /// samples, this against the mean (`candidate_tests` over `valid_samples`) says so.
    pub candidates_most: u32,
    /// Of those, within the radius and facing the sample (gathered).
    pub accepted: u64,
    /// View samples the gather estimated (those on a surface).
    pub valid_samples: u32,
    /// Photons a kernel took on average: `accepted` over `valid_samples` (the K that the
    /// count-following radius aims at).
    pub photons_per_kernel: f64,
    /// Visibility tests (the gathered photons, when the method traces): rays traced plus those
    /// proven clear without a ray.
    pub visibility_tests: u64,
    /// Visibility rays traced.
    pub visibility_rays: u64,
    /// Visibility tests proven clear by the photons' clearance, without a ray.
    pub proven_clear: u64,
    /// Gathered photons whose segment hit geometry: leaks removed.
    pub leaks_culled: u64,
    /// The compute traversal's work for those rays, where the tuning counts it (`render
    /// --count-work`): the nodes its walks processed and the triangles they tested, as `bench
    /// rays` counts them (a test against the triangle that blocked the invocation's last blocked
    /// segment is not a walk's and is left out). `None` where nothing counted.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ray_nodes_visited: Option<u64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ray_triangles_tested: Option<u64>,
    /// Samples that reached the per-pixel cap.
    pub capped_samples: u32,
    /// Leaked / (leaked + kept) indirect energy over the image (luminance), filled in by the
    /// renderer from the layers.
    pub leaked_energy_fraction: f64,
    /// Valid view samples × photons: what a splat without hierarchy would test.
    pub brute_force_tests: u64,
}

impl SplatStats {
    /// The stats of a completed frame from its counters.
    pub fn new(
        frame: &SplatFrame,
        photons: &PhotonCounters,
        lists: &SplatCounters,
        gather: &GatherCounters,
    ) -> SplatStats {
        let valid_samples = gather.valid_samples as u64;
        let counted = frame.tuning.count_work && frame.compute_trace;
        SplatStats {
            paths: frame.settings.paths,
            radius: frame.radius,
            branching: frame.branching(),
            trivial_accept: frame.settings.trivial_accept,
            photons_stored: photons.stored,
            photons_dropped: photons.overflowed,
            photon_rays: photons.rays,
            list_entries: lists.entries_used.min(frame.list_capacity),
            list_entries_dropped: lists.entries_dropped,
            list_capacity: frame.list_capacity,
            nodes_visited: lists.nodes_visited,
            photons_listed: lists.photons_listed,
            candidate_tests: gather.candidates(),
            candidates_most: gather.candidates_most,
            accepted: gather.accepted(),
            valid_samples: gather.valid_samples,
            photons_per_kernel: gather.accepted() as f64 / gather.valid_samples.max(1) as f64,
            visibility_tests: if frame.settings.visibility { gather.accepted() } else { 0 },
            visibility_rays: if frame.settings.visibility { gather.accepted() - gather.proven() } else { 0 },
            proven_clear: gather.proven(),
            leaks_culled: gather.occluded(),
            ray_nodes_visited: counted.then(|| gather.ray_nodes()),
            ray_triangles_tested: counted.then(|| gather.ray_triangles()),
            capped_samples: gather.capped_samples,
            leaked_energy_fraction: 0.0,
            brute_force_tests: valid_samples * photons.stored as u64,
        }
    }
}
