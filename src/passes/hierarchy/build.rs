//! Hierarchy build: one dispatch per level, bottom up, each node from its samples or children
//! (`hierarchy_build.comp`).

use leakless_device::{BindingDecl, Bound, ComputePipeline, Gpu};
use leakless_graph::{Access, Graph};

use super::{HierarchyHandles, Shape, LEVEL_LAYOUT, NODE_LAYOUT};
use crate::error::Result;
use crate::passes::gbuffer::GBufferHandles;
use crate::passes::uniform::Uniform;
use crate::shaders;

/// The `BuildParams` block of hierarchy_build.comp.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub struct BuildParams {
    pub level: u32,
    pub branching: u32,
    pub sample_count: u32,
    pub image_width: u32,
}

pub const BINDINGS: &[BindingDecl] = &[
    BindingDecl::storage_image("gbuffer_position"),
    BindingDecl::storage_image("gbuffer_normal"),
    BindingDecl::storage_words("sorted_keys"),
    BindingDecl::storage_words("sorted_samples"),
    BindingDecl::storage_array("levels", LEVEL_LAYOUT),
    BindingDecl::storage_array("nodes", NODE_LAYOUT),
    BindingDecl::uniform(
        "params",
        leakless_device::rust_layout!(BuildParams { level, branching, sample_count, image_width }),
    ),
];

pub struct BuildPass {
    pipeline: ComputePipeline,
    /// One parameter block per level: each level's dispatch reads its own.
    params: Vec<Uniform<BuildParams>>,
}

impl BuildPass {
    pub fn new(gpu: &Gpu, levels: usize) -> Result<Self> {
        let params = (0..levels).map(|_| Uniform::new(gpu, "hierarchy build params")).collect::<Result<_>>()?;
        Ok(BuildPass {
            pipeline: ComputePipeline::new(gpu, "hierarchy build", &shaders::HIERARCHY_BUILD_COMP, BINDINGS)?,
            params,
        })
    }

    pub fn add<'r>(
        &'r self,
        graph: &mut Graph<'r>,
        shape: &Shape,
        gbuffer: &GBufferHandles,
        h: &mut HierarchyHandles,
    ) -> Result<()> {
        for (index, (info, uniform)) in shape.levels.iter().zip(&self.params).enumerate() {
            let params_h = graph.import_buffer(&uniform.buffer);
            let mut pass = graph.pass(&format!("hierarchy level {index}"));
            let position = pass.read(&gbuffer.position, Access::ComputeRead);
            uniform.set(&BuildParams {
                level: index as u32,
                branching: shape.branching,
                sample_count: shape.sample_count,
                image_width: position.extent().width,
            })?;
            let bound = [
                ("gbuffer_position", Bound::Image(position)),
                ("gbuffer_normal", Bound::Image(pass.read(&gbuffer.normal, Access::ComputeRead))),
                ("sorted_keys", Bound::Buffer(pass.read(&h.keys, Access::ComputeRead))),
                ("sorted_samples", Bound::Buffer(pass.read(&h.samples, Access::ComputeRead))),
                ("levels", Bound::Buffer(pass.read(&h.levels, Access::ComputeRead))),
                ("params", Bound::Buffer(pass.read(&params_h, Access::ComputeRead))),
                ("nodes", Bound::Buffer(pass.write(&mut h.nodes, Access::ComputeReadWrite))),
            ];
            let count = info.count;
            pass.record(move |cmd| cmd.dispatch(&self.pipeline, &bound, [count, 1, 1]));
        }
        Ok(())
    }
}
