//! Hierarchy build: one dispatch per level, bottom up, each node from its samples or children
//! (`hierarchy_build.comp`), with the range of its samples' gather radii.

use bytemuck::{Pod, Zeroable};
use leakless_device::{gpu_struct, ComputePipeline, Gpu, GpuStruct};
use leakless_graph::{shader_bindings, Access, Graph, ImageHandle};

use super::{HierarchyHandles, Level, Node, Shape};
use crate::error::Result;
use crate::passes::gbuffer::GBufferHandles;
use crate::shaders;

gpu_struct! {
    /// The `BuildParams` push constants of hierarchy_build.comp.
    #[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
    pub struct BuildParams {
        pub level: u32,
        pub branching: u32,
        pub sample_count: u32,
        pub image_width: u32,
    }
}

shader_bindings! {
    pub struct BuildBindings {
        gbuffer_position: image,
        gbuffer_normal: image,
        sorted_keys: words,
        sorted_samples: words,
        levels: array(Level::LAYOUT),
        nodes: array(Node::LAYOUT),
        disk_mass: image,
    }
}

pub struct BuildPass {
    pipeline: ComputePipeline,
}

impl BuildPass {
    pub fn new(gpu: &Gpu) -> Result<Self> {
        let shader = &shaders::HIERARCHY_BUILD_COMP;
        let pipeline =
            ComputePipeline::new(gpu, "hierarchy build", shader, BuildBindings::DECLS, Some(&BuildParams::LAYOUT))?;
        Ok(BuildPass { pipeline })
    }

    pub fn add<'r>(
        &'r self,
        graph: &mut Graph<'r>,
        shape: &Shape,
        gbuffer: &GBufferHandles,
        disk_mass: &ImageHandle,
        h: &mut HierarchyHandles,
    ) {
        let image_width = gbuffer.position.extent().width;
        for (index, info) in shape.levels.iter().enumerate() {
            let params = BuildParams {
                level: index as u32,
                branching: shape.branching,
                sample_count: shape.sample_count,
                image_width,
            };
            let mut pass = graph.pass(&format!("hierarchy level {index}"));
            let own = BuildBindings {
                gbuffer_position: pass.read(&gbuffer.position, Access::ComputeRead),
                gbuffer_normal: pass.read(&gbuffer.normal, Access::ComputeRead),
                sorted_keys: pass.read(&h.keys, Access::ComputeRead),
                sorted_samples: pass.read(&h.samples, Access::ComputeRead),
                levels: pass.read(&h.levels, Access::ComputeRead),
                nodes: pass.write(&mut h.nodes, Access::ComputeReadWrite),
                disk_mass: pass.read(disk_mass, Access::ComputeRead),
            };
            let count = info.count;
            pass.record(move |ctx| ctx.dispatch(&self.pipeline, &[&own], &params, [count, 1, 1]));
        }
    }
}
