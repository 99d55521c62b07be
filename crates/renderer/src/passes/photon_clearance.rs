//! Photon clearance (`photon_clearance.comp`): per stored photon, its lifted position and the
//! radius of the ball around it that holds no geometry but the photon's own plane. The gather
//! proves visibility segments inside that ball clear without tracing them (gather.comp).

use ash::vk;
use bytemuck::{Pod, Zeroable};
use leakless_device::{gpu_struct, BufferDesc, GpuStruct, MemoryLocation};
use leakless_graph::{shader_bindings, BufferHandle, Graph, PassName};

use crate::error::Result;
use crate::passes::names::group;
use crate::passes::photon_dispatch::{PhotonDispatch, PHOTON_WORKGROUP};
use crate::passes::photons::{Photon, PhotonCounters};
use crate::pipelines::{compute_pass, ComputePass, Threads};
use crate::shaders;

gpu_struct! {
    /// The `ClearanceParams` push constants of photon_clearance.comp.
    #[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
    pub struct ClearanceParams {
        /// No visibility segment of the gather is longer than this: the search stops there.
        pub max_radius: f32,
        pub capacity: u32,
        /// 1: search only for the photons `photon_listed` marks (the splat's lists took them).
        pub only_listed: u32,
        pub pad1: u32,
    }
}

gpu_struct! {
    /// One photon's entry: its lifted position (where the gather's segments end) and radius.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct Clearance {
        pub lifted: [f32; 3],
        pub radius: f32,
    }
}

shader_bindings! {
    pub struct ClearanceBindings {
        photons: read array(Photon::LAYOUT),
        photon_counters: read block(PhotonCounters::LAYOUT),
        clearance: write array(Clearance::LAYOUT),
        photon_listed: read words,
    }
    pub struct ClearanceResources;
}

/// The clearance buffer for `capacity` photons (of the graph's pool).
pub fn buffer(graph: &mut Graph<'_>, capacity: u32) -> Result<BufferHandle> {
    Ok(graph.buffer(&BufferDesc {
        name: "photon clearance",
        size: capacity.max(1) as u64 * std::mem::size_of::<Clearance>() as u64,
        usage: vk::BufferUsageFlags::STORAGE_BUFFER
            | vk::BufferUsageFlags::TRANSFER_SRC
            | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS,
        location: MemoryLocation::GpuOnly,
    })?)
}

/// Which photons need a clearance.
pub enum Needed<'a> {
    /// Every stored photon (no splat ran: the photon tests).
    All,
    /// Those some node list took (`NodeListHandles::listed`): only they reach the gather.
    Listed(&'a BufferHandle),
}

compute_pass! {
    /// The clearance searches the scene's BVH on every backend (it needs distances, not hits).
    pub static PHOTON_CLEARANCE in FRAME_PASSES: ComputePass<ClearanceBindings, ClearanceParams> =
        ComputePass::any(
            PassName::new("photon clearance", group::CLEARANCE),
            &shaders::PHOTON_CLEARANCE_COMP,
            &[],
        ).workgroup([PHOTON_WORKGROUP, 1, 1]);
}

/// Computes the clearance of the `needed` stored photons (up to the dispatch's capacity) into
/// `clearance`, searching up to `max_radius` (the longest segment the gather may trace);
/// the others get radius 0.
#[allow(clippy::too_many_arguments)]
pub fn add<'r>(
    graph: &mut Graph<'r>,
    photons: &BufferHandle,
    photon_counters: &BufferHandle,
    dispatch: &PhotonDispatch,
    max_radius: f32,
    needed: Needed<'_>,
    clearance: &mut BufferHandle,
) -> Result<()> {
    let unread;
    let (listed, only_listed) = match needed {
        Needed::Listed(listed) => (listed, 1),
        Needed::All => {
            // The binding needs a buffer; the shader does not read it.
            unread = graph.buffer(&BufferDesc {
                name: "photon listed (unread)",
                size: 4,
                usage: vk::BufferUsageFlags::STORAGE_BUFFER,
                location: MemoryLocation::GpuOnly,
            })?;
            (&unread, 0)
        }
    };
    let params = ClearanceParams { max_radius, capacity: dispatch.capacity, only_listed, ..Default::default() };
    let resources = ClearanceResources { photons, photon_counters, clearance, photon_listed: listed };
    let threads = Threads::Indirect(dispatch);
    PHOTON_CLEARANCE.add_with(graph, resources, |_| (), params, threads);
    Ok(())
}
