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
use leakless_device::{gpu_struct, BufferDesc, ComputePipeline, Gpu, GpuStruct, MemoryLocation};
use leakless_graph::{shader_bindings, Access, BufferHandle, Graph};

use crate::error::Result;
use crate::passes::scan::ScanPass;
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
        cell_counts: words,
    }
}

shader_bindings! {
    pub struct EmissionOrderBindings {
        cell_starts: words,
        path_order: words,
    }
}

pub struct EmissionOrderPass {
    cells: ComputePipeline,
    scan: ScanPass,
    order: ComputePipeline,
}

impl EmissionOrderPass {
    pub fn new(gpu: &Gpu) -> Result<Self> {
        let push = Some(&EmissionOrderParams::LAYOUT);
        Ok(EmissionOrderPass {
            cells: ComputePipeline::new(
                gpu,
                "emission cells",
                &shaders::EMISSION_CELLS_COMP,
                EmissionCellBindings::DECLS,
                push,
            )?,
            scan: ScanPass::new(gpu)?,
            order: ComputePipeline::new(
                gpu,
                "emission order",
                &shaders::EMISSION_ORDER_COMP,
                EmissionOrderBindings::DECLS,
                push,
            )?,
        })
    }

    /// Adds the passes that order the `params.paths` paths; returns the buffer of path indices
    /// in the order the photon pass takes them.
    pub fn add<'r>(&'r self, graph: &mut Graph<'r>, params: EmissionOrderParams) -> Result<BufferHandle> {
        let storage = |name, words: u32, usage| BufferDesc {
            name,
            size: 4 * words.max(1) as u64,
            usage: vk::BufferUsageFlags::STORAGE_BUFFER | usage,
            location: MemoryLocation::GpuOnly,
        };
        let mut counts = graph.buffer(&storage("emission cell counts", CELLS, vk::BufferUsageFlags::TRANSFER_DST))?;
        let mut order = graph.buffer(&storage("path order", params.paths, vk::BufferUsageFlags::empty()))?;
        let mut clear = graph.pass("emission cells clear");
        let cleared = clear.write(&mut counts, Access::TransferWrite);
        clear.record(move |ctx| {
            let counts = ctx.buffer(cleared);
            ctx.cmd.fill_buffer(counts, 0, counts.size(), 0);
            Ok(())
        });
        let threads = [params.paths, 1, 1];
        let mut pass = graph.pass("emission cells");
        let own = EmissionCellBindings { cell_counts: pass.write(&mut counts, Access::ComputeReadWrite) };
        pass.record(move |ctx| ctx.dispatch(&self.cells, &[&own], &params, threads));

        self.scan.add(graph, "emission cell starts", CELLS, &mut counts)?;

        let mut pass = graph.pass("emission order");
        let own = EmissionOrderBindings {
            cell_starts: pass.write(&mut counts, Access::ComputeReadWrite),
            path_order: pass.write(&mut order, Access::ComputeWrite),
        };
        pass.record(move |ctx| ctx.dispatch(&self.order, &[&own], &params, threads));
        Ok(order)
    }
}
