//! Every pass's declared bindings and push constants agree with its shaders' reflection, on
//! both trace backends (no GPU needed: this is the build-time reflection against the Rust
//! declarations that pipeline creation also checks).

use leakless::passes::hierarchy::{build, morton, sample_bounds};
use leakless::passes::{
    accumulate, compose, direct, emission_order, gather, gbuffer, hang, luminance, photon_clearance, photon_dispatch,
    photon_order, photons, raycast, reference, scan, sort, splat, tonemap, view_bindings, visible_disk,
};
use leakless::shaders;
use leakless::Backend;
use leakless_device::shader::ShaderInfo;
use leakless_device::{check_bindings, check_push_constants, BindingDecl, GpuStruct, RustLayout};

/// (pass, shader, bindings, push constants) of every compute pass on `backend`.
fn compute_passes(backend: Backend) -> Vec<(&'static str, &'static ShaderInfo, Vec<BindingDecl>, Option<RustLayout>)> {
    let pick = |rq, compute| backend.pick(rq, compute);
    vec![
        (
            "direct",
            pick(&shaders::DIRECT_COMP_RAYQUERY, &shaders::DIRECT_COMP_COMPUTE),
            view_bindings(backend, direct::DirectBindings::DECLS),
            None,
        ),
        (
            "reference",
            pick(&shaders::REFERENCE_COMP_RAYQUERY, &shaders::REFERENCE_COMP_COMPUTE),
            view_bindings(backend, reference::ReferenceBindings::DECLS),
            Some(reference::ReferenceParams::LAYOUT),
        ),
        (
            "raycast",
            pick(&shaders::RAYCAST_COMP_RAYQUERY, &shaders::RAYCAST_COMP_COMPUTE),
            raycast::bindings(backend),
            Some(raycast::RaycastParams::LAYOUT),
        ),
        (
            "photons",
            pick(&shaders::PHOTONS_COMP_RAYQUERY, &shaders::PHOTONS_COMP_COMPUTE),
            photons::bindings(backend),
            Some(photons::PhotonPush::LAYOUT),
        ),
        (
            "gather",
            pick(&shaders::GATHER_COMP_RAYQUERY, &shaders::GATHER_COMP_COMPUTE),
            gather::bindings(backend),
            Some(gather::GatherParams::LAYOUT),
        ),
        (
            "visible disk",
            pick(&shaders::VISIBLE_DISK_COMP_RAYQUERY, &shaders::VISIBLE_DISK_COMP_COMPUTE),
            visible_disk::bindings(backend),
            Some(visible_disk::VisibleDiskParams::LAYOUT),
        ),
        (
            "photon clearance",
            &shaders::PHOTON_CLEARANCE_COMP,
            [photon_clearance::ClearanceBindings::DECLS, leakless::trace::ComputeTrace::DECLS].concat(),
            Some(photon_clearance::ClearanceParams::LAYOUT),
        ),
        (
            "accumulate",
            &shaders::ACCUMULATE_COMP,
            accumulate::AccumulateBindings::DECLS.to_vec(),
            Some(accumulate::AccumulateParams::LAYOUT),
        ),
        (
            "compose",
            &shaders::COMPOSE_COMP,
            compose::ComposeBindings::DECLS.to_vec(),
            Some(compose::ComposeParams::LAYOUT),
        ),
        ("splat", &shaders::SPLAT_COMP, splat::SplatBindings::DECLS.to_vec(), Some(splat::SplatParams::LAYOUT)),
        (
            "hierarchy build",
            &shaders::HIERARCHY_BUILD_COMP,
            build::BuildBindings::DECLS.to_vec(),
            Some(build::BuildParams::LAYOUT),
        ),
        ("morton", &shaders::MORTON_COMP, morton::MortonBindings::DECLS.to_vec(), None),
        ("sample bounds", &shaders::SAMPLE_BOUNDS_COMP, sample_bounds::SampleBoundsBindings::DECLS.to_vec(), None),
        (
            "sort histogram",
            &shaders::SORT_HISTOGRAM_COMP,
            sort::HistogramBindings::DECLS.to_vec(),
            Some(sort::SortParams::LAYOUT),
        ),
        ("sort scan", &shaders::SORT_SCAN_COMP, scan::ScanBindings::DECLS.to_vec(), Some(sort::SortParams::LAYOUT)),
        (
            "photon dispatch",
            &shaders::PHOTON_DISPATCH_COMP,
            photon_dispatch::PhotonDispatchBindings::DECLS.to_vec(),
            Some(photon_dispatch::PhotonDispatchParams::LAYOUT),
        ),
        (
            "photon cells",
            &shaders::PHOTON_CELLS_COMP,
            photon_order::CellBindings::DECLS.to_vec(),
            Some(photon_order::PhotonOrderParams::LAYOUT),
        ),
        (
            "photon order",
            &shaders::PHOTON_ORDER_COMP,
            photon_order::OrderBindings::DECLS.to_vec(),
            Some(photon_order::PhotonOrderParams::LAYOUT),
        ),
        (
            "emission cells",
            &shaders::EMISSION_CELLS_COMP,
            emission_order::EmissionCellBindings::DECLS.to_vec(),
            Some(emission_order::EmissionOrderParams::LAYOUT),
        ),
        (
            "emission order",
            &shaders::EMISSION_ORDER_COMP,
            emission_order::EmissionOrderBindings::DECLS.to_vec(),
            Some(emission_order::EmissionOrderParams::LAYOUT),
        ),
        (
            "sort scatter",
            &shaders::SORT_SCATTER_COMP,
            sort::ScatterBindings::DECLS.to_vec(),
            Some(sort::SortParams::LAYOUT),
        ),
        ("sort copy", &shaders::SORT_COPY_COMP, sort::CopyBindings::DECLS.to_vec(), Some(sort::SortParams::LAYOUT)),
        (
            "luminance tiles",
            &shaders::LUMINANCE_COMP,
            luminance::TileBindings::DECLS.to_vec(),
            Some(luminance::LuminanceParams::LAYOUT),
        ),
        (
            "luminance total",
            &shaders::LUMINANCE_TOTAL_COMP,
            luminance::TotalBindings::DECLS.to_vec(),
            Some(luminance::TotalParams::LAYOUT),
        ),
        ("hang", &shaders::HANG_COMP, hang::HangBindings::DECLS.to_vec(), None),
    ]
}

#[test]
fn every_compute_pass_matches_its_shader_on_both_backends() {
    for backend in [Backend::Compute, Backend::RayQuery] {
        for (pass, shader, decls, push) in compute_passes(backend) {
            check_bindings(shader, pass, &decls).unwrap_or_else(|e| panic!("{backend:?}: {e}"));
            check_push_constants(shader, pass, push.as_ref()).unwrap_or_else(|e| panic!("{backend:?}: {e}"));
        }
    }
}

#[test]
fn raster_passes_match_each_stage() {
    // A graphics pass's bindings are split over two stages: each stage's subset must match.
    let passes: [(&str, [&ShaderInfo; 2], Vec<BindingDecl>); 2] = [
        (
            "gbuffer",
            [&shaders::GBUFFER_VERT, &shaders::GBUFFER_FRAG],
            [gbuffer::GBufferBindings::DECLS, leakless::gpu_scene::SceneBindings::DECLS].concat(),
        ),
        ("tonemap", [&shaders::TONEMAP_VERT, &shaders::TONEMAP_FRAG], tonemap::TonemapBindings::DECLS.to_vec()),
    ];
    for (pass, stages, decls) in passes {
        for shader in stages {
            let reflected = shader.reflection.expect("naga parses raster modules");
            let used: Vec<_> = decls.iter().copied().filter(|d| reflected.iter().any(|r| r.name == d.name)).collect();
            check_bindings(shader, pass, &used).unwrap();
        }
    }
    check_push_constants(&shaders::TONEMAP_FRAG, "tonemap", Some(&tonemap::TonemapParams::LAYOUT)).unwrap();
}

#[test]
fn a_wrong_declaration_names_shader_binding_and_pass() {
    let mut decls = view_bindings(Backend::Compute, direct::DirectBindings::DECLS);
    decls.retain(|d| d.name != "lights");
    let err = check_bindings(&shaders::DIRECT_COMP_COMPUTE, "direct", &decls).unwrap_err().to_string();
    assert!(err.contains("direct.comp:compute") && err.contains("lights") && err.contains("pass direct"), "{err}");
    // A push-constant struct with a member moved fails too, naming the member.
    let err = check_push_constants(&shaders::GATHER_COMP_COMPUTE, "gather", Some(&splat::SplatParams::LAYOUT))
        .unwrap_err()
        .to_string();
    assert!(err.contains("push constants") && err.contains("gather"), "{err}");
}

#[test]
fn every_module_is_spirv_and_reflected() {
    // Ray-query modules too: naga cannot parse them, so build.rs scans them and takes their
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
