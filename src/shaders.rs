//! Every shader module of `shaders-glsl/`, compiled to SPIR-V at build time.
//!
//! `build.rs` compiles each `.vert` / `.frag` / `.comp` with glslang (GLSL 460, Vulkan 1.3,
//! SPIR-V 1.3 so that naga can reflect it; 1.6 for ray-query variants). A module that includes
//! `trace.glsl` is compiled twice, as `<file>:rayquery` (`TRACE_RAYQUERY` defined) and
//! `<file>:compute` (`TRACE_COMPUTE`), with statics suffixed `_RAYQUERY` / `_COMPUTE`. Each
//! module is reflected with naga, and one [`ShaderInfo`] static is generated per module
//! (`GBUFFER_VERT`, `DIRECT_COMP`, `GATHER_COMP_RAYQUERY`, ...), plus [`ALL`].
//!
//! naga cannot parse ray-query modules, nor modules that sample through a combined image
//! sampler (`sampler2D`; use `texture2D` + `sampler`): their `reflection` is `Err` with naga's
//! message, and the build prints a warning for the latter.

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
        let s = &DIRECT_COMP;
        assert_eq!((s.name, s.stage), ("direct.comp", ShaderStage::Compute));
        assert_eq!(s.workgroup_size, [8, 8, 1]);
        assert_eq!(s.spirv[0], 0x0723_0203, "SPIR-V magic number");
        let b = s.reflection.expect("naga parses direct.comp");
        assert_eq!(b.len(), 6);

        use BindingKind::*;
        assert_eq!(id(&b[0]), ("frame", 0, 0, UniformBuffer));
        let frame = b[0].layout.unwrap();
        let members = [
            m("view_proj", 0),
            m("camera_position", 64),
            m("width", 80),
            m("height", 84),
            m("light_count", 88),
            m("pad0", 92),
        ];
        assert_eq!(frame.members, &members);
        assert_eq!(frame.size, 96);
        assert_eq!((frame.array_stride, frame.element_members), (None, &[][..]));

        assert_eq!(id(&b[1]), ("lights", 0, 1, StorageBuffer));
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

        for (i, name) in [
            (2, "gbuffer_position"),
            (3, "gbuffer_normal"),
            (4, "gbuffer_albedo"),
            (5, "direct"),
        ] {
            assert_eq!(id(&b[i]), (name, 0, i as u32, StorageImage));
            assert_eq!(b[i].layout, None);
        }
    }

    #[test]
    fn all_lists_every_module_once() {
        assert!(ALL.iter().any(|s| std::ptr::eq(*s, &DIRECT_COMP)));
        let mut names: Vec<_> = ALL.iter().map(|s| s.name).collect();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), ALL.len());
        assert!(ALL
            .iter()
            .all(|s| s.spirv.len() > 5 && s.spirv[0] == 0x0723_0203));
    }
}
