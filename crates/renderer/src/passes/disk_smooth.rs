//! Disk smoothing (`disk_smooth.comp`): a single `leakless` frame's visible-disk mass and
//! radius, averaged over the samples of each surface within the distance neighbours lend their
//! directions at (`visible_disk::share_distance`), with a stride that spans that distance on the
//! screen. The visible-disk pass's own sharing spans a fixed 3×3 block of pixels (5×5 where a
//! direction is missing), whose noise is pixel-scale grain on narrow faces at larger sizes; this
//! takes it out at every resolution.

use bytemuck::{Pod, Zeroable};
use leakless_device::{gpu_struct, GpuStruct};
use leakless_graph::{shader_bindings, BufferHandle, Graph, ImageHandle, PassName};

use crate::gpu_types::Frame;
use crate::passes::gbuffer::{GBufferBindings, GBufferHandles};
use crate::passes::names::group;
use crate::pipelines::{compute_pass, ComputePass, Threads};
use crate::shaders;

gpu_struct! {
    /// The `DiskSmoothParams` push constants of disk_smooth.comp.
    #[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
    pub struct DiskSmoothParams {
        /// The frame's gather radius.
        pub radius: f32,
        /// Taps nearer than this share of the radius count (`visible_disk::share_distance`).
        pub share_distance: f32,
        pub pad0: u32,
        pub pad1: u32,
    }
}

shader_bindings! {
    pub struct DiskSmoothBindings {
        frame: read uniform(Frame::LAYOUT),
        measured: read image,
        disk_mass: write image,
    }
    pub struct DiskSmoothResources;
}

compute_pass! {
    pub static DISK_SMOOTH in FRAME_PASSES: ComputePass<DiskSmoothBindings, DiskSmoothParams> =
        ComputePass::any(
            PassName::new("disk smoothing", group::VISIBLE_DISK),
            &shaders::DISK_SMOOTH_COMP,
            &[GBufferBindings::DECLS],
        );
}

/// Writes `measured` (the visible-disk pass's image), smoothed, into `disk_mass`.
pub fn add<'r>(
    graph: &mut Graph<'r>,
    params: DiskSmoothParams,
    frame: &BufferHandle,
    gbuffer: &GBufferHandles,
    measured: &ImageHandle,
    disk_mass: &mut ImageHandle,
) {
    let extent = disk_mass.extent();
    let resources = DiskSmoothResources { frame, measured, disk_mass };
    let threads = Threads::Fixed([extent.width, extent.height, 1]);
    DISK_SMOOTH.add_with(graph, resources, |pass| gbuffer.declare(pass), params, threads);
}
