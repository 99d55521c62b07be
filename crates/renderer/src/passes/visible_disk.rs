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
use leakless_graph::{shader_bindings, BufferHandle, Graph, ImageHandle, PassName};

use crate::error::Result;
use crate::gpu_scene::SceneHandles;
use crate::gpu_types::Frame;
use crate::passes::gbuffer::{self, GBufferBindings, GBufferHandles};
use crate::passes::names::group;
use crate::pipelines::{compute_pass, ComputePass, Threads};
use crate::shaders;

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
        /// `x | y << 16`: the workgroups' 8×8 tiles, whose samples share their rays, start this
        /// far up and left of pixel 0 (moved every frame: [`tile_offset`]).
        pub tile_offset: u32,
        /// This frame's turn of the directions, in quarter turns (`[0, 1)`), the same for every
        /// sample so that four directions a quarter turn apart measure a straight edge exactly;
        /// an accumulation averages over the turns ([`rotation`]).
        pub rotation: f32,
        /// Neighbours closer than this share of the radius lend their directions: [`share_distance`].
        pub share_distance: f32,
        pub pad1: u32,
        pub pad2: u32,
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
/// the sample's gather radius in `.g`, in `.b` the rays down its invocation traced (its own
/// direction's and the jobs it took for its workgroup: a diagnostic whose sum over the image
/// `Renderer::capture` reads back for the tests), and in `.a` how far the
/// gather lifts the sample's visibility segments on a convex curved mesh (traced, so it
/// stops short of anything in front; 0 elsewhere).
pub fn image(graph: &mut Graph<'_>, extent: vk::Extent2D) -> Result<ImageHandle> {
    mass_image(graph, extent, "disk mass")
}

/// The image this pass writes where `disk_smooth` then averages it into [`image`]'s.
pub fn measured_image(graph: &mut Graph<'_>, extent: vk::Extent2D) -> Result<ImageHandle> {
    mass_image(graph, extent, "disk mass measured")
}

fn mass_image(graph: &mut Graph<'_>, extent: vk::Extent2D, name: &'static str) -> Result<ImageHandle> {
    Ok(graph.image(&ImageDesc {
        name,
        extent,
        format: gbuffer::FORMAT,
        usage: vk::ImageUsageFlags::STORAGE | vk::ImageUsageFlags::TRANSFER_SRC,
    })?)
}

compute_pass! {
    pub static VISIBLE_DISK in FRAME_PASSES: ComputePass<VisibleDiskBindings, VisibleDiskParams> =
        ComputePass::traced(
            PassName::new("visible disk", group::VISIBLE_DISK),
            (&shaders::VISIBLE_DISK_COMP_RAYQUERY, &shaders::VISIBLE_DISK_COMP_COMPUTE),
            &[GBufferBindings::DECLS],
        );
}

/// Writes each sample's mass and radius into `disk_mass` (mass 1 and the frame's radius
/// everywhere when `params.enabled` is 0).
#[allow(clippy::too_many_arguments)]
pub fn add<'r>(
    graph: &mut Graph<'r>,
    params: VisibleDiskParams,
    frame: &BufferHandle,
    gbuffer: &GBufferHandles,
    scene: &SceneHandles,
    disk_mass: &mut ImageHandle,
) {
    let extent = disk_mass.extent();
    let resources = VisibleDiskResources { frame, disk_mass, coplanar_neighbours: &scene.coplanar_neighbours };
    // One more tile each way: the tiles start up to TILE − 1 pixels before pixel 0.
    let threads = Threads::Fixed([extent.width + TILE - 1, extent.height + TILE - 1, 1]);
    VISIBLE_DISK.add_with(graph, resources, |pass| gbuffer.declare(pass), params, threads);
}

/// The side of visible_disk.comp's workgroups, whose samples share their directions' masses.
pub const TILE: u32 = 8;

/// Where a frame's tiles start (`VisibleDiskParams::tile_offset`), drawn from its `seed`: the
/// edges of a tile make the sharing one-sided, and moving them every frame keeps an
/// accumulation free of a seam along them.
pub fn tile_offset(seed: u32) -> u32 {
    let h = seed.wrapping_mul(0x2c1b_3c6d) ^ (seed >> 15);
    let h = h.wrapping_mul(0x297a_2d39) ^ (h >> 12);
    (h % TILE) | (((h >> 8) % TILE) << 16)
}

/// How near (a share of the frame's radius) a neighbour on the same surface must be to lend a
/// sample its direction (`VisibleDiskParams::share_distance`): 0.375 in a single frame, none in
/// an accumulation. A neighbour's disk is not the sample's, and the mass curves along a surface
/// near its edges, so sharing blurs it a little: a bias that an accumulation keeps, whose error
/// is bias once its noise has averaged away. Measured on the atrium at 160×120 (32 frames,
/// `corner_bias::accumulation_shrinks_the_radius_of_partial_disks`' setting): sharing within
/// 0.375r left the partial disks' relMSE at 0.00471, within 0.1r at 0.00390. A single frame's
/// error is its noise, which sharing lowers, and it is what a camera in motion shows.
pub fn share_distance(first_batch: u32) -> f32 {
    if first_batch == 0 {
        0.375
    } else {
        0.0
    }
}

/// The frame's turn of the directions (`VisibleDiskParams::rotation`), drawn from its `seed`.
pub fn rotation(seed: u32) -> f32 {
    let h = seed.wrapping_mul(0x9e37_79b9) ^ (seed >> 16);
    let h = h.wrapping_mul(0x85eb_ca6b) ^ (h >> 13);
    (h >> 8) as f32 / (1u32 << 24) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiles_move_over_every_offset() {
        let mut seen = std::collections::HashSet::new();
        for seed in 0..4096 {
            let offset = tile_offset(seed);
            assert!(offset & 0xffff < TILE && offset >> 16 < TILE, "{offset:#x}");
            seen.insert(offset);
        }
        assert_eq!(seen.len(), (TILE * TILE) as usize);
    }

    /// The frame's turn is uniform over a quarter turn: an accumulation measures every
    /// direction around each sample alike.
    #[test]
    fn the_turn_covers_a_quarter_turn_evenly() {
        let mut bins = [0u32; 8];
        for seed in 0..8192 {
            let turn = rotation(seed);
            assert!((0.0..1.0).contains(&turn), "{turn}");
            bins[(turn * 8.0) as usize] += 1;
        }
        assert!(bins.iter().all(|&n| (900..=1150).contains(&n)), "{bins:?}");
    }
}
