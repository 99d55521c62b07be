//! Hierarchy build: one dispatch per level, bottom up, each node from its samples or children
//! (`hierarchy_build.comp`), with the range of its samples' gather radii.

use bytemuck::{Pod, Zeroable};
use leakless_device::{gpu_struct, GpuStruct};
use leakless_graph::{shader_bindings, Graph, ImageHandle, PassName};

use super::{HierarchyHandles, Level, Node, SamplePosition, Shape};
use crate::passes::gbuffer::{GBufferBindings, GBufferHandles};
use crate::passes::names::group;
use crate::pipelines::{compute_pass, ComputePass, Threads};
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
        sorted_keys: read words,
        sorted_samples: read words,
        levels: read array(Level::LAYOUT),
        nodes: read_write array(Node::LAYOUT),
        disk_mass: read image,
        sample_positions: write array(SamplePosition::LAYOUT),
    }
    pub struct BuildResources;
}

compute_pass! {
    pub static HIERARCHY_LEVEL in FRAME_PASSES: ComputePass<BuildBindings, BuildParams> =
        ComputePass::any(
            PassName::new("hierarchy level", group::HIERARCHY),
            &shaders::HIERARCHY_BUILD_COMP,
            &[GBufferBindings::DECLS],
        )
        .specialize(crate::tuning::DeviceTuning::hierarchy_build);
}

pub fn add<'r>(
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
        let resources = BuildResources {
            sorted_keys: &h.keys,
            sorted_samples: &h.samples,
            levels: &h.levels,
            nodes: &mut h.nodes,
            disk_mass,
            sample_positions: &mut h.positions,
        };
        let (label, threads) = ((HIERARCHY_LEVEL.name, Some(index as u32)), Threads::Fixed([info.count, 1, 1]));
        HIERARCHY_LEVEL.add_as(graph, label, resources, |pass| gbuffer.declare(pass), params, threads);
    }
}
