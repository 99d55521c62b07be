//! One pass per file, named after what it computes; each declares its bindings once and adds
//! itself to the frame's graph with the resources it reads and writes.

pub mod compose;
pub mod direct;
pub mod gather;
pub mod gbuffer;
pub mod hierarchy;
pub mod photons;
pub mod raycast;
pub mod readback;
pub mod reference;
pub mod sort;
pub mod splat;
pub mod uniform;

use leakless_device::{BindingDecl, Bound};
use leakless_graph::{Access, BufferHandle, PassBuilder};

use crate::gpu_scene::{SceneHandles, SCENE_BINDINGS};
use crate::gpu_types::{FRAME_LAYOUT, LIGHT_LAYOUT};
use crate::trace::{Backend, TraceHandles};
use gbuffer::GBufferHandles;

/// What every pass that shades view samples reads: the frame, the lights, the G-buffer, the
/// scene's surfaces and the trace structures.
pub struct ViewInputs<'a> {
    pub frame: &'a BufferHandle,
    pub scene: &'a SceneHandles,
    pub trace: &'a TraceHandles,
    pub gbuffer: &'a GBufferHandles,
}

const VIEW_BINDINGS: &[BindingDecl] = &[
    BindingDecl::uniform("frame", FRAME_LAYOUT),
    BindingDecl::storage_array("lights", LIGHT_LAYOUT),
    BindingDecl::storage_image("gbuffer_position"),
    BindingDecl::storage_image("gbuffer_normal"),
    BindingDecl::storage_image("gbuffer_albedo"),
];

/// The bindings of a view-sample pass: [`ViewInputs`] plus the pass's own.
pub fn view_bindings(backend: Backend, own: &[BindingDecl]) -> Vec<BindingDecl> {
    [VIEW_BINDINGS, SCENE_BINDINGS, backend.bindings(), own].concat()
}

impl ViewInputs<'_> {
    /// Declares the compute reads of [`ViewInputs`] and returns what to bind.
    pub fn declare<'r>(&self, pass: &mut PassBuilder<'_, 'r>) -> Vec<(&'static str, Bound<'r>)> {
        let mut bound = vec![
            ("frame", Bound::Buffer(pass.read(self.frame, Access::ComputeRead))),
            ("lights", Bound::Buffer(pass.read(&self.scene.lights, Access::ComputeRead))),
            ("gbuffer_position", Bound::Image(pass.read(&self.gbuffer.position, Access::ComputeRead))),
            ("gbuffer_normal", Bound::Image(pass.read(&self.gbuffer.normal, Access::ComputeRead))),
            ("gbuffer_albedo", Bound::Image(pass.read(&self.gbuffer.albedo, Access::ComputeRead))),
        ];
        bound.extend(self.scene.declare(pass, Access::ComputeRead));
        bound.extend(self.trace.declare(pass));
        bound
    }
}
