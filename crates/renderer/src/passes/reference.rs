//! Reference path tracer: adds samples of the indirect radiance leaving each view sample to a
//! running sum (`reference.comp`).

use bytemuck::{Pod, Zeroable};
use leakless_device::gpu_struct;
use leakless_graph::{shader_bindings, Graph, ImageHandle, PassName};

use crate::passes::names::group;
use crate::passes::{ViewInputs, VIEW_GROUPS};
use crate::pipelines::{compute_pass, ComputePass, Threads};
use crate::shaders;

gpu_struct! {
    /// The `ReferenceParams` push constants of reference.comp.
    #[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
    pub struct ReferenceParams {
        /// Index of the dispatch's first sample in the sequence (the samples already in the sum,
        /// or further along it for a progressive reference's frames).
        pub first_sample: u32,
        /// Samples this dispatch adds.
        pub sample_count: u32,
        pub max_bounces: u32,
        pub seed: u32,
        /// Bounces before Russian roulette may end a path.
        pub roulette_start: u32,
        /// 1: start the sum over (a reference's first samples, and every frame of a progressive
        /// reference: each is a whole image, averaged by the accumulate pass); 0: add to it.
        pub restart: u32,
        pub pad1: u32,
        pub pad2: u32,
    }
}

shader_bindings! {
    /// The pass's own bindings, after those of [`ViewInputs`].
    pub struct ReferenceBindings {
        accumulated: read_write image,
    }
    pub struct ReferenceResources;
}

compute_pass! {
    pub static REFERENCE in FRAME_PASSES: ComputePass<ReferenceBindings, ReferenceParams> =
        ComputePass::traced(
            PassName::new("reference", group::REFERENCE),
            (&shaders::REFERENCE_COMP_RAYQUERY, &shaders::REFERENCE_COMP_COMPUTE),
            VIEW_GROUPS,
        )
        .on_demand();
}

/// Adds `params.sample_count` samples per view sample to `accumulated` (overwrites it
/// when `params.restart` is 1), in passes of about [`PATHS_PER_PASS`] paths each (see
/// [`dispatches`]).
pub fn add<'r>(graph: &mut Graph<'r>, params: ReferenceParams, view: &ViewInputs<'_>, accumulated: &mut ImageHandle) {
    let extent = accumulated.extent();
    for params in dispatches(params, extent.width as u64 * extent.height as u64) {
        let threads = Threads::Fixed([extent.width, extent.height, 1]);
        REFERENCE.add_with(graph, ReferenceResources { accumulated }, |pass| view.declare(pass), params, threads);
    }
}

/// Paths one reference pass may trace (samples × view samples), unless one sample per view
/// sample is already more, or the frame would need more than [`MAX_PASSES_PER_FRAME`]. The
/// device's progress is read between passes (`LEAKLESS_GPU_TIMEOUT` counts a pass that makes
/// none as a lost device): a frame of many samples on a slow device (lavapipe: about 40 s for
/// this many in the atrium) is then many passes that each finish, and on a GPU no dispatch runs
/// for long.
pub const PATHS_PER_PASS: u64 = 1 << 24;

/// Reference passes one frame may hold: a quarter of the pass graph's `MAX_PASSES`, leaving
/// the rest of the frame its own.
pub const MAX_PASSES_PER_FRAME: u32 = leakless_graph::MAX_PASSES / 4;

/// `params` split into the dispatches of one frame: each continues the sequence where the last
/// stopped and adds to its sum; only the first may start the sum over.
pub fn dispatches(params: ReferenceParams, view_samples: u64) -> Vec<ReferenceParams> {
    let by_paths = (PATHS_PER_PASS / view_samples.max(1)).clamp(1, u32::MAX as u64) as u32;
    let per_pass = by_paths.max(params.sample_count.div_ceil(MAX_PASSES_PER_FRAME));
    let mut out = vec![ReferenceParams { sample_count: params.sample_count.min(per_pass), ..params }];
    let mut done = out[0].sample_count;
    while done < params.sample_count {
        let count = per_pass.min(params.sample_count - done);
        out.push(ReferenceParams {
            first_sample: params.first_sample.wrapping_add(done),
            sample_count: count,
            restart: 0,
            ..params
        });
        done += count;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_frame_of_many_samples_is_split_into_passes_that_continue_its_sequence() {
        let frame = ReferenceParams { first_sample: 40, sample_count: 300, restart: 1, seed: 9, ..Default::default() };
        // 2^24 paths over 2^16 view samples: 256 samples a pass.
        let passes = dispatches(frame, 1 << 16);
        let spans: Vec<_> = passes.iter().map(|p| (p.first_sample, p.sample_count, p.restart)).collect();
        assert_eq!(spans, [(40, 256, 1), (296, 44, 0)]);
        assert!(passes.iter().all(|p| p.seed == 9));
        // A sum that starts over is overwritten by the first pass only.
        let fresh = ReferenceParams { first_sample: 0, sample_count: 3, restart: 1, ..Default::default() };
        let spans: Vec<_> =
            dispatches(fresh, 1 << 23).iter().map(|p| (p.first_sample, p.sample_count, p.restart)).collect();
        assert_eq!(spans, [(0, 2, 1), (2, 1, 0)]);
        // Few samples: one pass. More view samples than a pass's paths: one sample a pass, but
        // never more passes than a frame may hold (4K, 512 samples: 64 passes of 8).
        assert_eq!(dispatches(frame, 64).len(), 1);
        assert_eq!(dispatches(ReferenceParams { sample_count: 60, ..frame }, 1 << 26).len(), 60);
        let big = dispatches(ReferenceParams { sample_count: 512, ..frame }, 3840 * 2160);
        assert_eq!(big.len() as u32, MAX_PASSES_PER_FRAME);
        assert_eq!(big.iter().map(|p| p.sample_count).sum::<u32>(), 512);
    }
}
