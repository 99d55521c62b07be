//! Every pass's declared bindings and push constants agree with its shaders' reflection, on
//! both trace backends (no GPU needed: this is the build-time reflection against the Rust
//! declarations that pipeline creation also checks).

use leakless::frame_set::FRAME_SET;
use leakless::passes::{direct, gather, gbuffer, splat, tonemap, FRAME_PASSES, TOOL_PASSES};
use leakless::shaders;
use leakless::Backend;
use leakless_device::shader::ShaderInfo;
use leakless_device::{check_bindings, check_push_constants, BindingDecl, GpuStruct};

#[test]
fn every_compute_pass_matches_its_shader_on_both_backends() {
    let mut errors = Vec::new();
    for backend in [Backend::Compute, Backend::RayQuery] {
        for pass in FRAME_PASSES.iter().chain(TOOL_PASSES.iter()) {
            let (shader, name) = (pass.shader(backend), pass.name.label);
            if let Err(e) = check_bindings(shader, name, FRAME_SET, &pass.decls()) {
                errors.push(format!("{backend:?}: {e}"));
            }
            if let Err(e) = check_push_constants(shader, name, pass.push.as_ref()) {
                errors.push(format!("{backend:?}: {e}"));
            }
            if let Some(want) = pass.workgroup {
                if shader.workgroup_size != want {
                    errors.push(format!(
                        "{}: workgroup {:?}, the pass wants {want:?}",
                        shader.name, shader.workgroup_size
                    ));
                }
            }
        }
    }
    assert!(errors.is_empty(), "{}", errors.join("\n"));
}

#[test]
fn raster_passes_match_each_stage() {
    // A graphics pass's bindings are split over two stages: each stage's subset must match.
    let passes: [(&str, [&ShaderInfo; 2], Vec<BindingDecl>); 2] = [
        ("gbuffer", [&shaders::GBUFFER_VERT, &shaders::GBUFFER_FRAG], gbuffer::RasterBindings::DECLS.to_vec()),
        ("tonemap", [&shaders::TONEMAP_VERT, &shaders::TONEMAP_FRAG], tonemap::TonemapBindings::DECLS.to_vec()),
    ];
    for (pass, stages, decls) in passes {
        for shader in stages {
            let reflected = shader.reflection.expect("naga parses raster modules");
            let used: Vec<_> = decls.iter().copied().filter(|d| reflected.iter().any(|r| r.name == d.name)).collect();
            check_bindings(shader, pass, FRAME_SET, &used).unwrap();
        }
    }
    check_push_constants(&shaders::TONEMAP_FRAG, "tonemap", Some(&tonemap::TonemapParams::LAYOUT)).unwrap();
}

#[test]
fn a_wrong_declaration_names_shader_binding_and_pass() {
    let mut decls = direct::DIRECT.decls();
    decls.retain(|d| d.name != "lights");
    let err = check_bindings(&shaders::DIRECT_COMP_COMPUTE, "direct", FRAME_SET, &decls).unwrap_err().to_string();
    assert!(err.contains("direct.comp:compute") && err.contains("lights") && err.contains("pass direct"), "{err}");
    // A push-constant struct with a member moved fails too, naming the member.
    let err = check_push_constants(gather::GATHER.shader(Backend::Compute), "gather", splat::SPLAT.push.as_ref())
        .unwrap_err()
        .to_string();
    assert!(err.contains("push constants") && err.contains("gather"), "{err}");
}

#[test]
fn every_module_is_spirv_and_reflected() {
    // Ray-query modules too: naga cannot parse them, so crates/renderer/build.rs scans them and takes their
    // buffer layouts (and push constants) from the compute twin; none may be left unchecked.
    for s in shaders::ALL {
        assert_eq!(s.spirv.first(), Some(&0x0723_0203), "{} is not SPIR-V", s.name);
        let reflected = s.reflection.unwrap_or_else(|why| panic!("{} has no reflection: {why}", s.name));
        // Only the full-screen triangle's vertex stage binds nothing.
        assert!(!reflected.is_empty() || s.name == "tonemap.vert", "{} binds nothing", s.name);
        if s.name.ends_with(":rayquery") {
            let twin = shaders::ALL.iter().find(|t| t.name == s.name.replace(":rayquery", ":compute")).expect("twin");
            assert_eq!(s.push_constants, twin.push_constants, "{}", s.name);
        }
    }
}

/// Every module that the renderer compiles is some registered pass's (or a raster pass's), so
/// a new compute shader cannot skip the check above by not being listed.
#[test]
fn every_compute_module_belongs_to_a_registered_pass() {
    let registered: Vec<&str> = [Backend::Compute, Backend::RayQuery]
        .into_iter()
        .flat_map(|b| FRAME_PASSES.iter().chain(TOOL_PASSES.iter()).map(move |p| p.shader(b).name))
        .collect();
    for s in shaders::ALL.iter().filter(|s| s.stage == leakless_device::shader::ShaderStage::Compute) {
        assert!(registered.contains(&s.name), "{} is no registered pass's shader (passes::FRAME_PASSES)", s.name);
    }
    let mut labels: Vec<&str> = FRAME_PASSES.iter().chain(TOOL_PASSES.iter()).map(|p| p.name.label).collect();
    labels.sort();
    let count = labels.len();
    labels.dedup();
    assert_eq!(labels.len(), count, "two passes share a name");
}

/// What a frame binds once is in set 0 at the frame set's numbers; each module's own bindings
/// are in set 1, numbered from 0 without gaps.
#[test]
fn each_module_numbers_its_own_bindings_from_zero_after_the_frame_set() {
    for s in shaders::ALL {
        let reflected = s.reflection.expect("checked by every_module_is_spirv_and_reflected");
        let mut own: Vec<u32> =
            reflected.iter().filter(|r| r.set == leakless_device::PASS_SET).map(|r| r.binding).collect();
        own.sort();
        assert_eq!(own, (0..own.len() as u32).collect::<Vec<_>>(), "{}: the pass's bindings in set 1", s.name);
        for r in reflected.iter().filter(|r| r.set == leakless_device::FRAME_SET) {
            let frame = FRAME_SET.iter().find(|f| f.decl.name == r.name);
            assert_eq!(frame.map(|f| f.binding), Some(r.binding), "{}: {} in set 0", s.name, r.name);
        }
    }
}
