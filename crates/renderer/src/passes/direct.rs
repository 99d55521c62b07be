//! Direct light: Lambertian reflection of every punctual light at each view sample, with one
//! shadow ray per light, of the emissive triangles by resampled next-event estimation, and the
//! emission the camera sees (`direct.comp`).

use bytemuck::{Pod, Zeroable};
use leakless_device::gpu_struct;
use leakless_graph::{shader_bindings, Graph, ImageHandle, PassName};

use crate::passes::names::group;
use crate::passes::{ViewInputs, VIEW_GROUPS};
use crate::pipelines::{compute_pass, ComputePass, Threads};
use crate::shaders;

gpu_struct! {
    /// The `DirectParams` push constants of direct.comp.
    #[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
    pub struct DirectParams {
        /// Index of the frame's first emitter sample in the pixel's sequence: the frames of an
        /// accumulation continue one stratified sequence.
        pub first_sample: u32,
        /// Shadow rays toward emitters per pixel.
        pub samples: u32,
        /// Emitter points resampled for each shadow ray.
        pub candidates: u32,
        pub seed: u32,
    }
}

/// Shadow rays toward emitters one pixel may trace in a frame.
pub const MAX_SAMPLES: u32 = 1024;

/// A reference frame traces `light_samples` emitter rays per this many of its path samples: a
/// set per sample would cost more than the paths on lavapipe (8 candidates a ray are
/// arithmetic, but many), for direct light whose noise is already far below the indirect
/// light's.
pub const REFERENCE_SAMPLES_PER_DIRECT: u32 = 8;

shader_bindings! {
    /// The pass's own bindings, after those of [`ViewInputs`].
    pub struct DirectBindings {
        direct: write image,
    }
    pub struct DirectResources;
}

compute_pass! {
    pub static DIRECT in FRAME_PASSES: ComputePass<DirectBindings, DirectParams> =
        ComputePass::traced(
            PassName::new("direct", group::DIRECT),
            (&shaders::DIRECT_COMP_RAYQUERY, &shaders::DIRECT_COMP_COMPUTE),
            VIEW_GROUPS,
        );
}

pub fn add<'r>(graph: &mut Graph<'r>, params: DirectParams, view: &ViewInputs<'_>, direct: &mut ImageHandle) {
    let extent = direct.extent();
    let threads = Threads::Fixed([extent.width, extent.height, 1]);
    DIRECT.add_with(graph, DirectResources { direct }, |pass| view.declare(pass), params, threads);
}
