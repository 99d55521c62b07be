//! The node lists made contiguous: the list scan turns the splat's per-node counts into the
//! first slot of each node's range (an exclusive prefix sum, `scan.rs`), and the list scatter
//! (`list_scatter.comp`) writes each splat record's photon into its node's range, leaving the
//! range's end in the node's word. The gather then reads a node's list as one run of photon
//! indices, with no link to follow and no per-entry atomic on a shared head.

use bytemuck::{Pod, Zeroable};
use leakless_device::{gpu_struct, GpuStruct};
use leakless_graph::{shader_bindings, Graph, PassName};

use crate::error::Result;
use crate::passes::names::group;
use crate::passes::photon_dispatch::{self, PHOTON_WORKGROUP};
use crate::passes::scan;
use crate::passes::splat::{NodeListHandles, SplatCounters, SplatRecord};
use crate::pipelines::{compute_pass, ComputePass, Threads};
use crate::shaders;

gpu_struct! {
    /// The `ListScatterParams` push constants of list_scatter.comp.
    #[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
    pub struct ListScatterParams {
        /// Records the buffers hold: the splat counts those beyond it too.
        pub capacity: u32,
        pub pad0: u32,
        pub pad1: u32,
        pub pad2: u32,
    }
}

shader_bindings! {
    pub struct ListScatterBindings {
        splat_counters: read block(SplatCounters::LAYOUT),
        splat_records: read array(SplatRecord::LAYOUT),
        node_ends: read_write words,
        list_photons: write words,
    }
    pub struct ListScatterResources;
}

const LIST_SCAN: PassName = PassName::new("list scan", group::SPLAT);

/// The scatter's workgroups, from the splat's count of records (photon_dispatch.comp).
const LIST_DISPATCH: PassName = PassName::new("list dispatch", group::SPLAT);

compute_pass! {
    /// One thread per record, looping where the records outnumber the workgroups.
    pub static LIST_SCATTER in FRAME_PASSES: ComputePass<ListScatterBindings, ListScatterParams> =
        ComputePass::any(
            PassName::new("list scatter", group::SPLAT),
            &shaders::LIST_SCATTER_COMP,
            &[],
        ).workgroup([PHOTON_WORKGROUP, 1, 1]);
}

/// Adds the scan, the dispatch and the scatter that lay out `lists` after the splat; the
/// scatter runs at most `max_groups` workgroups (the device's maxComputeWorkGroupCount[0]).
pub fn add<'r>(graph: &mut Graph<'r>, lists: &mut NodeListHandles, max_groups: u32) -> Result<()> {
    scan::add(graph, (LIST_SCAN, None), lists.node_words, &mut lists.ends)?;
    let dispatch = photon_dispatch::add_over(
        graph,
        (LIST_DISPATCH, "list dispatch"),
        &lists.counters,
        lists.capacity,
        (PHOTON_WORKGROUP, max_groups),
    )?;
    let params = ListScatterParams { capacity: lists.capacity, ..Default::default() };
    let resources = ListScatterResources {
        splat_counters: &lists.counters,
        splat_records: &lists.records,
        node_ends: &mut lists.ends,
        list_photons: &mut lists.photons,
    };
    LIST_SCATTER.add_with(graph, resources, |_| (), params, Threads::Indirect(&dispatch));
    Ok(())
}
