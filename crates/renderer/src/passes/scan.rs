//! An exclusive prefix sum of u32 counts, in place, by one workgroup (`sort_scan.comp`): the
//! radix sort's step 2 (`sort.rs`), and on its own the first slot of every cell of the photon
//! and emission orders (`photon_order.rs`, `emission_order.rs`).

use leakless_device::GpuStruct;
use leakless_graph::{shader_bindings, BufferHandle, Graph, PassName};

use crate::error::{RenderError, Result};
use crate::passes::names::group;
use crate::passes::sort::{sort_pass, SortParams, RADIX, WORKGROUP_SIZE};
use crate::pipelines::{compute_pass, ComputePass, Threads};
use crate::shaders;

shader_bindings! {
    pub struct ScanBindings {
        histograms: read_write array(u32::LAYOUT),
    }
    pub struct ScanResources;
}

compute_pass! {
    /// The scan is one workgroup of the sort's size.
    pub static SCAN in FRAME_PASSES: ComputePass<ScanBindings, SortParams> =
        sort_pass(PassName::new("sort scan", group::HIERARCHY), &shaders::SORT_SCAN_COMP);
}

/// Adds a pass named `name` (number `index` of a repeated pass) that turns the first
/// `words` counts of `counts` into exclusive prefix sums. The scan walks counts in groups of
/// 16 (one per radix digit of a sort workgroup), so `words` must be a multiple of 16.
pub fn add<'r>(
    graph: &mut Graph<'r>,
    (name, index): (PassName, Option<u32>),
    words: u32,
    counts: &mut BufferHandle,
) -> Result<()> {
    if words % RADIX != 0 || counts.size() < 4 * words as u64 {
        return Err(RenderError::Settings(format!(
            "{name}: {words} counts in {} bytes; the scan needs a multiple of {RADIX} that the buffer holds",
            counts.size()
        )));
    }
    let params = SortParams { group_count: words / RADIX, ..Default::default() };
    let threads = Threads::Fixed([WORKGROUP_SIZE, 1, 1]);
    SCAN.add_as(graph, (name, index), ScanResources { histograms: counts }, |_| (), params, threads);
    Ok(())
}
