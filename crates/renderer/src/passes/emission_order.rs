//! Emission order: which path each thread of the photon pass takes, grouped by emission cell,
//! a 256×256 grid over the square the path's emission sample lies in, cells in Morton order
//! (`emission_cells.comp`, the sort's scan, `emission_order.comp`).
//!
//! Low-discrepancy paths in index order spread over the whole light by design, so the lanes
//! of a SIMD group started from points all over it and their rays took different branches of
//! the BVH. Taken in this order they start side by side. Every path is still traced, with the
//! same samples, so the photons are the same and so is every image.

use ash::vk;
use bytemuck::{Pod, Zeroable};
use leakless_device::{gpu_struct, BufferDesc, MemoryLocation};
use leakless_graph::{shader_bindings, BufferHandle, Fill, Graph, PassName};

use crate::error::Result;
use crate::passes::names::group;
use crate::passes::scan;
use crate::pipelines::{compute_pass, ComputePass};
use crate::shaders;

/// Bits per axis of a cell index (`EMISSION_CELL_BITS` in emission_cell.glsl).
pub const CELL_BITS: u32 = 8;
/// Cells of the grid.
pub const CELLS: u32 = 1 << (2 * CELL_BITS);

gpu_struct! {
    /// The `EmissionOrderParams` push constants of emission_cell.glsl.
    #[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
    pub struct EmissionOrderParams {
        pub paths: u32,
        pub path_offset: u32,
        pub seed: u32,
        pub pad0: u32,
    }
}

shader_bindings! {
    pub struct EmissionCellBindings {
        cell_counts: read_write words,
    }
    pub struct EmissionCellResources;
}

shader_bindings! {
    pub struct EmissionOrderBindings {
        cell_starts: read_write words,
        path_order: write words,
    }
    pub struct EmissionOrderResources;
}

pub const EMISSION_CELLS_CLEAR: PassName = PassName::new("emission cells clear", group::PHOTONS);
pub const EMISSION_CELL_STARTS: PassName = PassName::new("emission cell starts", group::PHOTONS);

compute_pass! {
    pub static EMISSION_CELLS in FRAME_PASSES: ComputePass<EmissionCellBindings, EmissionOrderParams> =
        ComputePass::any(PassName::new("emission cells", group::PHOTONS), &shaders::EMISSION_CELLS_COMP, &[]);
}

compute_pass! {
    pub static EMISSION_ORDER in FRAME_PASSES: ComputePass<EmissionOrderBindings, EmissionOrderParams> =
        ComputePass::any(PassName::new("emission order", group::PHOTONS), &shaders::EMISSION_ORDER_COMP, &[]);
}

/// Adds the passes that order the `params.paths` paths; returns the buffer of path indices
/// in the order the photon pass takes them.
pub fn add<'r>(graph: &mut Graph<'r>, params: EmissionOrderParams) -> Result<BufferHandle> {
    let storage = |name, words: u32, usage| BufferDesc {
        name,
        size: 4 * words.max(1) as u64,
        usage: vk::BufferUsageFlags::STORAGE_BUFFER | usage,
        location: MemoryLocation::GpuOnly,
    };
    let mut counts = graph.buffer(&storage("emission cell counts", CELLS, vk::BufferUsageFlags::TRANSFER_DST))?;
    let mut order = graph.buffer(&storage("path order", params.paths, vk::BufferUsageFlags::empty()))?;
    graph.fill(EMISSION_CELLS_CLEAR, &mut [(&mut counts, &[Fill::whole(0)])]);
    let threads = [params.paths, 1, 1];
    EMISSION_CELLS.add(graph, EmissionCellResources { cell_counts: &mut counts }, params, threads);

    scan::add(graph, (EMISSION_CELL_STARTS, None), CELLS, &mut counts)?;

    EMISSION_ORDER.add(
        graph,
        EmissionOrderResources { cell_starts: &mut counts, path_order: &mut order },
        params,
        threads,
    );
    Ok(order)
}
