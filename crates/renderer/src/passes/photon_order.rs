//! Photon order: a counting sort of the frame's photons by the cell of a 32³ grid over the
//! scene's bounds, cells in Morton order (`photon_cells.comp`, the sort's scan,
//! `photon_order.comp`).
//!
//! Photons are stored in the order their paths' atomics reach the buffer, so the 8 lanes of
//! one of lavapipe's SIMD groups (a GPU's 32 of a subgroup) hold photons from all over the
//! scene. The splat walks the view-sample hierarchy per photon and the clearance the BVH: a
//! group costs its longest walk, and its lanes load different nodes. Ordered by cell, a
//! group's photons lie together, take the same branches and culls, and those that no sample
//! sees (out of view, facing away) share groups that end at once. The photons are copied,
//! not indexed, so the gather's reads of a node list's photons fall close together too.
//! The splat, clearance and gather read only the ordered copy; every image is bit-identical to
//! the unordered one (the gather's sums do not depend on order), which `tests/suite/` checks.

use ash::vk;
use bytemuck::{Pod, Zeroable};
use leakless_device::shader::ShaderInfo;
use leakless_device::{gpu_struct, BufferDesc, GpuStruct, MemoryLocation};
use leakless_graph::{shader_bindings, BufferHandle, Fill, Graph, PassName};
use leakless_scene::Aabb;

use crate::error::Result;
use crate::passes::names::group;
use crate::passes::photon_dispatch::{PhotonDispatch, PHOTON_WORKGROUP};
use crate::passes::photons::{Photon, PhotonCounters};
use crate::passes::scan;
use crate::pipelines::Threads;
use crate::pipelines::{compute_pass, ComputePass};
use crate::shaders;
use leakless_graph::BindingGroup;

/// Bits per axis of a cell index (`PHOTON_CELL_BITS` in photon_cell.glsl): 32 cells a side.
/// At the default gather radius (5% of the scene's bounding radius) a cell is about 1.2 radii
/// wide, so a SIMD group's photons reach mostly the same nodes; finer cells order little more.
pub const CELL_BITS: u32 = 5;
/// Cells of the grid: 32,768 counts, which the scan walks in 8 tiles.
pub const CELLS: u32 = 1 << (3 * CELL_BITS);
/// The pool's name of the ordered copy (the capture reads it back by it).
pub const ORDERED_PHOTONS: &str = "ordered photons";

/// The cell of a position, as `photon_cell` in photon_cell.glsl computes it (for tests: the
/// device's division may round a position on a cell's boundary to the other side).
pub fn cell(p: [f32; 3], bounds: &Aabb) -> u32 {
    let side = 1u32 << CELL_BITS;
    let t = ((glam::Vec3::from(p) - bounds.min) / (bounds.max - bounds.min).max(glam::Vec3::splat(1e-30)))
        .clamp(glam::Vec3::ZERO, glam::Vec3::ONE);
    let c = (t * side as f32).to_array().map(|x| (x as u32).min(side - 1));
    let spread = |v: u32| (0..CELL_BITS).fold(0, |acc, i| acc | ((v >> i) & 1) << (3 * i));
    (spread(c[0]) << 2) | (spread(c[1]) << 1) | spread(c[2])
}

gpu_struct! {
    /// The `PhotonOrderParams` push constants of photon_cell.glsl.
    #[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
    pub struct PhotonOrderParams {
        pub bounds_min: [f32; 3],
        /// Photons the buffers hold.
        pub capacity: u32,
        pub bounds_max: [f32; 3],
        pub pad0: u32,
    }
}

shader_bindings! {
    pub struct CellBindings {
        photons: read array(Photon::LAYOUT),
        photon_counters: read block(PhotonCounters::LAYOUT),
        cell_counts: read_write words,
        photon_cell_of: write words,
    }
    pub struct CellResources;
}

shader_bindings! {
    pub struct OrderBindings {
        photons: read array(Photon::LAYOUT),
        photon_counters: read block(PhotonCounters::LAYOUT),
        cell_starts: read_write words,
        ordered_photons: write array(Photon::LAYOUT),
        photon_cell_of: read words,
    }
    pub struct OrderResources;
}

/// The two per-photon passes of the order.
const fn order_pass<B: BindingGroup>(name: PassName, shader: &'static ShaderInfo) -> ComputePass<B, PhotonOrderParams> {
    ComputePass::any(name, shader, &[]).workgroup([PHOTON_WORKGROUP, 1, 1])
}

const PHOTON_CELLS_CLEAR: PassName = PassName::new("photon cells clear", group::PHOTON_ORDER);
const PHOTON_CELL_STARTS: PassName = PassName::new("photon cell starts", group::PHOTON_ORDER);

compute_pass! {
    pub static PHOTON_CELLS in FRAME_PASSES: ComputePass<CellBindings, PhotonOrderParams> =
        order_pass(PassName::new("photon cells", group::PHOTON_ORDER), &shaders::PHOTON_CELLS_COMP);
    pub static PHOTON_ORDER in FRAME_PASSES: ComputePass<OrderBindings, PhotonOrderParams> =
        order_pass(PassName::new("photon order", group::PHOTON_ORDER), &shaders::PHOTON_ORDER_COMP);
}

/// Copies the stored photons of `photons` (at most the dispatch's capacity) into `ordered`,
/// grouped by cell of a grid over `bounds`, and cells in Morton order.
pub fn add<'r>(
    graph: &mut Graph<'r>,
    photons: &BufferHandle,
    photon_counters: &BufferHandle,
    dispatch: &PhotonDispatch,
    bounds: &Aabb,
    ordered: &mut BufferHandle,
) -> Result<()> {
    let params = PhotonOrderParams {
        bounds_min: bounds.min.to_array(),
        capacity: dispatch.capacity,
        bounds_max: bounds.max.to_array(),
        pad0: 0,
    };
    let mut counts = graph.buffer(&BufferDesc {
        name: "photon cell counts",
        size: 4 * CELLS as u64,
        usage: vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
        location: MemoryLocation::GpuOnly,
    })?;
    let mut cell_of = graph.buffer(&BufferDesc {
        name: "photon cell of",
        size: 4 * dispatch.capacity.max(1) as u64,
        usage: vk::BufferUsageFlags::STORAGE_BUFFER,
        location: MemoryLocation::GpuOnly,
    })?;
    graph.fill(PHOTON_CELLS_CLEAR, &mut [(&mut counts, &[Fill::whole(0)])]);

    let resources = CellResources { photons, photon_counters, cell_counts: &mut counts, photon_cell_of: &mut cell_of };
    PHOTON_CELLS.add_with(graph, resources, |_| (), params, Threads::Indirect(dispatch));

    scan::add(graph, (PHOTON_CELL_STARTS, None), CELLS, &mut counts)?;

    let resources = OrderResources {
        photons,
        photon_counters,
        cell_starts: &mut counts,
        ordered_photons: ordered,
        photon_cell_of: &cell_of,
    };
    PHOTON_ORDER.add_with(graph, resources, |_| (), params, Threads::Indirect(dispatch));
    Ok(())
}
