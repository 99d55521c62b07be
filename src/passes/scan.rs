//! An exclusive prefix sum of u32 counts, in place, by one workgroup (`sort_scan.comp`): the
//! radix sort's step 2 (`sort.rs`), and on its own the first slot of every cell of the photon
//! and emission orders (`photon_order.rs`, `emission_order.rs`).

use leakless_device::{ComputePipeline, Gpu, GpuStruct};
use leakless_graph::{shader_bindings, Access, BufferHandle, Graph};

use crate::error::{RenderError, Result};
use crate::passes::sort::{sort_pipeline, SortParams, RADIX, WORKGROUP_SIZE};
use crate::shaders;

shader_bindings! {
    pub struct ScanBindings {
        histograms: array(u32::LAYOUT),
    }
}

pub struct ScanPass {
    pipeline: ComputePipeline,
}

impl ScanPass {
    pub fn new(gpu: &Gpu) -> Result<Self> {
        Ok(ScanPass { pipeline: sort_pipeline(gpu, "sort scan", &shaders::SORT_SCAN_COMP, ScanBindings::DECLS)? })
    }

    /// Adds a pass named `name` that turns the first `words` counts of `counts` into exclusive
    /// prefix sums. The scan walks counts in groups of 16 (one per radix digit of a sort
    /// workgroup), so `words` must be a multiple of 16.
    pub fn add<'r>(&'r self, graph: &mut Graph<'r>, name: &str, words: u32, counts: &mut BufferHandle) -> Result<()> {
        if words % RADIX != 0 || counts.size() < 4 * words as u64 {
            return Err(RenderError::Settings(format!(
                "{name}: {words} counts in {} bytes; the scan needs a multiple of {RADIX} that the buffer holds",
                counts.size()
            )));
        }
        let params = SortParams { group_count: words / RADIX, ..Default::default() };
        let mut pass = graph.pass(name);
        let own = ScanBindings { histograms: pass.write(counts, Access::ComputeReadWrite) };
        pass.record(move |ctx| ctx.dispatch(&self.pipeline, &[&own], &params, [WORKGROUP_SIZE, 1, 1]));
        Ok(())
    }
}
