//! Photon splatting on the view-sample hierarchy (Moreau et al. 2016; docs/architecture.md):
//! trace photons, rebuild the hierarchy from the G-buffer, splat the photons onto node lists,
//! gather per view sample. One frame's photon part; its buffers live in the graph's pool,
//! and its counters are copied out with the frame for the stats.
//!
//! Its parts: the method's settings (`settings.rs`), the radius schedule (`radius.rs`), the
//! radius that follows the photon count (`kernel_radius.rs`), the node lists' capacity
//! (`capacity.rs`) and the stats (`stats.rs`); this file wires a frame's passes.

mod capacity;
mod kernel_radius;
mod radius;
mod settings;
mod stats;

pub use capacity::{batches_the_lists_hold, default_list_capacity, grown_batch_capacity, MAX_LIST_CAPACITY};
pub use kernel_radius::{KernelDensity, DEFAULT_KERNEL_PHOTONS, KERNEL_RADIUS_RANGE};
pub use radius::{
    auto_radius, frame_batches, largest_gather_radius, partial_radius_exponent, progressive_radius,
    ACCUMULATION_RADIUS_SCALE, MAX_RADIUS_SHARE, MIN_RADIUS_SHARE, PARTIAL_RADIUS_RAMP_BATCHES, PPM_ALPHA,
    SINGLE_FRAME_RADIUS_EXPONENT,
};
pub use settings::SplatSettings;
pub use stats::SplatStats;

use leakless_device::{BufferDesc, MemoryLocation};
use leakless_graph::{BufferHandle, Graph, PassName};
use leakless_scene::Aabb;

use crate::error::{RenderError, Result};
use crate::passes::disk_smooth::{self, DiskSmoothParams};
use crate::passes::gather::{self, GatherInputs, GatherOutputs};
use crate::passes::hierarchy::{self, HierarchyHandles, Shape};
use crate::passes::list_scatter;
use crate::passes::photon_clearance::{self, Needed};
use crate::passes::photon_dispatch;
use crate::passes::photon_dispatch::PHOTON_WORKGROUP;
use crate::passes::photon_order::{self, ORDERED_PHOTONS};
use crate::passes::photons::{
    self, photon_buffer_size, PhotonCounters, PhotonParams, COUNTER_BUFFER_USAGE, PHOTON_BUFFER_USAGE,
};
use crate::passes::sample_clearance;
use crate::passes::segment_entries;
use crate::passes::splat::{self, NodeListHandles, SplatInputs, SPLAT_DISPATCH};
use crate::passes::visible_disk::{self, VisibleDiskParams};
use crate::passes::ViewInputs;
use crate::photon_lights::LightHandles;
use crate::tuning::DeviceTuning;

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
    /// The device tuning's choices (paths per thread, the two orders, the default branching).
    pub tuning: DeviceTuning,
    /// Workgroups one dispatch may ask for (the device's maxComputeWorkGroupCount[0]): the
    /// list scatter loops over records beyond them.
    pub max_workgroups: u32,
    /// The trace backend is the compute BVH, whose traversal of visibility segments can start
    /// from each tile's entries (segment_entries.rs).
    pub compute_trace: bool,
}

impl SplatFrame {
    /// Whether the gather divides by the visible disk's mass (leakless): visibility on, and
    /// the visible disk not turned off.
    pub fn visible_disk(&self) -> bool {
        self.settings.visibility && self.settings.visible_disk
    }

    /// The pass this frame's gather runs, whose pipeline is made on demand.
    pub fn gather_pass(&self) -> PassName {
        gather::estimator(self.settings.visibility, self.visible_disk()).name
    }

    /// The hierarchy's branching factor: the settings', else the tuning's.
    pub fn branching(&self) -> u32 {
        self.settings.branching.unwrap_or(self.tuning.branching)
    }

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

/// Adds the frame's photon passes: photons (emitted from `lights`), hierarchy, splat, and the
/// gather of the view samples of `input` into `out`.
pub fn add<'r>(
    graph: &mut Graph<'r>,
    frame: &SplatFrame,
    input: &ViewInputs<'_>,
    lights: &LightHandles,
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
        emission_order: frame.settings.cap.is_none() && frame.tuning.emission_order,
        paths_per_thread: None,
    };
    photons::add(graph, &params, &frame.tuning, lights, &mut photons, capacity, &mut photon_counters)?;

    let dispatch = photon_dispatch::add(graph, &photon_counters, capacity)?;
    // Not for leakless-capped either: its cap keeps a list's first photons, which in cell order
    // would come from one side of the disk.
    if frame.settings.order_photons && frame.tuning.photon_order && frame.settings.cap.is_none() {
        let desc = photon_buffer(ORDERED_PHOTONS, photon_buffer_size(capacity), PHOTON_BUFFER_USAGE);
        let mut ordered = graph.buffer(&desc)?;
        photon_order::add(graph, &photons, &photon_counters, &dispatch, &frame.bounds, &mut ordered)?;
        photons = ordered;
    }

    let extent = input.gbuffer.position.extent();
    let shape = Shape::new(extent.width * extent.height, frame.branching())?;
    // Each sample's visible share of the kernel's disk (leakless), or 1, and its gather radius,
    // which the hierarchy's nodes bound.
    let visible_disk = frame.visible_disk();
    let partial = visible_disk && frame.settings.partial_disk_radius;
    let mut disk_mass = visible_disk::image(graph, extent)?;
    let disk_seed = frame.seed ^ frame.path_offset.wrapping_mul(0x9e37_79b9);
    let disk = VisibleDiskParams {
        radius: frame.radius,
        seed: disk_seed,
        tile_offset: visible_disk::tile_offset(disk_seed),
        rotation: visible_disk::rotation(disk_seed),
        share_distance: visible_disk::share_distance(frame.first_batch),
        enabled: visible_disk as u32,
        partial_radius_exponent: if partial { partial_radius_exponent(frame.first_batch) } else { 0.0 },
        min_radius_share: MIN_RADIUS_SHARE,
        max_radius_share: MAX_RADIUS_SHARE,
        walk_faces: frame.settings.walk_faces as u32,
        ..Default::default()
    };
    // A single frame's masses are smoothed over each surface (disk_smooth.rs); an
    // accumulation keeps every sample's own.
    if visible_disk && disk.share_distance > 0.0 {
        let mut measured = visible_disk::measured_image(graph, extent)?;
        visible_disk::add(graph, disk, input.frame, input.gbuffer, input.scene, &mut measured);
        let smooth =
            DiskSmoothParams { radius: frame.radius, share_distance: disk.share_distance, ..Default::default() };
        disk_smooth::add(graph, smooth, input.frame, input.gbuffer, &measured, &mut disk_mass);
    } else {
        visible_disk::add(graph, disk, input.frame, input.gbuffer, input.scene, &mut disk_mass);
    }
    let largest_radius = largest_gather_radius(frame.radius, frame.first_batch, partial);
    let mut h = HierarchyHandles::new(graph, &shape)?;
    hierarchy::add(graph, input.frame, input.gbuffer, &disk_mass, &shape, &mut h)?;

    let mut lists = NodeListHandles::new(graph, shape.node_count(), frame.list_capacity, capacity)?;
    // A splat that walks each photon with a cluster of lanes dispatches a cluster a photon.
    let clusters = match frame.tuning.splat_lanes {
        lanes if lanes > 1 => Some(photon_dispatch::add_over(
            graph,
            (SPLAT_DISPATCH, "splat dispatch"),
            &photon_counters,
            capacity,
            (PHOTON_WORKGROUP / lanes, frame.max_workgroups),
        )?),
        _ => None,
    };
    let splat = SplatInputs {
        photons: &photons,
        photon_counters: &photon_counters,
        dispatch: clusters.as_ref().unwrap_or(&dispatch),
        radius: largest_radius,
        node_radius: frame.settings.node_radius && largest_radius > frame.radius,
        trivial_accept: frame.settings.trivial_accept,
    };
    splat::add(graph, &shape, splat, &h, &mut lists);
    list_scatter::add(graph, &mut lists, frame.max_workgroups)?;

    // The photons' clearance, for the gather to prove segments clear (visibility only). The
    // search stops a little beyond the largest radius: a segment is no longer than that plus
    // both ends' tiny lifts, and one that is gets traced, so the bound only limits the work.
    let mut clearance = photon_clearance::buffer(graph, capacity)?;
    let mut sample_clearance = sample_clearance::SampleClearanceHandles::new(graph, extent)?;
    let mut segment_entries = segment_entries::SegmentEntriesHandles::new(graph, extent)?;
    // Only the compute backend's traversal starts from them; ray queries walk the driver's.
    let entries_written = frame.settings.visibility && frame.compute_trace;
    if frame.settings.visibility {
        let max_radius = 1.01 * largest_radius;
        let needed = Needed::Listed(&lists.listed);
        photon_clearance::add(graph, &photons, &photon_counters, &dispatch, max_radius, needed, &mut clearance)?;
        if frame.settings.prove_clear {
            sample_clearance::add(graph, frame.eye, max_radius, input.gbuffer, &mut sample_clearance);
        }
        if entries_written {
            segment_entries::add(graph, max_radius, input.gbuffer, &mut segment_entries);
        }
    }
    let table = &lights.table;
    let max_flux = table.entries.iter().flat_map(|e| e.flux).fold(0.0f32, f32::max) / frame.settings.paths as f32;
    let gather_input = GatherInputs {
        photons: &photons,
        radius: frame.radius,
        fixed_scale: gather::fixed_scale(capacity, max_flux, disk.min_radius_share * frame.radius),
        visibility: frame.settings.visibility,
        cap: frame.settings.cap,
        clearance: &clearance,
        sample_clearance: &sample_clearance,
        segment_entries: &segment_entries,
        entries_written,
        prove_clear: frame.settings.prove_clear,
        eye: frame.eye,
        visible_disk,
        disk_mass: &disk_mass,
    };
    gather::add(graph, &shape, gather_input, input.gbuffer, &h, &lists, out);
    Ok(SplatCounterHandles { photons: photon_counters, lists: lists.counters })
}
