//! Gather: every view sample walks the photon lists of its leaf and ancestors and sums flux ×
//! kernel over the photons within the radius that face it (`gather.comp`) into the indirect
//! layer; with visibility on, photons hidden behind geometry go to the leaked layer instead.

use ash::vk;
use bytemuck::{Pod, Zeroable};
use leakless_device::shader::ShaderInfo;
use leakless_device::{gpu_struct, BufferDesc, GpuStruct, MemoryLocation, Specialization};
use leakless_graph::{shader_bindings, BufferHandle, Fill, Graph, ImageHandle, PassName};

use crate::device_address::address_words;
use crate::error::Result;
use crate::passes::gbuffer::{GBufferBindings, GBufferHandles};
use crate::passes::hierarchy::{HierarchyHandles, Level, Shape};
use crate::passes::names::group;
use crate::passes::photon_clearance::Clearance;
use crate::passes::photons::Photon;
use crate::passes::sample_clearance::{SampleClearanceHandles, BALL_TILE};
use crate::passes::segment_entries::SegmentEntriesHandles;
use crate::passes::splat::{NodeListHandles, PhotonPosition};
use crate::pipelines::{compute_pass, ComputePass, Threads};
use crate::shaders;
use crate::tuning::DeviceTuning;

gpu_struct! {
    /// The `GatherParams` push constants of gather.comp.
    #[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
    pub struct GatherParams {
        pub radius: f32,
        /// Fixed-point units per W/m² (see [`fixed_scale`]).
        pub fixed_scale: f32,
        pub level_count: u32,
        pub sample_count: u32,
        /// The camera's position: segments leave from the sample moved toward it.
        pub eye: [f32; 3],
        /// 1: skip the rays the photons' clearance proves clear.
        pub prove_clear: u32,
        pub image_width: u32,
        /// 0: no cap; else gather at most this many photons per sample.
        pub cap: u32,
        /// `list_photons`, `photon_positions`, `photons` and `clearance`, read through their
        /// device addresses (device_address.rs says why).
        pub list_photons_address: [u32; 2],
        pub positions_address: [u32; 2],
        pub photons_address: [u32; 2],
        pub clearance_address: [u32; 2],
        /// Pixels a side of the tiles of `sample_clearance` and `segment_entries`.
        pub sample_clearance_tile: u32,
        /// 1: `segment_entries` holds this frame's tiles' entries (the compute backend).
        pub segment_entries: u32,
    }
}

gpu_struct! {
    /// The `GatherCounters` block of gather.comp: 64-bit totals as (lo, hi) word pairs.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
    pub struct GatherCounters {
        pub candidates_lo: u32,
        pub candidates_hi: u32,
        pub accepted_lo: u32,
        pub accepted_hi: u32,
        pub occluded_lo: u32,
        pub occluded_hi: u32,
        pub proven_lo: u32,
        pub proven_hi: u32,
        pub valid_samples: u32,
        pub capped_samples: u32,
        pub ray_nodes_lo: u32,
        pub ray_nodes_hi: u32,
        pub ray_triangles_lo: u32,
        pub ray_triangles_hi: u32,
        pub candidates_most: u32,
        pub pad1: u32,
    }
}

fn wide(lo: u32, hi: u32) -> u64 {
    lo as u64 | (hi as u64) << 32
}

impl GatherCounters {
    /// Photons the gather examined.
    pub fn candidates(&self) -> u64 {
        wide(self.candidates_lo, self.candidates_hi)
    }
    /// Photons within the radius that faced their sample (the visibility rays, if traced).
    pub fn accepted(&self) -> u64 {
        wide(self.accepted_lo, self.accepted_hi)
    }
    /// Photons whose visibility segment hit geometry: leaks removed.
    pub fn occluded(&self) -> u64 {
        wide(self.occluded_lo, self.occluded_hi)
    }
    /// Visibility tests the photons' clearance answered without a ray.
    pub fn proven(&self) -> u64 {
        wide(self.proven_lo, self.proven_hi)
    }
    /// Nodes the visibility rays' walks processed (counted where the tuning's `count_work`
    /// is on, on the compute backend; 0 otherwise).
    pub fn ray_nodes(&self) -> u64 {
        wide(self.ray_nodes_lo, self.ray_nodes_hi)
    }
    /// Triangles those walks tested.
    pub fn ray_triangles(&self) -> u64 {
        wide(self.ray_triangles_lo, self.ray_triangles_hi)
    }
}

shader_bindings! {
    /// What gather.comp binds besides the scene (geometric normals) and the trace structures
    /// (visibility segments).
    pub struct GatherBindings {
        sorted_keys: read words,
        sorted_samples: read words,
        levels: read array(Level::LAYOUT),
        photons: read array(Photon::LAYOUT),
        node_ends: read words,
        list_photons: read words,
        gather_counters: read_write block(GatherCounters::LAYOUT),
        indirect_sum: write image,
        leaked: write image,
        gather_counts: write image,
        clearance: read array(Clearance::LAYOUT),
        disk_mass: read image,
        photon_positions: read array(PhotonPosition::LAYOUT),
        sample_clearance: read image,
        sample_clearance_plane: read image,
        segment_region_lo: read image,
        segment_region_hi: read image,
        segment_entries: read image,
    }
    pub struct GatherResources;
}

const GATHER_CLEAR: PassName = PassName::new("gather clear", group::GATHER);

/// The label the gather's time goes under, whichever estimator it runs.
pub const GATHER_LABEL: PassName = PassName::new("gather", group::GATHER);

// One pipeline per estimator: gather.comp's VISIBILITY and VISIBLE_DISK are specialization
// constants, so a method's gather holds no code of another's (the shader says why).
compute_pass! {
    /// The gather without visibility rays (`splat`).
    pub static GATHER in FRAME_PASSES: ComputePass<GatherBindings, GatherParams> =
        ComputePass::traced(GATHER_LABEL, SHADERS, &[GBufferBindings::DECLS])
            .specialize(DeviceTuning::gather)
            .on_demand();
    /// With a visibility segment to every photon over the whole disk (`leakless-capped`,
    /// `leakless --whole-disk`).
    pub static GATHER_TRACED in FRAME_PASSES: ComputePass<GatherBindings, GatherParams> =
        ComputePass::traced(PassName::new("gather traced", group::GATHER), SHADERS, &[GBufferBindings::DECLS])
            .specialize(traced)
            .on_demand();
    /// With visibility over the visible disk (`leakless`).
    pub static GATHER_VISIBLE_DISK in FRAME_PASSES: ComputePass<GatherBindings, GatherParams> =
        ComputePass::traced(PassName::new("gather visible disk", group::GATHER), SHADERS, &[GBufferBindings::DECLS])
            .specialize(visible_disk)
            .on_demand();
}

/// The estimator a gather with these inputs runs (its pipeline is made when a frame first
/// names it: `Pipelines::prepare`).
pub fn estimator(visibility: bool, visible_disk: bool) -> &'static ComputePass<GatherBindings, GatherParams> {
    match (visibility, visible_disk) {
        (false, _) => &GATHER,
        (true, false) => &GATHER_TRACED,
        (true, true) => &GATHER_VISIBLE_DISK,
    }
}

const SHADERS: (&ShaderInfo, &ShaderInfo) = (&shaders::GATHER_COMP_RAYQUERY, &shaders::GATHER_COMP_COMPUTE);

fn traced(tuning: &DeviceTuning) -> Specialization {
    tuning.gather().with("VISIBILITY", 1)
}

fn visible_disk(tuning: &DeviceTuning) -> Specialization {
    traced(tuning).with("VISIBLE_DISK", 1)
}

/// The photons the gather reads, and how.
pub struct GatherInputs<'a> {
    pub photons: &'a BufferHandle,
    pub radius: f32,
    /// Fixed-point units per W/m² (see [`fixed_scale`]).
    pub fixed_scale: f32,
    /// Trace a visibility segment to every photon (leakage removal).
    pub visibility: bool,
    /// Gather at most this many photons per sample (the thesis' cap); `None` = all.
    pub cap: Option<u32>,
    /// Each photon's clearance (photon_clearance.rs), to prove segments clear without a ray
    /// when `prove_clear`.
    pub clearance: &'a BufferHandle,
    /// Each sample's clearance (sample_clearance.rs), the other end of the same proofs.
    pub sample_clearance: &'a SampleClearanceHandles,
    /// Where the tiles' segments' traversals start (segment_entries.rs), when `entries_written`.
    pub segment_entries: &'a SegmentEntriesHandles,
    pub entries_written: bool,
    pub prove_clear: bool,
    /// The camera's position this frame.
    pub eye: [f32; 3],
    /// Count only photons on each sample's own surface and divide by its `disk_mass`
    /// (`leakless`); off: the whole disk, every facing photon.
    pub visible_disk: bool,
    /// Each sample's visible-disk mass (visible_disk.rs; 1 everywhere when that is off).
    pub disk_mass: &'a ImageHandle,
}

/// What the gather writes.
pub struct GatherOutputs<'a> {
    pub indirect_sum: &'a mut ImageHandle,
    pub leaked: &'a mut ImageHandle,
    /// Per pixel: candidates, visibility rays, blocked rays (heat maps).
    pub counts: &'a mut ImageHandle,
    /// [`GatherCounters`], zeroed and then counted by the gather.
    pub counters: &'a mut BufferHandle,
}

/// Units per W/m² of the gather's 64-bit fixed-point sums such that no pixel can overflow:
/// at most `photons` contributions, each at most `max_flux` × the kernel's peak 3/(π r²) at
/// `smallest_radius`, the least radius any sample gathers within (a partial disk's, see
/// [`crate::splatting::MIN_RADIUS_SHARE`]): 2⁶² units for that bound.
pub fn fixed_scale(photons: u32, max_flux: f32, smallest_radius: f32) -> f32 {
    let peak = 3.0 / (std::f64::consts::PI * (smallest_radius as f64).powi(2));
    let bound = (photons.max(1) as f64) * (max_flux.max(1e-30) as f64) * peak;
    ((1u64 << 62) as f64 / bound) as f32
}

/// The gather's counters buffer in `graph`'s pool.
pub fn counters(graph: &mut Graph<'_>) -> Result<BufferHandle> {
    Ok(graph.buffer(&BufferDesc {
        name: "gather counters",
        size: std::mem::size_of::<GatherCounters>() as u64,
        usage: vk::BufferUsageFlags::STORAGE_BUFFER
            | vk::BufferUsageFlags::TRANSFER_DST
            | vk::BufferUsageFlags::TRANSFER_SRC,
        location: MemoryLocation::GpuOnly,
    })?)
}

#[allow(clippy::too_many_arguments)]
pub fn add<'r>(
    graph: &mut Graph<'r>,
    shape: &Shape,
    input: GatherInputs<'_>,
    gbuffer: &GBufferHandles,
    hierarchy: &HierarchyHandles,
    lists: &NodeListHandles,
    out: GatherOutputs<'_>,
) {
    graph.fill(GATHER_CLEAR, &mut [(&mut *out.counters, &[Fill::whole(0)])]);
    let params = GatherParams {
        radius: input.radius,
        fixed_scale: input.fixed_scale,
        level_count: shape.levels.len() as u32,
        sample_count: shape.sample_count,
        image_width: gbuffer.position.extent().width,
        cap: input.cap.unwrap_or(0),
        prove_clear: input.prove_clear as u32,
        eye: input.eye,
        list_photons_address: address_words(graph.buffer_address(&lists.photons)),
        positions_address: address_words(graph.buffer_address(&lists.positions)),
        photons_address: address_words(graph.buffer_address(input.photons)),
        clearance_address: address_words(graph.buffer_address(input.clearance)),
        sample_clearance_tile: BALL_TILE,
        segment_entries: input.entries_written as u32,
    };
    let resources = GatherResources {
        sorted_keys: &hierarchy.keys,
        sorted_samples: &hierarchy.samples,
        levels: &hierarchy.levels,
        photons: input.photons,
        node_ends: &lists.ends,
        list_photons: &lists.photons,
        gather_counters: out.counters,
        indirect_sum: out.indirect_sum,
        leaked: out.leaked,
        gather_counts: out.counts,
        clearance: input.clearance,
        disk_mass: input.disk_mass,
        photon_positions: &lists.positions,
        sample_clearance: &input.sample_clearance.balls,
        sample_clearance_plane: &input.sample_clearance.planes,
        segment_region_lo: &input.segment_entries.region_lo,
        segment_region_hi: &input.segment_entries.region_hi,
        segment_entries: &input.segment_entries.entries,
    };
    let threads = Threads::Fixed([shape.sample_count, 1, 1]);
    estimator(input.visibility, input.visible_disk).add_as(
        graph,
        (GATHER_LABEL, None),
        resources,
        |pass| gbuffer.declare(pass),
        params,
        threads,
    );
}
