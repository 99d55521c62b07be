//! Every pass's declared bindings agree with its shaders' reflection, on both trace backends
//! (no GPU needed: this is the build-time reflection against the Rust declarations).

use leakless::passes::{compose, direct, gather, gbuffer, photons, raycast, reference, splat, view_bindings};
use leakless::shaders;
use leakless::Backend;
use leakless_device::check_bindings;

#[test]
fn every_tracing_pass_matches_both_variants() {
    for backend in [Backend::Compute, Backend::RayQuery] {
        let passes = [
            (
                "direct",
                backend.pick(&shaders::DIRECT_COMP_RAYQUERY, &shaders::DIRECT_COMP_COMPUTE),
                view_bindings(backend, direct::BINDINGS),
            ),
            (
                "reference",
                backend.pick(&shaders::REFERENCE_COMP_RAYQUERY, &shaders::REFERENCE_COMP_COMPUTE),
                view_bindings(backend, reference::BINDINGS),
            ),
            (
                "raycast",
                backend.pick(&shaders::RAYCAST_COMP_RAYQUERY, &shaders::RAYCAST_COMP_COMPUTE),
                raycast::bindings(backend),
            ),
            (
                "photons",
                backend.pick(&shaders::PHOTONS_COMP_RAYQUERY, &shaders::PHOTONS_COMP_COMPUTE),
                photons::bindings(backend),
            ),
            (
                "gather",
                backend.pick(&shaders::GATHER_COMP_RAYQUERY, &shaders::GATHER_COMP_COMPUTE),
                gather::bindings(backend),
            ),
        ];
        for (pass, shader, decls) in passes {
            check_bindings(shader, pass, &decls).unwrap_or_else(|e| panic!("{backend:?}: {e}"));
        }
    }
    check_bindings(&shaders::COMPOSE_COMP, "compose", compose::BINDINGS).unwrap();
}

#[test]
fn every_splatting_pass_matches_its_shader() {
    use leakless::passes::hierarchy;
    let passes: [(&str, &leakless_device::shader::ShaderInfo, &[leakless_device::BindingDecl]); 3] = [
        ("splat", &shaders::SPLAT_COMP, splat::BINDINGS),
        ("hierarchy build", &shaders::HIERARCHY_BUILD_COMP, hierarchy::BUILD_BINDINGS),
        ("morton", &shaders::MORTON_COMP, hierarchy::MORTON_BINDINGS),
    ];
    for (pass, shader, decls) in passes {
        check_bindings(shader, pass, decls).unwrap();
    }
}

#[test]
fn gbuffer_matches_each_stage() {
    // The G-buffer's bindings are split over two stages: each stage's subset must match.
    for shader in [&shaders::GBUFFER_VERT, &shaders::GBUFFER_FRAG] {
        let reflected = shader.reflection.expect("naga parses raster modules");
        let used: Vec<_> =
            gbuffer::bindings().into_iter().filter(|d| reflected.iter().any(|r| r.name == d.name)).collect();
        check_bindings(shader, "gbuffer", &used).unwrap();
    }
}

#[test]
fn a_wrong_declaration_names_shader_binding_and_pass() {
    let mut decls = view_bindings(Backend::Compute, direct::BINDINGS);
    decls.retain(|d| d.name != "lights");
    let err = check_bindings(&shaders::DIRECT_COMP_COMPUTE, "direct", &decls).unwrap_err().to_string();
    assert!(err.contains("direct.comp:compute") && err.contains("lights") && err.contains("pass direct"), "{err}");
}

#[test]
fn every_module_is_spirv_and_reflected() {
    // Ray-query modules too: naga cannot parse them, so build.rs scans them and takes their
    // buffer layouts from the compute twin; none may be left unchecked.
    for s in shaders::ALL {
        assert_eq!(s.spirv.first(), Some(&0x0723_0203), "{} is not SPIR-V", s.name);
        let reflected = s.reflection.unwrap_or_else(|why| panic!("{} has no reflection: {why}", s.name));
        assert!(!reflected.is_empty(), "{} binds nothing", s.name);
    }
}
