//! Photon splatting on the view-sample hierarchy (Moreau et al. 2016; docs/architecture.md):
//! trace photons, rebuild the hierarchy from the G-buffer, splat the photons onto node lists,
//! gather per view sample. One frame's photon part; its buffers live in the graph's pool,
//! and its counters are copied out with the frame for the stats.

use leakless_device::{BufferDesc, MemoryLocation};
use leakless_graph::{BufferHandle, Graph};
use leakless_scene::Aabb;
use serde::Serialize;

use crate::error::{RenderError, Result};
use crate::gpu_scene::SceneHandles;
use crate::passes::gather::{self, GatherCounters, GatherInputs, GatherOutputs, GatherPass};
use crate::passes::gbuffer::GBufferHandles;
use crate::passes::hierarchy::{HierarchyHandles, HierarchyPasses, Shape};
use crate::passes::photon_clearance::{self, ClearancePass, Needed};
use crate::passes::photon_dispatch::PhotonDispatchPass;
use crate::passes::photon_order::{PhotonOrderPass, ORDERED_PHOTONS};
use crate::passes::photons::{
    photon_buffer_size, PhotonCounters, PhotonParams, PhotonPass, COUNTER_BUFFER_USAGE, PHOTON_BUFFER_USAGE,
};
use crate::passes::splat::{NodeListHandles, SplatCounters, SplatInputs, SplatPass};
use crate::passes::visible_disk::{self, VisibleDiskParams, VisibleDiskPass};
use crate::photon_lights::LightHandles;
use crate::trace::TraceHandles;

/// The photon method's parameters (`--paths`, `--radius`, …).
#[derive(Clone, Debug, PartialEq)]
pub struct SplatSettings {
    /// Light paths traced per frame.
    pub paths: u32,
    /// Gather radius in scene units; `None` = 5% of the scene's bounding-sphere radius.
    pub radius: Option<f32>,
    /// Branching factor B of the hierarchy.
    pub branching: u32,
    /// List a photon on an enveloped, facing node instead of descending (Moreau et al.).
    pub trivial_accept: bool,
    /// Node-list entries per frame; more are counted as dropped, never written.
    pub list_capacity: Option<u32>,
    /// Trace a visibility segment from each sample to each photon (leakage removal); set by
    /// the method.
    pub visibility: bool,
    /// Gather at most this many photons per pixel (`leakless-capped`; `--cap`).
    pub cap: Option<u32>,
    /// Skip the visibility rays the photons' clearance proves clear (same image; off with
    /// `--trace-every-pair`, to measure what the proofs save and check they change nothing).
    pub prove_clear: bool,
    /// Divide each sample's sum by the kernel's mass over the part of its disk that can be
    /// seen, counting only photons on its own surface (`leakless`; off with `--whole-disk`,
    /// the estimator before the corner fix). Needs `visibility`.
    pub visible_disk: bool,
    /// Gather within r·clamp(m^γ, ½, 1.5) where the visible disk holds a share m < 1 of the
    /// kernel's mass: γ = −1 (grow) in a single frame, then ramping from 1/64 to 1 (shrink) as
    /// batches accumulate ([`partial_radius_exponent`]; visible_disk.comp says why; off with
    /// `--no-partial-disk-radius`). Needs `visible_disk`.
    pub partial_disk_radius: bool,
    /// Find whether the sample's face lies under a visible-disk probe by walking to a coplanar
    /// neighbour of its triangle before tracing a ray down (`Scene::coplanar_neighbours`;
    /// same image, fewer rays; off only to check that).
    pub walk_faces: bool,
    /// Cull each hierarchy node with its own samples' largest gather radius, not the frame's
    /// largest, where a single frame grows partial disks (same image, fewer list entries; off
    /// only to check that).
    pub node_radius: bool,
    /// Copy the photons in the order of a grid's cells before the splat, so that neighbouring
    /// threads walk the same nodes (photon_order.rs; same image, faster; off only to check
    /// that).
    pub order_photons: bool,
}

impl Default for SplatSettings {
    fn default() -> Self {
        SplatSettings {
            paths: 10_000,
            radius: None,
            branching: 8,
            trivial_accept: true,
            list_capacity: None,
            visibility: false,
            cap: None,
            prove_clear: true,
            visible_disk: true,
            partial_disk_radius: true,
            walk_faces: true,
            node_radius: true,
            order_photons: true,
        }
    }
}

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
    /// Of those, within the radius and facing the sample (gathered).
    pub accepted: u64,
    /// Visibility tests (the gathered photons, when the method traces): rays traced plus those
    /// proven clear without a ray.
    pub visibility_tests: u64,
    /// Visibility rays traced.
    pub visibility_rays: u64,
    /// Visibility tests proven clear by the photons' clearance, without a ray.
    pub proven_clear: u64,
    /// Gathered photons whose segment hit geometry: leaks removed.
    pub leaks_culled: u64,
    /// Samples that reached the per-pixel cap.
    pub capped_samples: u32,
    /// Leaked / (leaked + kept) indirect energy over the image (luminance), filled in by the
    /// renderer from the layers.
    pub leaked_energy_fraction: f64,
    /// Valid view samples × photons: what a splat without hierarchy would test.
    pub brute_force_tests: u64,
}

/// The pipelines of the photon part of a frame.
pub struct SplattingPasses<'a> {
    pub photons: &'a PhotonPass,
    pub clearance: &'a ClearancePass,
    pub hierarchy: &'a HierarchyPasses,
    pub dispatch: &'a PhotonDispatchPass,
    pub order: &'a PhotonOrderPass,
    pub splat: &'a SplatPass,
    pub visible_disk: &'a VisibleDiskPass,
    pub gather: &'a GatherPass,
}

/// What one frame's photon part does: the method's settings resolved for this frame.
#[derive(Clone, Debug)]
pub struct SplatFrame {
    pub settings: SplatSettings,
    /// The gather radius in scene units.
    pub radius: f32,
    pub max_bounces: u32,
    /// This frame's seed of the photon sequences.
    pub seed: u32,
    /// Index of this frame's first path in the sequence (frames that accumulate continue it).
    pub path_offset: u32,
    /// Index of this frame's first photon batch in its accumulation (0: a single frame, or
    /// an accumulation's first).
    pub first_batch: u32,
    /// The camera's position (visibility segments leave from samples moved toward it).
    pub eye: [f32; 3],
    /// Node-list entries this frame may use.
    pub list_capacity: u32,
    /// Photon batches in `settings.paths` (the frames of an accumulation grow).
    pub batches: u32,
    /// The scene's bounds, over which the photons are ordered.
    pub bounds: Aabb,
}

/// The gather radius when `--radius` is not given: 5% of the scene's bounding radius.
pub fn auto_radius(scene: &crate::Scene) -> f32 {
    0.05 * scene.bounds().bounding_radius()
}

/// The exponent α of the radius reduction of progressive photon mapping (Knaus and Zwicker,
/// "Progressive Photon Mapping: A Probabilistic Approach", 2011): r²ᵢ₊₁ = r²ᵢ (i + α)/(i + 1).
/// Any α in (0, 1) makes the average of the frames converge; 2/3 is their choice, balancing
/// the variance that a shrinking radius adds against the bias it removes.
pub const PPM_ALPHA: f64 = 2.0 / 3.0;

/// How much larger than the single frame's radius the shrinking sequence of an accumulation
/// starts. Batch 0 is the single frame the app shows while the view moves, at the radius chosen
/// for one frame; the batches after it are averaged, so their noise matters less than their
/// bias, and a larger start trades the one for the other. Measured at equal wall time (README,
/// "Converging while the view is still"): 2 lowers relMSE at 1 s and 10 s in the atrium, the
/// doorway and the Cornell box, and HDR-FLIP in the first two and the Cornell box at 10 s (at
/// 1 s it stays within a run's spread); 4, measured on the atrium with the single frame at 4×
/// too, lets the bias take over. With the partial-disk radius, 1.5 and 3 were measured again on
/// the atrium: both are worse in HDR-FLIP at 10 s (1.27×, 1.24× the path tracer's, against
/// 1.22×).
pub const ACCUMULATION_RADIUS_SCALE: f64 = 2.0;

/// The gather radius of photon batch `index` (0-based) of an accumulation whose single frame
/// has `radius` r: batch 0 has r exactly (the single frame), and batch i ≥ 1 follows the global
/// radius sequence of Knaus and Zwicker from s·r (s = `ACCUMULATION_RADIUS_SCALE`),
/// r²ᵢ = (s·r)² Πⱼ₌₁..ᵢ (j + α)/(j + 1), one radius per batch of `paths` paths for every pixel
/// (no batch has s·r itself: batch 1 is already shrunk once).
/// It needs no per-pixel state (unlike SPPM's per-pixel radius, which needs each pixel's photon
/// count), so each batch stays an independent estimate and the image is their plain average.
/// A frame of several batches gives all of them its first batch's radius: indexing by batches,
/// not frames, makes the radius follow the photons traced so far however frames group them (as
/// SPPM's follows each pixel's photon count).
pub fn progressive_radius(radius: f32, index: u32) -> f32 {
    if index == 0 {
        return radius; // exactly: a single frame is the frame without accumulation
    }
    let mut r2 = ACCUMULATION_RADIUS_SCALE * ACCUMULATION_RADIUS_SCALE;
    for i in 1..=index {
        r2 *= (i as f64 + PPM_ALPHA) / (i as f64 + 1.0);
    }
    (radius as f64 * r2.sqrt()) as f32
}

/// The least share of the frame's radius a partial disk shrinks to (visible_disk.comp): a
/// corner's quarter disk keeps half the radius. The gather's fixed point allows for the
/// kernel's peak there ([`gather::fixed_scale`]).
pub const MIN_RADIUS_SHARE: f32 = 0.5;

/// The largest share of the frame's radius a partial disk grows to in a single frame
/// (visible_disk.comp). Measured on the atrium's single frames at twice the default radius,
/// where bias dominates: −1.0% in the mean with 1.5, −4.5% with 2 (−0.4% with 1.5 since the
/// visible disk's probes stop at the tangent plane; the corner-bias target is 5%).
pub const MAX_RADIUS_SHARE: f32 = 1.5;

/// The exponent γ of a single frame's partial disks: r·min(m^γ, g) with γ = −1 grows a disk
/// of share m until it holds about a whole disk's photons (a half disk to 1.5r rather than
/// √2·r: a partial disk's share falls as it grows). Single frames at 10k paths, 96×72, seeds
/// 1–16, relMSE of the indirect layer against the whole disk's: Cornell box 1.11× with γ = 0,
/// 0.99× with −1; doorway 1.05× and 0.97×. γ = −0.5 left the Cornell box 2% worse.
pub const SINGLE_FRAME_RADIUS_EXPONENT: f32 = -1.0;

/// Batches over which the partial-disk shrink of an accumulation ramps in.
pub const PARTIAL_RADIUS_RAMP_BATCHES: f32 = 64.0;

/// The exponent γ of the partial-disk radius (r·clamp(m^γ, ½, g), visible_disk.comp) for a
/// frame whose first batch is `first_batch`: `SINGLE_FRAME_RADIUS_EXPONENT` (grow) for batch 0,
/// the single frame, whose error is its noise; then from 1/64 at batch 1 (whose radius is
/// already near twice the single frame's) linearly to 1 (shrink) at
/// `PARTIAL_RADIUS_RAMP_BATCHES`. A partial disk's bias is of first order in r, its noise grows
/// as the disk shrinks, and only the noise falls as batches add up, so the best shrink deepens
/// with the photons traced. Measured with the whole shrink from batch 1: the Cornell box's 16
/// one-batch frames got 12% worse in relMSE (0.01449 → 0.01621) while 239 atrium batches got
/// 19% better at the edges.
pub fn partial_radius_exponent(first_batch: u32) -> f32 {
    if first_batch == 0 {
        return SINGLE_FRAME_RADIUS_EXPONENT;
    }
    (first_batch as f32 / PARTIAL_RADIUS_RAMP_BATCHES).min(1.0)
}

/// The largest radius any sample of a frame at `radius` gathers within: grown partial disks
/// reach `MAX_RADIUS_SHARE`·r in a single frame (`first_batch` 0) when `partial` is on.
pub fn largest_gather_radius(radius: f32, first_batch: u32, partial: bool) -> f32 {
    if partial && partial_radius_exponent(first_batch) < 0.0 {
        MAX_RADIUS_SHARE * radius
    } else {
        radius
    }
}

/// Photon batches frame `index` (0-based) of an accumulation traces: 1, 2, 4, … up to
/// `max_batches`. Frame 0 is one batch, exactly the frame without accumulation; doubling
/// keeps the first second's frames short while the per-frame work soon weighs little.
pub fn frame_batches(index: u32, max_batches: u32) -> u32 {
    1u32.checked_shl(index).unwrap_or(u32::MAX).min(max_batches.max(1))
}

impl SplatFrame {
    /// Photons the buffer holds: every path stores at most `max_bounces`, so it cannot
    /// overflow.
    pub fn photon_capacity(&self) -> Result<u32> {
        self.settings.paths.checked_mul(self.max_bounces.max(1)).ok_or_else(|| {
            RenderError::Settings(format!(
                "{} paths × {} bounces overflow the photon count",
                self.settings.paths, self.max_bounces
            ))
        })
    }
}

/// The counters a frame's photon part leaves (besides the gather's, which the caller passes
/// in with the gather's outputs), to copy out for the stats.
pub struct SplatCounterHandles {
    pub photons: BufferHandle,
    pub lists: BufferHandle,
}

/// What the photon part reads from the rest of the frame.
pub struct SplatInputsOfFrame<'a> {
    pub frame: &'a BufferHandle,
    pub scene: &'a SceneHandles,
    pub trace: &'a TraceHandles,
    pub lights: &'a LightHandles,
    pub gbuffer: &'a GBufferHandles,
}

/// Adds the frame's photon passes: photons, hierarchy, splat, and the gather into `out`.
pub fn add<'r>(
    graph: &mut Graph<'r>,
    passes: SplattingPasses<'r>,
    frame: &SplatFrame,
    input: SplatInputsOfFrame<'_>,
    out: GatherOutputs<'_>,
) -> Result<SplatCounterHandles> {
    let capacity = frame.photon_capacity()?;
    let photon_buffer = |name, size, usage| BufferDesc { name, size, usage, location: MemoryLocation::GpuOnly };
    let mut photons = graph.buffer(&photon_buffer("photons", photon_buffer_size(capacity), PHOTON_BUFFER_USAGE))?;
    let counter_size = std::mem::size_of::<PhotonCounters>() as u64;
    let mut photon_counters = graph.buffer(&photon_buffer("photon counters", counter_size, COUNTER_BUFFER_USAGE))?;
    let params = PhotonParams {
        paths: frame.settings.paths,
        max_bounces: frame.max_bounces,
        seed: frame.seed,
        store_direct: false,
        path_offset: frame.path_offset,
        // leakless-capped keeps the first photons of each list: in either order they would
        // come from one part of the light or of the disk, not from all over it.
        emission_order: frame.settings.cap.is_none(),
    };
    passes.photons.add(
        graph,
        &params,
        input.scene,
        input.trace,
        input.lights,
        &mut photons,
        capacity,
        &mut photon_counters,
    )?;

    let dispatch = passes.dispatch.add(graph, &photon_counters, capacity)?;
    // Not for leakless-capped either: its cap keeps a list's first photons, which in cell order
    // would come from one side of the disk.
    if frame.settings.order_photons && frame.settings.cap.is_none() {
        let desc = photon_buffer(ORDERED_PHOTONS, photon_buffer_size(capacity), PHOTON_BUFFER_USAGE);
        let mut ordered = graph.buffer(&desc)?;
        passes.order.add(graph, &photons, &photon_counters, &dispatch, &frame.bounds, &mut ordered)?;
        photons = ordered;
    }

    let extent = input.gbuffer.position.extent();
    let shape = Shape::new(extent.width * extent.height, frame.settings.branching)?;
    // Each sample's visible share of the kernel's disk (leakless), or 1, and its gather radius,
    // which the hierarchy's nodes bound.
    let visible_disk = frame.settings.visibility && frame.settings.visible_disk;
    let partial = visible_disk && frame.settings.partial_disk_radius;
    let mut disk_mass = visible_disk::image(graph, extent)?;
    let disk = VisibleDiskParams {
        radius: frame.radius,
        seed: frame.seed ^ frame.path_offset.wrapping_mul(0x9e37_79b9),
        enabled: visible_disk as u32,
        partial_radius_exponent: if partial { partial_radius_exponent(frame.first_batch) } else { 0.0 },
        min_radius_share: MIN_RADIUS_SHARE,
        max_radius_share: MAX_RADIUS_SHARE,
        walk_faces: frame.settings.walk_faces as u32,
        ..Default::default()
    };
    passes.visible_disk.add(graph, disk, input.frame, input.gbuffer, input.scene, input.trace, &mut disk_mass);
    let largest_radius = largest_gather_radius(frame.radius, frame.first_batch, partial);
    let mut h = HierarchyHandles::new(graph, &shape)?;
    passes.hierarchy.add(graph, input.frame, input.gbuffer, &disk_mass, &shape, &mut h)?;

    let mut lists = NodeListHandles::new(graph, shape.node_count(), frame.list_capacity, capacity)?;
    let splat = SplatInputs {
        photons: &photons,
        photon_counters: &photon_counters,
        dispatch: &dispatch,
        radius: largest_radius,
        node_radius: frame.settings.node_radius && largest_radius > frame.radius,
        trivial_accept: frame.settings.trivial_accept,
    };
    passes.splat.add(graph, &shape, splat, &h, &mut lists);

    // The photons' clearance, for the gather to prove segments clear (visibility only). The
    // search stops a little beyond the largest radius: a segment is no longer than that plus
    // both ends' tiny lifts, and one that is gets traced, so the bound only limits the work.
    let mut clearance = photon_clearance::buffer(graph, capacity)?;
    if frame.settings.visibility {
        let max_radius = 1.01 * largest_radius;
        let needed = Needed::Listed(&lists.listed);
        passes.clearance.add(
            graph,
            input.trace,
            &photons,
            &photon_counters,
            &dispatch,
            max_radius,
            needed,
            &mut clearance,
        )?;
    }
    let table = &input.lights.table;
    let max_flux = table.entries.iter().flat_map(|e| e.flux).fold(0.0f32, f32::max) / frame.settings.paths as f32;
    let gather_input = GatherInputs {
        photons: &photons,
        radius: frame.radius,
        fixed_scale: gather::fixed_scale(capacity, max_flux, disk.min_radius_share * frame.radius),
        visibility: frame.settings.visibility,
        cap: frame.settings.cap,
        clearance: &clearance,
        prove_clear: frame.settings.prove_clear,
        eye: frame.eye,
        visible_disk,
        disk_mass: &disk_mass,
    };
    passes.gather.add(graph, &shape, gather_input, input.gbuffer, input.scene, input.trace, &h, &lists, out);
    Ok(SplatCounterHandles { photons: photon_counters, lists: lists.counters })
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
        SplatStats {
            paths: frame.settings.paths,
            radius: frame.radius,
            branching: frame.settings.branching,
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
            accepted: gather.accepted(),
            visibility_tests: if frame.settings.visibility { gather.accepted() } else { 0 },
            visibility_rays: if frame.settings.visibility { gather.accepted() - gather.proven() } else { 0 },
            proven_clear: gather.proven(),
            leaks_culled: gather.occluded(),
            capped_samples: gather.capped_samples,
            leaked_energy_fraction: 0.0,
            brute_force_tests: valid_samples * photons.stored as u64,
        }
    }
}

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

    #[test]
    fn frames_double_their_batches_up_to_the_most() {
        let batches: Vec<u32> = (0..6).map(|k| frame_batches(k, 8)).collect();
        assert_eq!(batches, [1, 2, 4, 8, 8, 8]);
        assert_eq!(frame_batches(40, 8), 8, "a shift past the word's width");
        assert_eq!(frame_batches(u32::MAX, 64), 64);
        assert_eq!((frame_batches(0, 1), frame_batches(5, 1)), (1, 1));
        assert_eq!(frame_batches(3, 0), 1, "at least one batch");
    }

    /// The single frame keeps the frame's radius (its partial disks grow from it, per sample);
    /// the accumulation's sequence starts from twice it and
    /// shrinks by Knaus and Zwicker's ratio, so r² falls as i^(α − 1) (its bias vanishes).
    #[test]
    fn the_accumulation_radius_starts_from_twice_the_single_frames_and_shrinks() {
        assert_eq!(progressive_radius(0.3, 0), 0.3);
        let r = |i| progressive_radius(1.0, i) as f64;
        let first = ACCUMULATION_RADIUS_SCALE * ((1.0 + PPM_ALPHA) / 2.0).sqrt();
        assert!((r(1) - first).abs() < 1e-6, "batch 1: {}", r(1));
        for i in 1..50u32 {
            let ratio = (r(i + 1) / r(i)).powi(2);
            let expected = (i as f64 + 1.0 + PPM_ALPHA) / (i as f64 + 2.0);
            assert!((ratio - expected).abs() < 1e-5, "batch {i}: r² shrinks by {ratio}, not {expected}");
        }
        // r²ᵢ ~ C i^(α − 1): doubling i far out scales r² by 2^(α − 1).
        let slope = (r(20000) / r(10000)).powi(2).log2();
        assert!((slope - (PPM_ALPHA - 1.0)).abs() < 1e-3, "r² falls as i^{slope}");
    }

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
