//! Splat: every photon walks the view-sample hierarchy and is listed on the nodes whose
//! samples it may reach (`splat.comp`). Lists are linked through one entry buffer of fixed
//! capacity: entries beyond it are counted as dropped, never written.

use ash::vk;
use bytemuck::{Pod, Zeroable};
use leakless_device::{gpu_struct, BufferDesc, GpuStruct, MemoryLocation};
use leakless_graph::{shader_bindings, BufferHandle, Fill, Graph, PassName, Stage};

use crate::error::Result;
use crate::passes::hierarchy::{HierarchyHandles, Level, Node, Shape};
use crate::passes::names::group;
use crate::passes::photon_dispatch::{PhotonDispatch, PHOTON_WORKGROUP};
use crate::passes::photons::{Photon, PhotonCounters};
use crate::pipelines::ComputePassDef;
use crate::shaders;

gpu_struct! {
    /// `struct ListEntry` of photon.glsl.
    #[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
    pub struct ListEntry {
        pub photon: u32,
        pub next: u32,
    }
}

gpu_struct! {
    /// The `SplatCounters` block of splat.comp.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
    pub struct SplatCounters {
        /// List entries written (and attempted beyond capacity).
        pub entries_used: u32,
        /// Entries that did not fit: their contributions are lost.
        pub entries_dropped: u32,
        /// Node tests made by all photons.
        pub nodes_visited: u32,
        /// Photons some list took: those the gather can reach, and the clearance searches for.
        pub photons_listed: u32,
    }
}

gpu_struct! {
    /// The `SplatParams` push constants of splat.comp.
    #[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
    pub struct SplatParams {
        /// The largest radius any sample gathers within.
        pub radius: f32,
        pub trivial_accept: u32,
        pub root: u32,
        /// Entries the list buffer holds.
        pub capacity: u32,
        /// Photons the photon buffer holds.
        pub photon_capacity: u32,
        /// 1: some samples gather beyond the frame's radius; test each node's own largest.
        pub node_radius: u32,
        pub pad1: u32,
        pub pad2: u32,
    }
}

shader_bindings! {
    pub struct SplatBindings {
        photons: read array(Photon::LAYOUT),
        photon_counters: read block(PhotonCounters::LAYOUT),
        levels: read array(Level::LAYOUT),
        nodes: read array(Node::LAYOUT),
        node_heads: read_write words,
        list_entries: write array(ListEntry::LAYOUT),
        splat_counters: read_write block(SplatCounters::LAYOUT),
        photon_listed: write words,
    }
    pub struct SplatResources;
}

/// The node lists of one frame (buffers of the graph's pool).
pub struct NodeListHandles {
    pub heads: BufferHandle,
    pub entries: BufferHandle,
    pub counters: BufferHandle,
    /// Per photon, 1 when some list took it (only those reach the gather), else 0.
    pub listed: BufferHandle,
    pub capacity: u32,
}

impl NodeListHandles {
    /// Lists for `node_count` nodes with room for `capacity` entries, of `photons` photons.
    pub fn new(graph: &mut Graph<'_>, node_count: u32, capacity: u32, photons: u32) -> Result<NodeListHandles> {
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER
            | vk::BufferUsageFlags::TRANSFER_DST
            | vk::BufferUsageFlags::TRANSFER_SRC;
        let mut buffer =
            |name, size| graph.buffer(&BufferDesc { name, size, usage, location: MemoryLocation::GpuOnly });
        Ok(NodeListHandles {
            heads: buffer("node list heads", 4 * node_count as u64)?,
            entries: buffer("node list entries", std::mem::size_of::<ListEntry>() as u64 * capacity as u64)?,
            counters: buffer("splat counters", std::mem::size_of::<SplatCounters>() as u64)?,
            listed: buffer("photon listed", 4 * photons.max(1) as u64)?,
            capacity,
        })
    }
}

/// What the splat walks and with which photons.
pub struct SplatInputs<'a> {
    pub photons: &'a BufferHandle,
    pub photon_counters: &'a BufferHandle,
    /// One thread per stored photon.
    pub dispatch: &'a PhotonDispatch,
    /// The largest radius any sample gathers within.
    pub radius: f32,
    /// Whether samples' radii exceed the frame's (grown partial disks): the nodes' own
    /// largest radius then culls more (the hierarchy's `radius_max`).
    pub node_radius: bool,
    pub trivial_accept: bool,
}

const SPLAT_CLEAR: PassName = PassName::new("splat clear", group::SPLAT);

/// The splat: one thread per stored photon.
pub static SPLAT: ComputePassDef =
    ComputePassDef::any(PassName::new("splat", group::SPLAT), &shaders::SPLAT_COMP, &[SplatBindings::DECLS])
        .push(SplatParams::LAYOUT)
        .workgroup([PHOTON_WORKGROUP, 1, 1])
        .specialize(crate::tuning::DeviceTuning::counters);

pub fn add<'r>(
    graph: &mut Graph<'r>,
    shape: &Shape,
    input: SplatInputs<'_>,
    hierarchy: &HierarchyHandles,
    lists: &mut NodeListHandles,
) {
    let params = SplatParams {
        radius: input.radius,
        node_radius: input.node_radius as u32,
        trivial_accept: input.trivial_accept as u32,
        root: shape.root(),
        capacity: lists.capacity,
        photon_capacity: input.dispatch.capacity,
        ..Default::default()
    };
    let empty = [Fill::whole(u32::MAX)];
    graph.fill(SPLAT_CLEAR, &mut [(&mut lists.heads, &empty), (&mut lists.counters, &[Fill::whole(0)])]);
    let mut pass = graph.pass(SPLAT.name);
    let own = SplatBindings::declare(
        &mut pass,
        Stage::Compute,
        SplatResources {
            photons: input.photons,
            photon_counters: input.photon_counters,
            levels: &hierarchy.levels,
            nodes: &hierarchy.nodes,
            node_heads: &mut lists.heads,
            list_entries: &mut lists.entries,
            splat_counters: &mut lists.counters,
            photon_listed: &mut lists.listed,
        },
    );
    let (args, threads) = (input.dispatch.declare(&mut pass), input.dispatch.most_threads());
    pass.dispatch_indirect(SPLAT.name, own, params, args, threads);
}
