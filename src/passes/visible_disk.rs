//! Visible disk (`visible_disk.comp`): per view sample, the share of the gather kernel's mass
//! over the part of its disk where the sample's own surface exists and can be seen from it.
//! `leakless` divides the flux of the photons on that surface by it instead of by the whole
//! disk, which darkened it wherever the disk runs off a face or behind an occluder. It also
//! sets the radius of samples whose disk is partial: grown in a single frame, shrunk as an
//! accumulation goes on (the gather's and the hierarchy's radius rides in `.g`), and traces
//! the lift the gather gives a convex curved mesh's segments (`.a`).

use ash::vk;
use bytemuck::{Pod, Zeroable};
use leakless_device::{gpu_struct, GpuStruct, ImageDesc};
use leakless_graph::{shader_bindings, BufferHandle, Graph, ImageHandle, PassName, Stage};

use crate::error::Result;
use crate::gpu_scene::{SceneBindings, SceneHandles};
use crate::gpu_types::Frame;
use crate::passes::gbuffer::{self, GBufferBindings, GBufferHandles};
use crate::passes::names::group;
use crate::pipelines::ComputePassDef;
use crate::shaders;
use crate::trace::TraceHandles;

gpu_struct! {
    /// The `VisibleDiskParams` push constants of visible_disk.comp.
    #[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
    pub struct VisibleDiskParams {
        /// This frame's gather radius.
        pub radius: f32,
        /// This frame's seed (the rotation of the rays).
        pub seed: u32,
        /// 0: every sample's mass is 1 (the whole disk).
        pub enabled: u32,
        /// γ: where the disk is partial, the sample's radius becomes r·clamp(m^γ, s, g): grown
        /// for γ < 0, shrunk for γ > 0, kept for 0.
        pub partial_radius_exponent: f32,
        /// s: the least share of the radius a partial disk shrinks to.
        pub min_radius_share: f32,
        /// 1: walk to a coplanar neighbour before tracing a probe's ray down.
        pub walk_faces: u32,
        /// g: the largest share of the radius a partial disk grows to.
        pub max_radius_share: f32,
        pub pad1: u32,
    }
}

shader_bindings! {
    /// What visible_disk.comp binds besides the scene and the trace structures.
    pub struct VisibleDiskBindings {
        frame: read uniform(Frame::LAYOUT),
        disk_mass: write image,
        coplanar_neighbours: read array(u32::LAYOUT),
    }
    pub struct VisibleDiskResources;
}

/// The per-pixel mass image of an `extent` frame (of the graph's pool): the mass in `.r`,
/// the sample's gather radius in `.g`, in `.b` the rays down the pass traced for it (a
/// diagnostic: `Renderer::capture` reads it back for the tests), and in `.a` how far the
/// gather lifts the sample's visibility segments on a convex curved mesh (traced, so it
/// stops short of anything in front; 0 elsewhere).
pub fn image(graph: &mut Graph<'_>, extent: vk::Extent2D) -> Result<ImageHandle> {
    Ok(graph.image(&ImageDesc {
        name: "disk mass",
        extent,
        format: gbuffer::FORMAT,
        usage: vk::ImageUsageFlags::STORAGE | vk::ImageUsageFlags::TRANSFER_SRC,
    })?)
}

pub static VISIBLE_DISK: ComputePassDef = ComputePassDef::traced(
    PassName::new("visible disk", group::VISIBLE_DISK),
    (&shaders::VISIBLE_DISK_COMP_RAYQUERY, &shaders::VISIBLE_DISK_COMP_COMPUTE),
    &[VisibleDiskBindings::DECLS, GBufferBindings::DECLS, SceneBindings::DECLS],
)
.push(VisibleDiskParams::LAYOUT);

/// Writes each sample's mass and radius into `disk_mass` (mass 1 and the frame's radius
/// everywhere when `params.enabled` is 0).
#[allow(clippy::too_many_arguments)]
pub fn add<'r>(
    graph: &mut Graph<'r>,
    params: VisibleDiskParams,
    frame: &BufferHandle,
    gbuffer: &GBufferHandles,
    scene: &SceneHandles,
    trace: &TraceHandles,
    disk_mass: &mut ImageHandle,
) {
    let extent = disk_mass.extent();
    let mut pass = graph.pass(VISIBLE_DISK.name);
    let own = VisibleDiskBindings::declare(
        &mut pass,
        Stage::Compute,
        VisibleDiskResources { frame, disk_mass, coplanar_neighbours: &scene.coplanar_neighbours },
    );
    let gbuffer = gbuffer.declare(&mut pass);
    let surfaces = scene.declare(&mut pass, Stage::Compute);
    let trace = trace.declare(&mut pass);
    pass.dispatch(VISIBLE_DISK.name, (own, gbuffer, surfaces, trace), params, [extent.width, extent.height, 1]);
}
