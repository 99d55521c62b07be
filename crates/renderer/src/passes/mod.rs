//! One pass per file, named after what it computes; each declares its bindings once
//! (`shader_bindings!`), collects itself into [`FRAME_PASSES`] where it is defined, and adds
//! itself to the frame's graph with the resources it reads and writes in its signature.

pub mod accumulate;
pub mod compose;
pub mod direct;
pub mod disk_smooth;
pub mod emission_order;
pub mod gather;
pub mod gbuffer;
pub mod hang;
pub mod hierarchy;
pub mod instance_vertices;
pub mod lighting_level;
pub mod list_scatter;
pub mod luminance;
pub mod names;
pub mod photon_clearance;
pub mod photon_dispatch;
pub mod photon_order;
pub mod photons;
pub mod primary_rays;
pub mod raycast;
pub mod readback;
pub mod reference;
pub mod sample_clearance;
pub mod scan;
pub mod segment_entries;
pub mod sort;
pub mod spatial;
pub mod splat;
pub mod temporal;
pub mod tonemap;
pub mod visible_disk;

use leakless_device::GpuStruct;
use leakless_graph::{shader_bindings, BufferHandle, PassBuilder, Stage};

use crate::gpu_scene::SceneHandles;
use crate::gpu_types::{Frame, Light};
use crate::pipelines::ComputePassDef;
use gbuffer::{GBufferBindings, GBufferHandles};

/// Every compute pass a frame may run, collected from their definitions (`compute_pass!`
/// declares each into it): the renderer's pipeline cache makes
/// them all, and the bindings test checks them all against their shaders on both backends.
#[linkme::distributed_slice]
pub static FRAME_PASSES: [&'static ComputePassDef];

/// The compute passes of tools and tests, outside the frame: `bench rays` and the
/// backend-agreement tests' ray casts, and fault injection's stall.
#[linkme::distributed_slice]
pub static TOOL_PASSES: [&'static ComputePassDef];

/// The frame's passes, as a pipeline set takes them.
pub fn frame_passes() -> Vec<&'static ComputePassDef> {
    FRAME_PASSES.to_vec()
}

/// What the passes that shade view samples bind besides the frame set: the frame, the
/// lights, the G-buffer, and the scene's buffers outside the frame set.
pub struct ViewInputs<'a> {
    pub frame: &'a BufferHandle,
    pub lights: &'a BufferHandle,
    pub scene: &'a SceneHandles,
    pub gbuffer: &'a GBufferHandles,
}

shader_bindings! {
    /// The frame and lights of a view-sample shading pass.
    pub struct ViewBindings {
        frame: read uniform(Frame::LAYOUT),
        lights: read array(Light::LAYOUT),
    }
    pub struct ViewResources;
}

/// The groups a view-sample pass binds of [`ViewInputs`]: what it is defined with.
pub const VIEW_GROUPS: &[&[leakless_device::BindingDecl]] = &[ViewBindings::DECLS, GBufferBindings::DECLS];

impl ViewInputs<'_> {
    /// Declares the compute reads of [`ViewInputs`].
    pub fn declare(&self, pass: &mut PassBuilder<'_, '_>) -> (ViewBindings, GBufferBindings) {
        let resources = ViewResources { frame: self.frame, lights: self.lights };
        (ViewBindings::declare(pass, Stage::Compute, resources), self.gbuffer.declare(pass))
    }
}
