//! Accumulate: running sums of photon frames and their means, the image of a progressive
//! render (`accumulate.comp`; docs/architecture.md §1).

use bytemuck::{Pod, Zeroable};
use leakless_device::{gpu_struct, ComputePipeline, Gpu, GpuStruct};
use leakless_graph::{shader_bindings, Access, BufferHandle, Graph, ImageHandle};

use crate::error::Result;
use crate::gpu_types::Frame;
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
        frame: uniform(Frame::LAYOUT),
        direct: image,
        indirect: image,
        leaked: image,
        sum_direct: image,
        sum_indirect: image,
        sum_leaked: image,
        mean_direct: image,
        mean_indirect: image,
        mean_leaked: image,
        mean_radiance: image,
    }
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

pub struct AccumulatePass {
    pipeline: ComputePipeline,
}

impl AccumulatePass {
    pub fn new(gpu: &Gpu) -> Result<Self> {
        let pipeline = ComputePipeline::new(
            gpu,
            "accumulate",
            &shaders::ACCUMULATE_COMP,
            AccumulateBindings::DECLS,
            Some(&AccumulateParams::LAYOUT),
        )?;
        Ok(AccumulatePass { pipeline })
    }

    /// Adds frame number `count.frames` (1 for the first) of an accumulation to `sums` and
    /// writes the means: the direct layer's over frames, the photon layers' over batches.
    pub fn add<'r>(
        &'r self,
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
        let mut pass = graph.pass("accumulate");
        let own = AccumulateBindings {
            frame: pass.read(frame, Access::ComputeRead),
            direct: pass.read(layers.direct, Access::ComputeRead),
            indirect: pass.read(layers.indirect, Access::ComputeRead),
            leaked: pass.read(layers.leaked, Access::ComputeRead),
            sum_direct: pass.write(sums.direct, Access::ComputeReadWrite),
            sum_indirect: pass.write(sums.indirect, Access::ComputeReadWrite),
            sum_leaked: pass.write(sums.leaked, Access::ComputeReadWrite),
            mean_direct: pass.write(means.direct, Access::ComputeWrite),
            mean_indirect: pass.write(means.indirect, Access::ComputeWrite),
            mean_leaked: pass.write(means.leaked, Access::ComputeWrite),
            mean_radiance: pass.write(means.radiance, Access::ComputeWrite),
        };
        pass.record(move |ctx| ctx.dispatch(&self.pipeline, &[&own], &params, [extent.width, extent.height, 1]));
    }
}
