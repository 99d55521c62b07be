//! Every shader module of `shaders-glsl/`, compiled to SPIR-V at build time.
//!
//! `crates/renderer/build.rs` compiles each `.vert` / `.frag` / `.comp` with glslang (GLSL 460, Vulkan 1.3,
//! SPIR-V 1.3 so that naga can reflect it; 1.6 for ray-query variants). A module that includes
//! `trace.glsl` is compiled twice, as `<file>:rayquery` (`TRACE_RAYQUERY` defined) and
//! `<file>:compute` (`TRACE_COMPUTE`), with statics suffixed `_RAYQUERY` / `_COMPUTE`. Each
//! module is reflected with naga, and one [`ShaderInfo`] static is generated per module
//! (`GBUFFER_VERT`, `COMPOSE_COMP`, `DIRECT_COMP_RAYQUERY`, ...), plus [`ALL`].
//!
//! naga cannot parse ray-query modules: a small SPIR-V scan (`crates/renderer/build/spirv_scan.rs`) finds
//! their names, sets, bindings and kinds, and buffer layouts come from the `:compute` twin
//! (the build fails if the twins disagree on a binding they share). The scan also checks
//! naga's result on every module naga does parse.

include!(concat!(env!("OUT_DIR"), "/shaders.rs"));

#[cfg(test)]
mod tests {
    use super::*;

    fn m(name: &'static str, offset: u32) -> Member {
        Member { name, offset }
    }

    fn id(b: &ReflectedBinding) -> (&str, u32, u32, BindingKind) {
        (b.name, b.set, b.binding, b.kind)
    }

    /// Reflection of a real module: the direct-light pass.
    #[test]
    fn reflection_of_direct_comp() {
        let s = &DIRECT_COMP_COMPUTE;
        assert_eq!((s.name, s.stage), ("direct.comp:compute", ShaderStage::Compute));
        assert_eq!(s.workgroup_size, [8, 8, 1]);
        assert_eq!(s.spirv[0], 0x0723_0203, "SPIR-V magic number");
        let b = s.reflection.expect("naga parses direct.comp:compute");
        // The frame set's (set 0): the scene's six and their addresses, the emitters, the trace
        // backend's five (bottom-level nodes and triangles, the top level, the scale, the
        // instances); then its own six (set 1).
        assert_eq!(b.len(), 19);
        let frame_set: Vec<_> = crate::frame_set::FRAME_SET.iter().filter(|f| f.decl.name != "tlas").collect();
        let names: Vec<_> = b[..13].iter().map(|r| (r.name, r.set, r.binding)).collect();
        assert_eq!(names, frame_set.iter().map(|f| (f.decl.name, 0, f.binding)).collect::<Vec<_>>());
        let b = &b[13..];

        use BindingKind::*;
        assert_eq!(id(&b[0]), ("frame", 1, 0, UniformBuffer));
        let frame = b[0].layout.unwrap();
        let members = [
            m("view_proj", 0),
            m("camera_position", 64),
            m("width", 80),
            m("height", 84),
            m("light_count", 88),
            m("emitter_count", 92),
        ];
        assert_eq!(frame.members, &members);
        assert_eq!(frame.size, 96);
        assert_eq!((frame.array_stride, frame.element_members), (None, &[][..]));

        assert_eq!(id(&b[1]), ("lights", 1, 1, StorageBuffer));
        let lights = b[1].layout.unwrap();
        assert_eq!(lights.size, 0, "offset of the runtime array");
        assert_eq!(lights.array_stride, Some(48));
        let element = [
            m("position", 0),
            m("kind", 12),
            m("direction", 16),
            m("cos_outer", 28),
            m("intensity", 32),
            m("cos_inner", 44),
        ];
        assert_eq!(lights.element_members, &element);

        for (i, name) in [(2, "gbuffer_position"), (3, "gbuffer_normal"), (4, "gbuffer_albedo"), (5, "direct")] {
            assert_eq!(id(&b[i]), (name, 1, i as u32, StorageImage));
            assert_eq!(b[i].layout, None);
        }
    }

    #[test]
    fn all_lists_every_module_once() {
        assert!(ALL.iter().any(|s| std::ptr::eq(*s, &DIRECT_COMP_RAYQUERY)));
        let mut names: Vec<_> = ALL.iter().map(|s| s.name).collect();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), ALL.len());
        assert!(ALL.iter().all(|s| s.spirv.len() > 5 && s.spirv[0] == 0x0723_0203));
    }

    /// A ray-query variant, which naga cannot parse, is reflected by crates/renderer/build.rs's SPIR-V scan:
    /// it has `tlas` where its compute twin has the BVH buffers (both levels), and every binding the two
    /// share (buffer layouts included, taken from the twin) is the twin's.
    #[test]
    fn rayquery_variants_are_reflected_like_their_compute_twins() {
        use BindingKind::*;
        let only_in = |a: &[ReflectedBinding], b: &[ReflectedBinding]| -> Vec<&str> {
            a.iter().filter(|x| !b.iter().any(|y| y.name == x.name)).map(|x| x.name).collect()
        };
        let mut twins = 0;
        for rq in ALL.iter().filter(|s| s.name.ends_with(":rayquery")) {
            let twin_name = rq.name.replace(":rayquery", ":compute");
            let cs = ALL.iter().find(|s| s.name == twin_name).expect("every ray-query variant has a compute twin");
            let (r, c) = (rq.reflection.expect(rq.name), cs.reflection.expect(cs.name));
            assert_eq!(only_in(r, c), ["tlas"], "{}", rq.name);
            assert_eq!(only_in(c, r), ["bvh_nodes", "bvh_triangles", "bvh_top", "bvh_instances"], "{}", cs.name);
            let tlas = r.iter().find(|b| b.name == "tlas").unwrap();
            let number = crate::frame_set::FRAME_SET.iter().find(|f| f.decl.name == "tlas").unwrap().binding;
            assert_eq!((id(tlas), tlas.layout), (("tlas", 0, number, AccelerationStructure), None), "{}", rq.name);
            for b in r.iter().filter(|b| b.name != "tlas") {
                assert_eq!(Some(b), c.iter().find(|t| t.name == b.name), "{}: {}", rq.name, b.name);
            }
            assert!(r.windows(2).all(|w| (w[0].set, w[0].binding) < (w[1].set, w[1].binding)), "{}", rq.name);
            assert_eq!(rq.workgroup_size, cs.workgroup_size, "{}", rq.name);
            twins += 1;
        }
        assert!(twins > 0, "no ray-query variants");

        // direct.comp traces: its frame block and lights buffer keep their checked layouts.
        let b = DIRECT_COMP_RAYQUERY.reflection.unwrap();
        let own: Vec<_> = b.iter().filter(|r| r.set == 1).collect();
        assert_eq!(id(own[0]), ("frame", 1, 0, UniformBuffer));
        assert_eq!(own[0].layout.map(|l| l.size), Some(96));
        assert_eq!(id(own[1]), ("lights", 1, 1, StorageBuffer));
        assert_eq!(own[1].layout.and_then(|l| l.array_stride), Some(48));
    }
}
