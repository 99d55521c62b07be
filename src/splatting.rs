//! Photon splatting on the view-sample hierarchy (Moreau et al. 2016), as DESIGN.md §1 has
//! it: trace photons, rebuild the hierarchy from the G-buffer, splat the photons onto node
//! lists, gather per view sample. One frame's photon part, with its buffers kept between
//! frames and its counts read back for `--stats`.

use leakless_device::{Buffer, BufferDesc, Gpu, MemoryLocation};
use leakless_graph::{Access, BufferHandle, Graph};
use leakless_scene::Scene;
use serde::Serialize;

use crate::error::{RenderError, Result};
use crate::gpu_scene::SceneHandles;
use crate::passes::gather::{self, GatherInputs, GatherOutputs, GatherPass};
use crate::passes::gbuffer::GBufferHandles;
use crate::passes::hierarchy::Hierarchy;
use crate::passes::photons::{
    photon_buffer_size, PhotonCounters, PhotonParams, PhotonPass, COUNTER_BUFFER_USAGE, PHOTON_BUFFER_USAGE,
};
use crate::passes::splat::{NodeLists, SplatInputs, SplatPass};
use crate::photon_lights::PhotonLights;
use crate::trace::{Backend, TraceHandles};

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
    pub list_entries: u32,
    pub list_entries_dropped: u32,
    pub list_capacity: u32,
    pub nodes_visited: u32,
    /// Photons the gather examined.
    pub candidate_tests: u64,
    /// Of those, within the radius and facing the sample (gathered).
    pub accepted: u64,
    /// Visibility segments traced (the gathered photons, when the method traces).
    pub visibility_rays: u64,
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

pub struct PhotonSplatting {
    settings: SplatSettings,
    radius: f32,
    max_bounces: u32,
    seed: u32,
    lights: PhotonLights,
    photons: Buffer,
    photon_counters: Buffer,
    photon_pass: PhotonPass,
    pub hierarchy: Hierarchy,
    lists: NodeLists,
    splat: SplatPass,
    gather: GatherPass,
    fixed_scale: f32,
}

/// The photon part of one frame's graph.
pub struct SplatHandles {
    pub photons: BufferHandle,
    pub photon_counters: BufferHandle,
}

impl PhotonSplatting {
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        gpu: &Gpu,
        scene: &Scene,
        backend: Backend,
        width: u32,
        height: u32,
        settings: &SplatSettings,
        max_bounces: u32,
        seed: u32,
    ) -> Result<PhotonSplatting> {
        if settings.paths == 0 {
            return Err(RenderError::Settings("--paths must be at least 1".into()));
        }
        let bounds = scene.bounds();
        let radius = settings.radius.unwrap_or(0.05 * bounds.bounding_radius());
        if !(radius.is_finite() && radius > 0.0) {
            return Err(RenderError::Settings(format!("--radius {radius} must be a positive number")));
        }
        // Every path stores at most max_bounces photons: this capacity cannot overflow.
        let photon_capacity = settings.paths.checked_mul(max_bounces.max(1)).ok_or_else(|| {
            RenderError::Settings(format!("{} paths × {max_bounces} bounces overflow the photon count", settings.paths))
        })?;
        let lights = PhotonLights::upload(gpu, scene)?;
        let buffer = |name, size, usage, location| Buffer::new(gpu, &BufferDesc { name, size, usage, location });
        let photons =
            buffer("photons", photon_buffer_size(photon_capacity), PHOTON_BUFFER_USAGE, MemoryLocation::GpuOnly)?;
        let photon_counters = buffer("photon counters", 8, COUNTER_BUFFER_USAGE, MemoryLocation::GpuToCpu)?;
        let hierarchy = Hierarchy::new(gpu, width, height, settings.branching)?;
        let list_capacity =
            settings.list_capacity.unwrap_or_else(|| default_list_capacity(photon_capacity, width * height));
        let lists = NodeLists::new(gpu, hierarchy.shape.node_count(), list_capacity)?;
        let max_flux = lights.table.entries.iter().flat_map(|e| e.flux).fold(0.0f32, f32::max) / settings.paths as f32;
        Ok(PhotonSplatting {
            settings: settings.clone(),
            radius,
            max_bounces,
            seed,
            photon_pass: PhotonPass::new(gpu, backend, photon_capacity)?,
            fixed_scale: gather::fixed_scale(photon_capacity, max_flux, radius),
            lights,
            photons,
            photon_counters,
            hierarchy,
            lists,
            splat: SplatPass::new(gpu)?,
            gather: GatherPass::new(gpu, backend)?,
        })
    }

    pub fn radius(&self) -> f32 {
        self.radius
    }

    /// After a frame that dropped list entries, grows the lists to hold all of them (up to
    /// [`MAX_LIST_CAPACITY`]) unless the user fixed the capacity; true if it grew, so the
    /// caller can render the frame again.
    pub fn grow_lists_after_drops(&mut self, gpu: &Gpu) -> Result<bool> {
        let counters = self.lists.read_counters()?;
        if counters.entries_dropped == 0
            || self.settings.list_capacity.is_some()
            || self.lists.capacity >= MAX_LIST_CAPACITY
        {
            return Ok(false);
        }
        // `entries_used` counts every attempted append: exactly what the frame needed.
        let needed = (counters.entries_used as u64 * 5 / 4).min(MAX_LIST_CAPACITY as u64) as u32;
        self.lists = NodeLists::new(gpu, self.hierarchy.shape.node_count(), needed)?;
        Ok(true)
    }

    /// Adds the frame's photon passes: photons, hierarchy, splat and gather into the
    /// indirect sum (radiance, scale 1) and the leaked layer.
    #[allow(clippy::too_many_arguments)]
    pub fn add<'r>(
        &'r self,
        graph: &mut Graph<'r>,
        frame: &BufferHandle,
        scene: &SceneHandles,
        trace: &TraceHandles,
        gbuffer: &GBufferHandles,
        out: GatherOutputs<'_>,
    ) -> Result<()> {
        let mut photons = graph.import_buffer(&self.photons);
        let mut photon_counters = graph.import_buffer(&self.photon_counters);
        let lights = self.lights.import(graph);
        let params = PhotonParams {
            paths: self.settings.paths,
            max_bounces: self.max_bounces,
            seed: self.seed,
            store_direct: false,
        };
        self.photon_pass.add(graph, &params, scene, trace, &lights, &mut photons, &mut photon_counters)?;

        let mut h = self.hierarchy.import(graph);
        self.hierarchy.add(graph, frame, gbuffer, &mut h)?;

        let mut lists = self.lists.import(graph);
        let input = SplatInputs {
            photons: &photons,
            photon_counters: &photon_counters,
            photon_capacity: self.photon_pass.capacity(),
            radius: self.radius,
            trivial_accept: self.settings.trivial_accept,
        };
        self.splat.add(graph, &self.hierarchy.shape, input, &h, &mut lists, self.lists.capacity)?;
        let input = GatherInputs {
            photons: &photons,
            radius: self.radius,
            fixed_scale: self.fixed_scale,
            visibility: self.settings.visibility,
            cap: self.settings.cap,
        };
        let counters = self.gather.add(graph, &self.hierarchy.shape, input, gbuffer, scene, trace, &h, &lists, out)?;

        // The counters are read on the host once the frame completed.
        let mut host = graph.pass("splat counters to host");
        host.read(&photon_counters, Access::HostRead);
        host.read(&lists.counters, Access::HostRead);
        host.read(&counters, Access::HostRead);
        host.record(|_| Ok(()));
        Ok(())
    }

    /// The photon buffer and how many photons the last frame stored in it.
    pub fn photons(&self) -> Result<(&Buffer, u32)> {
        Ok((&self.photons, self.photon_counters.read_vec::<PhotonCounters>(1)?[0].stored))
    }

    /// The counts of the last frame.
    pub fn read_stats(&self) -> Result<SplatStats> {
        let photons = self.photon_counters.read_vec::<PhotonCounters>(1)?[0];
        let lists = self.lists.read_counters()?;
        let gather = self.gather.read_counters()?;
        let valid_samples = gather.valid_samples as u64;
        Ok(SplatStats {
            paths: self.settings.paths,
            radius: self.radius,
            branching: self.settings.branching,
            trivial_accept: self.settings.trivial_accept,
            photons_stored: photons.stored,
            photons_dropped: photons.overflowed,
            list_entries: lists.entries_used.min(self.lists.capacity),
            list_entries_dropped: lists.entries_dropped,
            list_capacity: self.lists.capacity,
            nodes_visited: lists.nodes_visited,
            candidate_tests: gather.candidates(),
            accepted: gather.accepted(),
            visibility_rays: if self.settings.visibility { gather.accepted() } else { 0 },
            leaks_culled: gather.occluded(),
            capped_samples: gather.capped_samples,
            leaked_energy_fraction: 0.0,
            brute_force_tests: valid_samples * photons.stored as u64,
        })
    }
}

/// Most node-list entries a frame may use: 2^27 entries, 1 GiB. Beyond it entries are
/// dropped and reported, so memory stays bounded whatever the radius and photon count.
pub const MAX_LIST_CAPACITY: u32 = 1 << 27;

/// Node-list entries to start with: a photon lands on the leaves within its radius (fewer
/// nodes with trivial accept); 16 per photon, at least one per pixel. A frame that needs more
/// grows the lists and is rendered again (`grow_lists_after_drops`).
fn default_list_capacity(photons: u32, pixels: u32) -> u32 {
    (photons as u64 * 16).max(pixels as u64).min(MAX_LIST_CAPACITY as u64) as u32
}
