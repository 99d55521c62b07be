//! Splat: every photon walks the view-sample hierarchy and is listed on the nodes whose
//! samples it may reach (`splat.comp`). Lists are linked through one entry buffer of fixed
//! capacity: entries beyond it are counted as dropped, never written.

use ash::vk;
use bytemuck::{Pod, Zeroable};
use leakless_device::{
    rust_layout, BindingDecl, Bound, Buffer, BufferDesc, ComputePipeline, Gpu, MemoryLocation, RustLayout,
};
use leakless_graph::{Access, BufferHandle, Graph};

use crate::error::Result;
use crate::passes::hierarchy::{HierarchyHandles, Shape, LEVEL_LAYOUT, NODE_LAYOUT};
use crate::passes::photons::{PHOTON_COUNTERS_LAYOUT, PHOTON_LAYOUT};
use crate::passes::uniform::Uniform;
use crate::shaders;

/// `struct ListEntry` of photon.glsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct ListEntry {
    pub photon: u32,
    pub next: u32,
}

pub const LIST_ENTRY_LAYOUT: RustLayout = rust_layout!(ListEntry { photon, next });

/// The `SplatCounters` block of splat.comp.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct SplatCounters {
    pub entries_used: u32,
    pub entries_dropped: u32,
    pub nodes_visited: u32,
    pub pad0: u32,
}

/// The `SplatParams` block of splat.comp.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct SplatParams {
    pub radius: f32,
    pub trivial_accept: u32,
    pub root: u32,
    pub capacity: u32,
    pub photon_capacity: u32,
    pub pad0: u32,
    pub pad1: u32,
    pub pad2: u32,
}

pub const BINDINGS: &[BindingDecl] = &[
    BindingDecl::storage_array("photons", PHOTON_LAYOUT),
    BindingDecl::storage_block("photon_counters", PHOTON_COUNTERS_LAYOUT),
    BindingDecl::storage_array("levels", LEVEL_LAYOUT),
    BindingDecl::storage_array("nodes", NODE_LAYOUT),
    BindingDecl::storage_words("node_heads"),
    BindingDecl::storage_array("list_entries", LIST_ENTRY_LAYOUT),
    BindingDecl::storage_block(
        "splat_counters",
        rust_layout!(SplatCounters { entries_used, entries_dropped, nodes_visited, pad0 }),
    ),
    BindingDecl::uniform(
        "params",
        rust_layout!(SplatParams { radius, trivial_accept, root, capacity, photon_capacity, pad0, pad1, pad2 }),
    ),
];

/// The node lists, kept between frames.
pub struct NodeLists {
    pub heads: Buffer,
    pub entries: Buffer,
    pub counters: Buffer,
    pub capacity: u32,
}

impl NodeLists {
    pub fn new(gpu: &Gpu, node_count: u32, capacity: u32) -> Result<NodeLists> {
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST;
        let buffer =
            |name, size| Buffer::new(gpu, &BufferDesc { name, size, usage, location: MemoryLocation::GpuOnly });
        let counters = Buffer::new(
            gpu,
            &BufferDesc { name: "splat counters", size: 16, usage, location: MemoryLocation::GpuToCpu },
        )?;
        Ok(NodeLists {
            heads: buffer("node list heads", 4 * node_count as u64)?,
            entries: buffer("node list entries", 8 * capacity as u64)?,
            counters,
            capacity,
        })
    }

    pub fn import<'r>(&'r self, graph: &mut Graph<'r>) -> NodeListHandles {
        NodeListHandles {
            heads: graph.import_buffer(&self.heads),
            entries: graph.import_buffer(&self.entries),
            counters: graph.import_buffer(&self.counters),
        }
    }

    /// The splat's counts of the last frame (after it completed).
    pub fn read_counters(&self) -> Result<SplatCounters> {
        Ok(self.counters.read_vec::<SplatCounters>(1)?[0])
    }
}

pub struct NodeListHandles {
    pub heads: BufferHandle,
    pub entries: BufferHandle,
    pub counters: BufferHandle,
}

pub struct SplatPass {
    pipeline: ComputePipeline,
    params: Uniform<SplatParams>,
}

/// What the splat walks and with which photons.
pub struct SplatInputs<'a> {
    pub photons: &'a BufferHandle,
    pub photon_counters: &'a BufferHandle,
    pub photon_capacity: u32,
    pub radius: f32,
    pub trivial_accept: bool,
}

impl SplatPass {
    pub fn new(gpu: &Gpu) -> Result<Self> {
        Ok(SplatPass {
            pipeline: ComputePipeline::new(gpu, "splat", &shaders::SPLAT_COMP, BINDINGS)?,
            params: Uniform::new(gpu, "splat params")?,
        })
    }

    pub fn add<'r>(
        &'r self,
        graph: &mut Graph<'r>,
        shape: &Shape,
        input: SplatInputs<'_>,
        hierarchy: &HierarchyHandles,
        lists: &mut NodeListHandles,
        capacity: u32,
    ) -> Result<()> {
        self.params.set(&SplatParams {
            radius: input.radius,
            trivial_accept: input.trivial_accept as u32,
            root: shape.root(),
            capacity,
            photon_capacity: input.photon_capacity,
            ..Default::default()
        })?;
        let mut clear = graph.pass("splat clear");
        let heads = clear.write(&mut lists.heads, Access::TransferWrite);
        let counters = clear.write(&mut lists.counters, Access::TransferWrite);
        clear.record(move |cmd| {
            cmd.fill_buffer(heads, 0, heads.size(), u32::MAX);
            cmd.fill_buffer(counters, 0, counters.size(), 0);
            Ok(())
        });
        let params = graph.import_buffer(&self.params.buffer);
        let mut pass = graph.pass("splat");
        let bound = [
            ("photons", Bound::Buffer(pass.read(input.photons, Access::ComputeRead))),
            ("photon_counters", Bound::Buffer(pass.read(input.photon_counters, Access::ComputeRead))),
            ("levels", Bound::Buffer(pass.read(&hierarchy.levels, Access::ComputeRead))),
            ("nodes", Bound::Buffer(pass.read(&hierarchy.nodes, Access::ComputeRead))),
            ("params", Bound::Buffer(pass.read(&params, Access::ComputeRead))),
            ("node_heads", Bound::Buffer(pass.write(&mut lists.heads, Access::ComputeReadWrite))),
            ("list_entries", Bound::Buffer(pass.write(&mut lists.entries, Access::ComputeWrite))),
            ("splat_counters", Bound::Buffer(pass.write(&mut lists.counters, Access::ComputeReadWrite))),
        ];
        let photons = input.photon_capacity;
        pass.record(move |cmd| cmd.dispatch(&self.pipeline, &bound, [photons, 1, 1]));
        Ok(())
    }
}
