//! Direct light: Lambertian reflection of every punctual light at each view sample, with one
//! shadow ray per light (`direct.comp`).

use leakless_graph::{shader_bindings, Graph, ImageHandle, PassName, Stage};

use crate::gpu_scene::SceneBindings;
use crate::passes::gbuffer::GBufferBindings;
use crate::passes::names::group;
use crate::passes::{ViewBindings, ViewInputs};
use crate::pipelines::ComputePassDef;
use crate::shaders;

shader_bindings! {
    /// The pass's own bindings, after those of [`ViewInputs`].
    pub struct DirectBindings {
        direct: write image,
    }
    pub struct DirectResources;
}

pub static DIRECT: ComputePassDef = ComputePassDef::traced(
    PassName::new("direct", group::DIRECT),
    (&shaders::DIRECT_COMP_RAYQUERY, &shaders::DIRECT_COMP_COMPUTE),
    &[ViewBindings::DECLS, GBufferBindings::DECLS, SceneBindings::DECLS, DirectBindings::DECLS],
);

pub fn add<'r>(graph: &mut Graph<'r>, view: &ViewInputs<'_>, direct: &mut ImageHandle) {
    let extent = direct.extent();
    let mut pass = graph.pass(DIRECT.name);
    let inputs = view.declare(&mut pass);
    let own = DirectBindings::declare(&mut pass, Stage::Compute, DirectResources { direct });
    pass.dispatch(DIRECT.name, (inputs, own), (), [extent.width, extent.height, 1]);
}
