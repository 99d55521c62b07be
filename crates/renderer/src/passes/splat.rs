//! Splat: every photon walks the view-sample hierarchy and is recorded on the nodes whose
//! samples it may reach, each node counting its records (`splat.comp`); the list scatter
//! (`list_scatter.rs`) then lays every node's photons out contiguously. The record and list
//! buffers have a fixed capacity: records beyond it are counted as dropped, never written.

use ash::vk;
use bytemuck::{Pod, Zeroable};
use leakless_device::{gpu_struct, BufferDesc, GpuStruct, MemoryLocation};
use leakless_graph::{shader_bindings, BufferHandle, Fill, Graph, PassName};

use crate::device_address::address_words;
use crate::error::Result;
use crate::passes::hierarchy::{HierarchyHandles, Level, Node, SamplePosition, Shape};
use crate::passes::names::group;
use crate::passes::photon_dispatch::{PhotonDispatch, PHOTON_WORKGROUP};
use crate::passes::photons::{Photon, PhotonCounters};
use crate::pipelines::{compute_pass, ComputePass, Threads};
use crate::shaders;

gpu_struct! {
    /// `struct SplatRecord` of photon.glsl: a node's list takes a photon.
    #[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
    pub struct SplatRecord {
        pub node: u32,
        pub photon: u32,
    }
}

gpu_struct! {
    /// `struct PhotonPosition` of photon.glsl: a photon's position alone, 16 bytes.
    #[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
    pub struct PhotonPosition {
        pub position: [f32; 3],
        pub pad0: u32,
    }
}

gpu_struct! {
    /// The `SplatCounters` block of splat.comp.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
    pub struct SplatCounters {
        /// List entries recorded (and attempted beyond capacity).
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
        /// Entries the record and list buffers hold.
        pub capacity: u32,
        /// Photons the photon buffer holds.
        pub photon_capacity: u32,
        /// 1: some samples gather beyond the frame's radius; test each node's own largest.
        pub node_radius: u32,
        /// The hierarchy's nodes, read through their device address (splat.comp says why).
        pub nodes_address: [u32; 2],
    }
}

shader_bindings! {
    pub struct SplatBindings {
        photons: read array(Photon::LAYOUT),
        photon_counters: read block(PhotonCounters::LAYOUT),
        levels: read array(Level::LAYOUT),
        nodes: read array(Node::LAYOUT),
        node_counts: read_write words,
        splat_records: write array(SplatRecord::LAYOUT),
        splat_counters: read_write block(SplatCounters::LAYOUT),
        photon_listed: write words,
        photon_positions: write array(PhotonPosition::LAYOUT),
        sample_positions: read array(SamplePosition::LAYOUT),
    }
    pub struct SplatResources;
}

/// The node lists of one frame (buffers of the graph's pool).
pub struct NodeListHandles {
    /// Per node: the splat's count of its records; the list scan makes it the first slot of
    /// the node's range, and the list scatter the end of it (`list_scatter.comp`).
    pub ends: BufferHandle,
    /// Nodes the `ends` buffer has words for: the node count rounded up for the scan.
    pub node_words: u32,
    /// The splat's (node, photon) records, in the order the splat made them.
    pub records: BufferHandle,
    /// Every node's photons, node after node: the lists the gather reads.
    pub photons: BufferHandle,
    /// Per photon, its position (vec4, w unused): what the gather's distance test reads.
    pub positions: BufferHandle,
    pub counters: BufferHandle,
    /// Per photon, 1 when some list took it (only those reach the gather), else 0.
    pub listed: BufferHandle,
    pub capacity: u32,
}

/// The name of the buffer of every node's photons (captures read it back).
pub const LIST_PHOTONS: &str = "node list photons";
/// The name of the buffer of the nodes' list ends.
pub const LIST_ENDS: &str = "node list ends";

/// The list buffers' usage: storage, filled and read back by transfers.
pub const LIST_BUFFER_USAGE: vk::BufferUsageFlags = vk::BufferUsageFlags::from_raw(
    vk::BufferUsageFlags::STORAGE_BUFFER.as_raw()
        | vk::BufferUsageFlags::TRANSFER_DST.as_raw()
        | vk::BufferUsageFlags::TRANSFER_SRC.as_raw()
        | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS.as_raw(),
);

/// Words the `ends` buffer of `node_count` nodes has: a multiple of the scan's group of 16.
pub fn node_words(node_count: u32) -> u32 {
    node_count.div_ceil(crate::passes::sort::RADIX) * crate::passes::sort::RADIX
}

impl NodeListHandles {
    /// Lists for `node_count` nodes with room for `capacity` entries, of `photons` photons.
    pub fn new(graph: &mut Graph<'_>, node_count: u32, capacity: u32, photons: u32) -> Result<NodeListHandles> {
        let mut buffer = |name, size| {
            graph.buffer(&BufferDesc { name, size, usage: LIST_BUFFER_USAGE, location: MemoryLocation::GpuOnly })
        };
        let node_words = node_words(node_count);
        let entries = capacity.max(1) as u64;
        Ok(NodeListHandles {
            ends: buffer(LIST_ENDS, 4 * node_words as u64)?,
            node_words,
            records: buffer("splat records", std::mem::size_of::<SplatRecord>() as u64 * entries)?,
            photons: buffer(LIST_PHOTONS, 4 * entries)?,
            positions: buffer(
                "photon positions",
                std::mem::size_of::<PhotonPosition>() as u64 * photons.max(1) as u64,
            )?,
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
    /// One thread per stored photon, or a cluster of the tuning's `splat_lanes` threads.
    pub dispatch: &'a PhotonDispatch,
    /// The largest radius any sample gathers within.
    pub radius: f32,
    /// Whether samples' radii exceed the frame's (grown partial disks): the nodes' own
    /// largest radius then culls more (the hierarchy's `radius_max`).
    pub node_radius: bool,
    pub trivial_accept: bool,
}

const SPLAT_CLEAR: PassName = PassName::new("splat clear", group::SPLAT);
/// The dispatch of a splat that walks each photon with a cluster of lanes.
pub const SPLAT_DISPATCH: PassName = PassName::new("splat dispatch", group::SPLAT);

compute_pass! {
    /// The splat: one thread per stored photon, or a cluster of threads (`DeviceTuning::splat_lanes`).
    pub static SPLAT in FRAME_PASSES: ComputePass<SplatBindings, SplatParams> =
        ComputePass::any(PassName::new("splat", group::SPLAT), &shaders::SPLAT_COMP, &[])
            .workgroup([PHOTON_WORKGROUP, 1, 1])
            .specialize(crate::tuning::DeviceTuning::splat);
}

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
        nodes_address: address_words(graph.buffer_address(&hierarchy.nodes)),
    };
    let zero = [Fill::whole(0)];
    graph.fill(SPLAT_CLEAR, &mut [(&mut lists.ends, &zero), (&mut lists.counters, &zero)]);
    let resources = SplatResources {
        photons: input.photons,
        photon_counters: input.photon_counters,
        levels: &hierarchy.levels,
        nodes: &hierarchy.nodes,
        node_counts: &mut lists.ends,
        splat_records: &mut lists.records,
        splat_counters: &mut lists.counters,
        photon_listed: &mut lists.listed,
        photon_positions: &mut lists.positions,
        sample_positions: &hierarchy.positions,
    };
    SPLAT.add_with(graph, resources, |_| (), params, Threads::Indirect(input.dispatch));
}
