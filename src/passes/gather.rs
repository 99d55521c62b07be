//! Gather: every view sample walks the photon lists of its leaf and ancestors and sums flux ×
//! kernel over the photons within the radius that face it (`gather.comp`) into the indirect
//! layer; with visibility on, photons hidden behind geometry go to the leaked layer instead.

use ash::vk;
use bytemuck::{Pod, Zeroable};
use leakless_device::{rust_layout, BindingDecl, Bound, Buffer, BufferDesc, ComputePipeline, Gpu, MemoryLocation};
use leakless_graph::{Access, BufferHandle, Graph, ImageHandle};

use crate::error::Result;
use crate::gpu_scene::{SceneHandles, SCENE_BINDINGS};
use crate::passes::gbuffer::GBufferHandles;
use crate::passes::hierarchy::{HierarchyHandles, Shape, LEVEL_LAYOUT};
use crate::passes::photons::PHOTON_LAYOUT;
use crate::passes::splat::{NodeListHandles, LIST_ENTRY_LAYOUT};
use crate::passes::uniform::Uniform;
use crate::shaders;
use crate::trace::{Backend, TraceHandles};

/// The `GatherParams` block of gather.comp.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GatherParams {
    pub radius: f32,
    pub fixed_scale: f32,
    pub level_count: u32,
    pub sample_count: u32,
    pub image_width: u32,
    pub visibility: u32,
    pub cap: u32,
    pub pad0: u32,
}

/// The `GatherCounters` block of gather.comp: 64-bit totals as (lo, hi) word pairs.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct GatherCounters {
    pub candidates_lo: u32,
    pub candidates_hi: u32,
    pub accepted_lo: u32,
    pub accepted_hi: u32,
    pub occluded_lo: u32,
    pub occluded_hi: u32,
    pub valid_samples: u32,
    pub capped_samples: u32,
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
}

pub const BINDINGS: &[BindingDecl] = &[
    BindingDecl::storage_image("gbuffer_position"),
    BindingDecl::storage_image("gbuffer_normal"),
    BindingDecl::storage_image("gbuffer_albedo"),
    BindingDecl::storage_words("sorted_keys"),
    BindingDecl::storage_words("sorted_samples"),
    BindingDecl::storage_array("levels", LEVEL_LAYOUT),
    BindingDecl::storage_array("photons", PHOTON_LAYOUT),
    BindingDecl::storage_words("node_heads"),
    BindingDecl::storage_array("list_entries", LIST_ENTRY_LAYOUT),
    BindingDecl::storage_block(
        "gather_counters",
        rust_layout!(GatherCounters {
            candidates_lo,
            candidates_hi,
            accepted_lo,
            accepted_hi,
            occluded_lo,
            occluded_hi,
            valid_samples,
            capped_samples
        }),
    ),
    BindingDecl::storage_image("indirect_sum"),
    BindingDecl::storage_image("leaked"),
    BindingDecl::uniform(
        "params",
        rust_layout!(GatherParams {
            radius,
            fixed_scale,
            level_count,
            sample_count,
            image_width,
            visibility,
            cap,
            pad0
        }),
    ),
];

/// Every binding of the gather on `backend`: its own, the scene's (geometric normals) and the
/// trace backend's (visibility segments).
pub fn bindings(backend: Backend) -> Vec<BindingDecl> {
    [BINDINGS, SCENE_BINDINGS, backend.bindings()].concat()
}

pub struct GatherPass {
    pipeline: ComputePipeline,
    params: Uniform<GatherParams>,
    pub counters: Buffer,
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
}

/// The images the gather writes.
pub struct GatherOutputs<'a> {
    pub indirect_sum: &'a mut ImageHandle,
    pub leaked: &'a mut ImageHandle,
}

/// Units per W/m² of the gather's 64-bit fixed-point sums such that no pixel can overflow:
/// at most `photons` contributions, each at most `max_flux` × the kernel's peak 3/(π r²).
pub fn fixed_scale(photons: u32, max_flux: f32, radius: f32) -> f32 {
    let peak = 3.0 / (std::f64::consts::PI * (radius as f64).powi(2));
    let bound = (photons.max(1) as f64) * (max_flux.max(1e-30) as f64) * peak;
    ((1u64 << 62) as f64 / bound) as f32
}

impl GatherPass {
    pub fn new(gpu: &Gpu, backend: Backend) -> Result<Self> {
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST;
        let desc = BufferDesc {
            name: "gather counters",
            size: std::mem::size_of::<GatherCounters>() as u64,
            usage,
            location: MemoryLocation::GpuToCpu,
        };
        let shader = backend.pick(&shaders::GATHER_COMP_RAYQUERY, &shaders::GATHER_COMP_COMPUTE);
        Ok(GatherPass {
            pipeline: ComputePipeline::new(gpu, "gather", shader, &bindings(backend))?,
            params: Uniform::new(gpu, "gather params")?,
            counters: Buffer::new(gpu, &desc)?,
        })
    }

    /// The gather's counts of the last frame (after it completed).
    pub fn read_counters(&self) -> Result<GatherCounters> {
        Ok(self.counters.read_vec::<GatherCounters>(1)?[0])
    }

    /// Adds the gather; returns the counters' handle for the host read.
    #[allow(clippy::too_many_arguments)]
    pub fn add<'r>(
        &'r self,
        graph: &mut Graph<'r>,
        shape: &Shape,
        input: GatherInputs<'_>,
        gbuffer: &GBufferHandles,
        scene: &SceneHandles,
        trace: &TraceHandles,
        hierarchy: &HierarchyHandles,
        lists: &NodeListHandles,
        out: GatherOutputs<'_>,
    ) -> Result<BufferHandle> {
        let mut counters_h = graph.import_buffer(&self.counters);
        let mut clear = graph.pass("gather clear");
        let counters = clear.write(&mut counters_h, Access::TransferWrite);
        clear.record(move |cmd| {
            cmd.fill_buffer(counters, 0, counters.size(), 0);
            Ok(())
        });
        let params = graph.import_buffer(&self.params.buffer);
        let mut pass = graph.pass("gather");
        let position = pass.read(&gbuffer.position, Access::ComputeRead);
        self.params.set(&GatherParams {
            radius: input.radius,
            fixed_scale: input.fixed_scale,
            level_count: shape.levels.len() as u32,
            sample_count: shape.sample_count,
            image_width: position.extent().width,
            visibility: input.visibility as u32,
            cap: input.cap.unwrap_or(0),
            pad0: 0,
        })?;
        let mut bound = vec![
            ("gbuffer_position", Bound::Image(position)),
            ("gbuffer_normal", Bound::Image(pass.read(&gbuffer.normal, Access::ComputeRead))),
            ("gbuffer_albedo", Bound::Image(pass.read(&gbuffer.albedo, Access::ComputeRead))),
            ("sorted_keys", Bound::Buffer(pass.read(&hierarchy.keys, Access::ComputeRead))),
            ("sorted_samples", Bound::Buffer(pass.read(&hierarchy.samples, Access::ComputeRead))),
            ("levels", Bound::Buffer(pass.read(&hierarchy.levels, Access::ComputeRead))),
            ("photons", Bound::Buffer(pass.read(input.photons, Access::ComputeRead))),
            ("node_heads", Bound::Buffer(pass.read(&lists.heads, Access::ComputeRead))),
            ("list_entries", Bound::Buffer(pass.read(&lists.entries, Access::ComputeRead))),
            ("params", Bound::Buffer(pass.read(&params, Access::ComputeRead))),
            ("gather_counters", Bound::Buffer(pass.write(&mut counters_h, Access::ComputeReadWrite))),
            ("indirect_sum", Bound::Image(pass.write(out.indirect_sum, Access::ComputeWrite))),
            ("leaked", Bound::Image(pass.write(out.leaked, Access::ComputeWrite))),
        ];
        bound.extend(scene.declare(&mut pass, Access::ComputeRead));
        bound.extend(trace.declare(&mut pass));
        let samples = shape.sample_count;
        pass.record(move |cmd| cmd.dispatch(&self.pipeline, &bound, [samples, 1, 1]));
        Ok(counters_h)
    }
}
