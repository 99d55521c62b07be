//! The frame set: what a frame binds once, in descriptor set 0 of every pipeline: the scene's
//! surfaces (`scene.glsl`), its emitters (`emitters.glsl`) and both backends' trace structures
//! (`trace.glsl`, `bvh.glsl`: every backend's clearance pass searches the BVH). The numbers
//! here are the shaders' (`frame_set.glsl`), which the bindings test checks for every module.
//! Each pass's own bindings are in set 1, numbered from 0.

use leakless_device::{BindingDecl, FrameBinding};
use leakless_graph::Graph;

use crate::gpu_scene::{EmitterBindings, SceneBindings, SceneHandles};
use crate::trace::{ComputeTrace, RayQueryTrace, TraceHandles};

/// The groups the frame set holds, in the order of their numbers.
const GROUPS: [&[BindingDecl]; 4] =
    [SceneBindings::DECLS, EmitterBindings::DECLS, RayQueryTrace::DECLS, ComputeTrace::DECLS];

/// The frame set's bindings: each binding of [`GROUPS`] once (both backends' trace groups hold
/// `trace_scale`), numbered from 0 in order.
pub static FRAME_SET: &[FrameBinding] = &numbered::<14>(GROUPS);

/// The distinct bindings of `groups`, numbered in order of first appearance; fails to compile
/// unless there are `N`.
const fn numbered<const N: usize>(groups: [&[BindingDecl]; 4]) -> [FrameBinding; N] {
    let unset = BindingDecl::storage_words("", leakless_device::BindingAccess::Read);
    let mut out = [FrameBinding { binding: 0, decl: unset }; N];
    let mut count = 0;
    let mut g = 0;
    while g < groups.len() {
        let mut i = 0;
        while i < groups[g].len() {
            let decl = groups[g][i];
            let mut seen = false;
            let mut j = 0;
            while j < count {
                seen |= same_name(out[j].decl.name, decl.name);
                j += 1;
            }
            if !seen {
                assert!(count < N, "the frame set holds more bindings than declared");
                out[count] = FrameBinding { binding: count as u32, decl };
                count += 1;
            }
            i += 1;
        }
        g += 1;
    }
    assert!(count == N, "the frame set holds fewer bindings than declared");
    out
}

const fn same_name(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

/// Binds the frame's scene and trace structures as the graph's frame set.
pub fn bind<'r>(graph: &mut Graph<'r>, scene: &SceneHandles, trace: &TraceHandles) {
    graph.bind_frame_set(FRAME_SET, |set| {
        let stage = leakless_graph::Stage::Compute;
        (scene.declare(set, stage), scene.declare_emitters(set, stage), trace.declare_frame_set(set))
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each group's every binding is in the frame set once, with the group's declaration.
    #[test]
    fn the_frame_set_holds_each_shared_group_once() {
        for decl in GROUPS.iter().flat_map(|g| g.iter()) {
            let found: Vec<_> = FRAME_SET.iter().filter(|b| b.decl.name == decl.name).collect();
            assert_eq!(found.len(), 1, "{}", decl.name);
            assert_eq!(format!("{:?}", found[0].decl), format!("{decl:?}"));
        }
        let numbers: Vec<u32> = FRAME_SET.iter().map(|b| b.binding).collect();
        assert_eq!(numbers, (0..FRAME_SET.len() as u32).collect::<Vec<_>>());
        let names: Vec<&str> = FRAME_SET.iter().map(|b| b.decl.name).collect();
        assert_eq!(names[6..10], ["scene_addresses", "emitters", "tlas", "trace_scale"]);
    }
}
