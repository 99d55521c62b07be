//! Accumulate: running sums of photon frames and their means, the image of a progressive
//! render (`accumulate.comp`; docs/architecture.md §1).

use bytemuck::{Pod, Zeroable};
use leakless_device::{gpu_struct, GpuStruct};
use leakless_graph::{shader_bindings, BufferHandle, Graph, ImageHandle, PassName};

use crate::gpu_types::Frame;
use crate::passes::names::group;
use crate::pipelines::{compute_pass, ComputePass};
use crate::shaders;

gpu_struct! {
    /// The `AccumulateParams` push constants of accumulate.comp.
    #[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
    pub struct AccumulateParams {
        /// 1: this frame starts the sums (overwrites them).
        pub first: u32,
        /// 1 / the frames in the sums once this one is added.
        pub inv_frames: f32,
        /// Photon batches this frame traced: the weight of its photon layers.
        pub batches: f32,
        /// 1 / the photon batches in the sums once this one is added.
        pub inv_batches: f32,
    }
}

shader_bindings! {
    pub struct AccumulateBindings {
        frame: read uniform(Frame::LAYOUT),
        direct: read image,
        indirect: read image,
        leaked: read image,
        sum_direct: read_write image,
        sum_indirect: read_write image,
        sum_leaked: read_write image,
        mean_direct: write image,
        mean_indirect: write image,
        mean_leaked: write image,
        mean_radiance: write image,
    }
    pub struct AccumulateResources;
}

/// This frame's layers, in.
pub struct FrameLayers<'a> {
    pub direct: &'a ImageHandle,
    pub indirect: &'a ImageHandle,
    pub leaked: &'a ImageHandle,
}

/// The sums kept from frame to frame (temporal resources of the pool, by name).
pub struct Sums<'a> {
    pub direct: &'a mut ImageHandle,
    pub indirect: &'a mut ImageHandle,
    pub leaked: &'a mut ImageHandle,
}

/// The means over the accumulated frames, out: the image.
pub struct Means<'a> {
    pub direct: &'a mut ImageHandle,
    pub indirect: &'a mut ImageHandle,
    pub leaked: &'a mut ImageHandle,
    pub radiance: &'a mut ImageHandle,
}

/// How much an accumulation holds once a frame is added.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Accumulated {
    /// Frames (1 for the first).
    pub frames: u32,
    /// Photon batches, this frame's included.
    pub batches: u32,
    /// Photon batches this frame traced.
    pub frame_batches: u32,
}

compute_pass! {
    pub static ACCUMULATE in FRAME_PASSES: ComputePass<AccumulateBindings, AccumulateParams> =
        ComputePass::any(PassName::new("accumulate", group::COMPOSE), &shaders::ACCUMULATE_COMP, &[]);
}

/// Adds frame number `count.frames` (1 for the first) of an accumulation to `sums` and
/// writes the means: the direct layer's over frames, the photon layers' over batches.
pub fn add<'r>(
    graph: &mut Graph<'r>,
    count: Accumulated,
    frame: &BufferHandle,
    layers: FrameLayers<'_>,
    sums: Sums<'_>,
    means: Means<'_>,
) {
    let params = AccumulateParams {
        first: (count.frames <= 1) as u32,
        inv_frames: 1.0 / count.frames.max(1) as f32,
        batches: count.frame_batches as f32,
        inv_batches: 1.0 / count.batches.max(1) as f32,
    };
    let extent = means.radiance.extent();
    let resources = AccumulateResources {
        frame,
        direct: layers.direct,
        indirect: layers.indirect,
        leaked: layers.leaked,
        sum_direct: sums.direct,
        sum_indirect: sums.indirect,
        sum_leaked: sums.leaked,
        mean_direct: means.direct,
        mean_indirect: means.indirect,
        mean_leaked: means.leaked,
        mean_radiance: means.radiance,
    };
    ACCUMULATE.add(graph, resources, params, [extent.width, extent.height, 1]);
}
