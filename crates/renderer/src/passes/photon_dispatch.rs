//! The workgroup count of every pass that runs one thread per stored photon (photon cells and
//! order, splat, clearance), written on the device from the photon counters
//! (`photon_dispatch.comp`) and read by indirect dispatches. The photon buffer has room for
//! `paths × max_bounces` photons, so a dispatch over that capacity ran about eight threads
//! per photon in the atrium, seven of them only to return: 12% of an accumulating frame's
//! time on lavapipe, where every workgroup costs its launch. The list scatter's dispatch is
//! made the same way from the splat's counters ([`add_over`]).

use ash::vk;
use bytemuck::{Pod, Zeroable};
use leakless_device::{gpu_struct, BufferDesc, GpuStruct, MemoryLocation};
use leakless_graph::{shader_bindings, Access, Buf, BufferHandle, Graph, PassBuilder, PassName};

use crate::error::Result;
use crate::passes::names::group;
use crate::pipelines::{compute_pass, ComputePass, Threads};
use crate::shaders;

/// Threads per workgroup of every per-photon pass, checked when their pipelines are made
/// (`ComputePassDef::workgroup`).
pub const PHOTON_WORKGROUP: u32 = 64;

gpu_struct! {
    /// The `PhotonDispatchParams` push constants of photon_dispatch.comp.
    #[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
    pub struct PhotonDispatchParams {
        pub capacity: u32,
        pub group_size: u32,
        pub max_groups: u32,
        pub pad1: u32,
    }
}

gpu_struct! {
    /// `VkDispatchIndirectCommand`, the `PhotonDispatch` block of photon_dispatch.comp.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
    pub struct DispatchCommand {
        pub x: u32,
        pub y: u32,
        pub z: u32,
    }
}

shader_bindings! {
    pub struct PhotonDispatchBindings {
        counters: read words,
        photon_dispatch: write block(DispatchCommand::LAYOUT),
    }
    pub struct PhotonDispatchResources;
}

/// A frame's per-photon dispatch: the command's buffer, and the capacity that bounds it.
pub struct PhotonDispatch {
    pub args: BufferHandle,
    pub capacity: u32,
    /// Workgroups the command asks for at most.
    pub max_groups: u32,
    /// Items a workgroup of [`PHOTON_WORKGROUP`] threads takes: all of them one each, or
    /// fewer, each a cluster of threads (the splat's shared walk).
    pub items_per_group: u32,
}

impl PhotonDispatch {
    /// Declares the pass's indirect read of the command; pass the result to
    /// `dispatch_indirect` with [`PhotonDispatch::most_threads`].
    pub fn declare(&self, pass: &mut PassBuilder<'_, '_>) -> (Buf, u64) {
        (pass.read(&self.args, Access::IndirectCommandRead), 0)
    }

    /// The threads the command asks for at most: the workgroups of the items the buffer
    /// holds, within `max_groups` of them.
    pub fn most_threads(&self) -> [u32; 3] {
        let groups = self.capacity.div_ceil(self.items_per_group.max(1)).min(self.max_groups);
        [groups.saturating_mul(PHOTON_WORKGROUP), 1, 1]
    }
}

compute_pass! {
    pub static PHOTON_DISPATCH in FRAME_PASSES: ComputePass<PhotonDispatchBindings, PhotonDispatchParams> =
        ComputePass::any(PassName::new("photon dispatch", group::PHOTONS), &shaders::PHOTON_DISPATCH_COMP, &[]);
}

/// Adds the pass that turns `photon_counters` (of a buffer of `capacity` photons) into the
/// per-photon passes' dispatch. `limits::check` holds the photons within the workgroup limit.
pub fn add<'r>(graph: &mut Graph<'r>, photon_counters: &BufferHandle, capacity: u32) -> Result<PhotonDispatch> {
    add_over(graph, (PHOTON_DISPATCH.name, "photon dispatch"), photon_counters, capacity, (PHOTON_WORKGROUP, u32::MAX))
}

/// Adds a pass named `name` that turns the first word of `counters`, at most `capacity` items,
/// into a dispatch of groups of [`PHOTON_WORKGROUP`] threads, `items_per_group` items each (one
/// thread an item, or a cluster of threads), at most `max_groups` groups (a pass over more
/// items loops), written to a buffer named `args`.
pub fn add_over<'r>(
    graph: &mut Graph<'r>,
    (name, args): (PassName, &'static str),
    counters: &BufferHandle,
    capacity: u32,
    (items_per_group, max_groups): (u32, u32),
) -> Result<PhotonDispatch> {
    let mut args = graph.buffer(&BufferDesc {
        name: args,
        size: std::mem::size_of::<DispatchCommand>() as u64,
        usage: vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::INDIRECT_BUFFER,
        location: MemoryLocation::GpuOnly,
    })?;
    let items_per_group = items_per_group.clamp(1, PHOTON_WORKGROUP);
    let params = PhotonDispatchParams { capacity, group_size: items_per_group, max_groups, ..Default::default() };
    let resources = PhotonDispatchResources { counters, photon_dispatch: &mut args };
    PHOTON_DISPATCH.add_as(graph, (name, None), resources, |_| (), params, Threads::Fixed([1, 1, 1]));
    Ok(PhotonDispatch { args, capacity, max_groups, items_per_group })
}
