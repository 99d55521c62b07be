//! One pass per file, named after what it computes; each declares its bindings once
//! (`shader_bindings!`) and adds itself to the frame's graph with the resources it reads and
//! writes in its signature.

pub mod accumulate;
pub mod compose;
pub mod direct;
pub mod emission_order;
pub mod gather;
pub mod gbuffer;
pub mod hang;
pub mod hierarchy;
pub mod instance_vertices;
pub mod luminance;
pub mod photon_clearance;
pub mod photon_dispatch;
pub mod photon_order;
pub mod photons;
pub mod raycast;
pub mod readback;
pub mod reference;
pub mod scan;
pub mod sort;
pub mod splat;
pub mod tonemap;
pub mod visible_disk;

use leakless_device::{BindingDecl, GpuStruct};
use leakless_graph::{shader_bindings, Access, BufferHandle, PassBuilder};

use crate::gpu_scene::{SceneBindings, SceneHandles};
use crate::gpu_types::{Frame, Light};
use crate::trace::{Backend, TraceBindings, TraceHandles};
use gbuffer::GBufferHandles;

/// What every pass that shades view samples reads: the frame, the lights, the G-buffer, the
/// scene's surfaces and the trace structures.
pub struct ViewInputs<'a> {
    pub frame: &'a BufferHandle,
    pub lights: &'a BufferHandle,
    pub scene: &'a SceneHandles,
    pub trace: &'a TraceHandles,
    pub gbuffer: &'a GBufferHandles,
}

shader_bindings! {
    /// The frame, lights and G-buffer of a view-sample shading pass.
    pub struct ViewBindings {
        frame: uniform(Frame::LAYOUT),
        lights: array(Light::LAYOUT),
        gbuffer_position: image,
        gbuffer_normal: image,
        gbuffer_albedo: image,
    }
}

/// The bindings of a view-sample pass: [`ViewInputs`] plus the pass's own.
pub fn view_bindings(backend: Backend, own: &[BindingDecl]) -> Vec<BindingDecl> {
    [ViewBindings::DECLS, SceneBindings::DECLS, backend.bindings(), own].concat()
}

impl ViewInputs<'_> {
    /// Declares the compute reads of [`ViewInputs`].
    pub fn declare(&self, pass: &mut PassBuilder<'_, '_>) -> (ViewBindings, SceneBindings, TraceBindings) {
        let view = ViewBindings {
            frame: pass.read(self.frame, Access::ComputeRead),
            lights: pass.read(self.lights, Access::ComputeRead),
            gbuffer_position: pass.read(&self.gbuffer.position, Access::ComputeRead),
            gbuffer_normal: pass.read(&self.gbuffer.normal, Access::ComputeRead),
            gbuffer_albedo: pass.read(&self.gbuffer.albedo, Access::ComputeRead),
        };
        (view, self.scene.declare(pass, Access::ComputeRead), self.trace.declare(pass))
    }
}
