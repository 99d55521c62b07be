//! The device tuning changes speed, never the image: every choice it makes (paths per thread,
//! the ray queue's length, the gather's workgroup size, counters combined per subgroup, the
//! subgroup's shared walk of the lists, the splat's lanes a photon, the two orders) renders the CPU preset's image bit for bit, on both backends. The GPU preset runs
//! here as it would on a GPU, subgroup operations included.

use leakless::{BackendChoice, DeviceTuning, Method, RenderSettings, Renderer, SplatSettings, TuningChoice};

use crate::common;

fn frame(path: &str, settings: &RenderSettings, tuning: DeviceTuning) -> Option<leakless::RenderedFrame> {
    let gpu = common::gpu_with(settings.backend.wants_ray_queries())?;
    let mut renderer = Renderer::with_tuning(gpu, &common::scene(path), settings.clone(), tuning).expect("renderer");
    let frame = renderer.render().expect("render");
    renderer.gpu().check_validation().expect("validation clean");
    Some(frame)
}

/// The gather's count of its rays' traversal work (`count_work`) is there only where the tuning
/// asks for it on the compute backend: none of a frame without it (`base`), and in `other`
/// none of nodes where no ray is traced (`splat`) and some where rays are (the doorway's
/// `leakless`, whose frame culls leaks: each blocked ray a walk found tested a triangle).
fn assert_traversal_counted(
    base: &leakless::RenderedFrame,
    other: &leakless::RenderedFrame,
    counted: bool,
    what: &str,
) {
    let (b, o) = (base.splat.as_ref().unwrap(), other.splat.as_ref().unwrap());
    assert_eq!((b.ray_nodes_visited, b.ray_triangles_tested), (None, None), "{what}: counted without count_work");
    if !counted {
        assert_eq!((o.ray_nodes_visited, o.ray_triangles_tested), (None, None), "{what}");
        return;
    }
    let (nodes, triangles) = (o.ray_nodes_visited.expect("counted"), o.ray_triangles_tested.expect("counted"));
    if o.visibility_rays == 0 {
        assert_eq!((nodes, triangles), (0, 0), "{what}: work without rays");
    } else {
        assert!(o.leaks_culled > 0, "{what}: the doorway culls leaks");
        assert!(
            nodes > 0 && triangles > 0,
            "{what}: {nodes} nodes, {triangles} triangles for {} rays",
            o.visibility_rays
        );
    }
}

/// Every layer and count equal.
fn assert_same(a: &leakless::RenderedFrame, b: &leakless::RenderedFrame, what: &str) {
    assert!(a.radiance == b.radiance && a.indirect == b.indirect && a.leaked == b.leaked, "{what}: images differ");
    let (sa, sb) = (a.splat.as_ref().unwrap(), b.splat.as_ref().unwrap());
    let counts = |s: &leakless::splatting::SplatStats| {
        (s.photons_stored, s.photon_rays, s.list_entries, s.nodes_visited, s.photons_listed, s.candidate_tests)
    };
    assert_eq!(counts(sa), counts(sb), "{what}: counters differ");
    assert_eq!((sa.accepted, sa.visibility_rays, sa.proven_clear), (sb.accepted, sb.visibility_rays, sb.proven_clear));
}

#[test]
fn every_tuning_renders_the_cpu_presets_image() {
    let Some(gpu) = common::gpu() else { return };
    let report = gpu.report().clone();
    drop(gpu);
    let cpu = DeviceTuning::choose(&report, TuningChoice::Cpu);
    let gpu_preset = DeviceTuning::choose(&report, TuningChoice::Gpu);
    assert_eq!(gpu_preset.subgroup_counters, report.subgroup_arithmetic);
    let odd = DeviceTuning {
        ray_queue: 1,
        gather_workgroup: 32,
        paths_per_thread: 3,
        subgroup_counters: report.subgroup_arithmetic,
        shared_walk: !cpu.shared_walk,
        count_work: true,
        // Clusters of 4 lanes: several a subgroup where the subgroup is 8 lanes or more.
        splat_lanes: if report.subgroup_arithmetic && report.subgroup_size >= 4 { 4 } else { 1 },
        // Three workgroups: the clustered splat and the list scatter loop over the rest.
        dispatch_groups: 3,
        ..cpu.clone()
    };
    for backend in common::choices() {
        for method in [Method::Splat, Method::LeakLess] {
            let settings = RenderSettings {
                width: 48,
                height: 36,
                backend,
                method,
                splat: SplatSettings { paths: 3000, ..Default::default() },
                ..Default::default()
            };
            let base = frame("scenes/doorway.gltf", &settings, cpu.clone()).unwrap();
            assert!(base.splat.as_ref().unwrap().photons_stored > 0);
            // The GPU preset tests wide leaves' samples, which lists fewer photons (the same
            // image: `splat.rs`'s `no_sample_tests_a_share_of_all_photons`); here it lists
            // what the CPU preset lists.
            let gpu_lists = DeviceTuning { leaf_samples: cpu.leaf_samples, ..gpu_preset.clone() };
            for (name, tuning) in [("gpu preset", gpu_lists), ("odd sizes", odd.clone())] {
                let other = frame("scenes/doorway.gltf", &settings, tuning.clone()).unwrap();
                let what = format!("{name}, {} on {}", method.name(), backend.name());
                assert_same(&base, &other, &what);
                assert_traversal_counted(&base, &other, tuning.count_work && backend == BackendChoice::Compute, &what);
            }
            // Clusters narrower than the subgroup (a GPU's 32 lanes walk four leaves of 8 so;
            // here halves and quarters of a leaf) walk side by side and test what the whole
            // subgroup's walk does.
            for cluster in [2, 4].into_iter().filter(|&c| report.subgroup_arithmetic && c < report.subgroup_size) {
                let clustered = DeviceTuning { shared_walk: true, walk_cluster: cluster, ..cpu.clone() };
                let other = frame("scenes/doorway.gltf", &settings, clustered).unwrap();
                assert_same(
                    &base,
                    &other,
                    &format!("walk clusters of {cluster}, {} on {}", method.name(), backend.name()),
                );
            }
            // A shared walk over leaves narrower than the subgroup: its rounds walk one leaf after
            // another, or (in clusters of a leaf) every leaf at once, and test what each lane's
            // own walk does.
            if report.subgroup_arithmetic && report.subgroup_size > 2 {
                let narrow = RenderSettings {
                    splat: SplatSettings { branching: Some(2), ..settings.splat.clone() },
                    ..settings.clone()
                };
                let alone =
                    frame("scenes/doorway.gltf", &narrow, DeviceTuning { shared_walk: false, ..cpu.clone() }).unwrap();
                let shared =
                    frame("scenes/doorway.gltf", &narrow, DeviceTuning { shared_walk: true, ..cpu.clone() }).unwrap();
                assert_same(
                    &alone,
                    &shared,
                    &format!("shared walk, branching 2, {} on {}", method.name(), backend.name()),
                );
                let leaves = DeviceTuning { shared_walk: true, walk_cluster: 2, ..cpu.clone() };
                let clustered = frame("scenes/doorway.gltf", &narrow, leaves).unwrap();
                assert_same(
                    &alone,
                    &clustered,
                    &format!("walk clusters of a leaf, branching 2, {} on {}", method.name(), backend.name()),
                );
            }
        }
    }
}

/// The shared walk keeps every lane of a subgroup in the walk, those past the last sample and
/// those that see no surface included, to read its share of each chunk: an image whose pixel
/// count is no multiple of the subgroup (47 × 35 = 1645 samples, 5 in the last group of 8),
/// with pixels outside the Cornell box, renders as each lane's own walk renders it, a one-entry
/// ray queue clamping the chunks too, and so does a walk in clusters of 4 lanes.
#[test]
fn the_shared_walk_renders_an_image_with_a_partial_last_subgroup_as_lanes_alone() {
    let Some(gpu) = common::gpu() else { return };
    let report = gpu.report().clone();
    drop(gpu);
    if !(report.subgroup_arithmetic && report.subgroup_size > 1) {
        return;
    }
    let cpu = DeviceTuning::choose(&report, TuningChoice::Cpu);
    for method in [Method::Splat, Method::LeakLess] {
        let settings = RenderSettings {
            width: 47,
            height: 35,
            method,
            splat: SplatSettings { paths: 3000, ..Default::default() },
            ..Default::default()
        };
        let alone =
            frame("scenes/cornell-box.gltf", &settings, DeviceTuning { shared_walk: false, ..cpu.clone() }).unwrap();
        for (ray_queue, walk_cluster) in [(cpu.ray_queue, 0), (1, 0), (cpu.ray_queue, 4), (1, 4)] {
            if walk_cluster >= report.subgroup_size {
                continue;
            }
            let shared = DeviceTuning { shared_walk: true, ray_queue, walk_cluster, ..cpu.clone() };
            let shared = frame("scenes/cornell-box.gltf", &settings, shared).unwrap();
            let what = format!("{}, ray queue {ray_queue}, walk clusters {walk_cluster}", method.name());
            assert_same(&alone, &shared, &what);
        }
        let stats = alone.splat.as_ref().unwrap();
        assert!(stats.candidate_tests > 0);
        assert!(stats.valid_samples < 47 * 35, "some pixels see no surface (outside the box)");
    }
}

/// Where the walk is shared, the ray queues are pooled in the workgroup's shared memory: the
/// longest queue that fits the device's `maxComputeSharedMemorySize` exactly renders the
/// lanes-alone image (every word of the pool in use), and one entry more is refused with the
/// limit's name before any pipeline is made.
#[test]
fn a_pooled_ray_queue_fits_the_devices_shared_memory_or_is_refused() {
    let Some(gpu) = common::gpu() else { return };
    let report = gpu.report().clone();
    drop(gpu);
    if !report.subgroup_arithmetic {
        return;
    }
    let cpu = DeviceTuning::choose(&report, TuningChoice::Cpu);
    let fits = report.limits.max_compute_shared_memory_size / (4 * cpu.gather_workgroup);
    if fits >= 1024 {
        return; // every queue the tuning takes fits
    }
    let settings = RenderSettings {
        width: 48,
        height: 36,
        method: Method::LeakLess,
        splat: SplatSettings { paths: 3000, ..Default::default() },
        ..Default::default()
    };
    let alone = frame("scenes/doorway.gltf", &settings, DeviceTuning { shared_walk: false, ..cpu.clone() }).unwrap();
    let full = DeviceTuning { shared_walk: true, ray_queue: fits, ..cpu.clone() };
    assert_eq!(4 * full.ray_pool_words(), report.limits.max_compute_shared_memory_size);
    let pooled = frame("scenes/doorway.gltf", &settings, full).unwrap();
    assert_same(&alone, &pooled, &format!("ray queue {fits}, the whole shared memory"));
    let over = DeviceTuning { shared_walk: true, ray_queue: fits + 1, ..cpu };
    let gpu = common::gpu().unwrap();
    let err = Renderer::with_tuning(gpu, &common::scene("scenes/doorway.gltf"), settings, over)
        .err()
        .expect("a pool beyond shared memory is refused");
    assert!(err.to_string().contains("maxComputeSharedMemorySize"), "{err}");
}

/// `leakless-capped` keeps each list's first photons, which depend on the order lists are
/// appended to: its counters still agree (the GPU preset's wide-leaf test lists fewer photons,
/// and is left out here as in `every_tuning_renders_the_cpu_presets_image`).
#[test]
fn the_capped_methods_counts_do_not_depend_on_the_tuning() {
    let Some(gpu) = common::gpu() else { return };
    let report = gpu.report().clone();
    drop(gpu);
    let settings = RenderSettings {
        width: 48,
        height: 36,
        method: Method::LeakLessCapped,
        splat: SplatSettings { paths: 3000, ..Default::default() },
        ..Default::default()
    };
    let a = frame("scenes/cornell-box.gltf", &settings, DeviceTuning::choose(&report, TuningChoice::Cpu)).unwrap();
    let cpu_lists = DeviceTuning { leaf_samples: false, ..DeviceTuning::choose(&report, TuningChoice::Gpu) };
    let b = frame("scenes/cornell-box.gltf", &settings, cpu_lists).unwrap();
    let (sa, sb) = (a.splat.unwrap(), b.splat.unwrap());
    assert_eq!(
        (sa.photons_stored, sa.list_entries, sa.nodes_visited),
        (sb.photons_stored, sb.list_entries, sb.nodes_visited)
    );
}

/// The specialization constants the tuning sets exist in the modules (the build reads them from
/// the SPIR-V), and the pipelines take the tuning's workgroup size.
#[test]
fn the_tuning_specializes_the_modules_it_names() {
    use leakless::shaders;
    // Both variants also have the traversal's work counters' switch (ray queries count nothing),
    // off unless the tuning counts, and the walk's clusters (0: the whole subgroup).
    // Then the estimator's, which each gather pass sets (gather.rs), and off by default.
    let tuned = [
        ("local_size_x", 0, 64),
        ("SUBGROUP_COUNTERS", 1, 0),
        ("RAY_QUEUE", 2, 64),
        ("SHARED_WALK", 3, 0),
        ("VISIBILITY", 4, 0),
        ("VISIBLE_DISK", 5, 0),
        ("RAY_POOL", 6, 1),
        ("POOL_WAIT", 7, 1),
    ];
    let counting = [("TRACE_COUNT_WORK", 10, 0), ("WALK_CLUSTER", 11, 0)];
    for (module, extra) in
        [(&shaders::GATHER_COMP_COMPUTE, &counting[..]), (&shaders::GATHER_COMP_RAYQUERY, &counting[..])]
    {
        let names: Vec<(&str, u32, u32)> = module.spec_constants.iter().map(|c| (c.name, c.id, c.default)).collect();
        assert_eq!(names, [&tuned[..], extra].concat(), "{}", module.name);
        assert_eq!(module.workgroup_size, [64, 1, 1]);
    }
    let tuning = DeviceTuning { gather_workgroup: 128, ray_queue: 8, ..DeviceTuning::cpu() };
    assert_eq!(tuning.gather().workgroup_size(&shaders::GATHER_COMP_COMPUTE), [128, 1, 1]);
    assert_eq!(tuning.gather().value(&shaders::GATHER_COMP_COMPUTE, "RAY_QUEUE"), Some(8));
    use leakless::passes::gather::{GATHER, GATHER_TRACED, GATHER_VISIBLE_DISK};
    for (pass, estimator) in [(&GATHER, [0, 0]), (&GATHER_TRACED, [1, 0]), (&GATHER_VISIBLE_DISK, [1, 1])] {
        let spec = pass.specialization(&tuning);
        let value = |name| spec.value(&shaders::GATHER_COMP_COMPUTE, name).unwrap();
        assert_eq!([value("VISIBILITY"), value("VISIBLE_DISK")], estimator, "{}", pass.name);
        assert_eq!(value("RAY_QUEUE"), 8, "{}: the tuning's constants too", pass.name);
    }
    for module in [&shaders::SPLAT_COMP, &shaders::PHOTONS_COMP_COMPUTE] {
        assert!(module.spec_constants.iter().any(|c| c.name == "SUBGROUP_COUNTERS"), "{}", module.name);
    }
    // A constant the module lacks is refused with its name, not ignored.
    let Some(gpu) = common::gpu() else { return };
    let spec = leakless_device::Specialization::new().with("NO_SUCH_CONSTANT", 1);
    let pass = &leakless::passes::splat::SPLAT;
    let err = leakless_device::ComputePipeline::new(
        &gpu,
        "test",
        &shaders::SPLAT_COMP,
        leakless::frame_set::FRAME_SET,
        &pass.decls(),
        pass.push.as_ref(),
        &spec,
    )
    .err()
    .expect("an unknown constant is an error");
    assert!(err.to_string().contains("NO_SUCH_CONSTANT"), "{err}");
}

/// With GPU timestamps in one submission a frame reports its span on the device: from the
/// first pass's start to the last one's end, so at least any one pass's time.
#[test]
fn a_timestamped_frame_reports_its_gpu_span() {
    let Some(gpu) = common::gpu() else { return };
    let settings = RenderSettings { width: 32, height: 24, ..Default::default() };
    let mut renderer = Renderer::new(gpu, &common::scene("scenes/cornell-box.gltf"), settings).unwrap();
    renderer.set_timing(leakless_graph::Timing::Timestamps);
    let frame = renderer.render().unwrap();
    let longest = frame.timings.iter().map(|t| t.ms).fold(0.0, f64::max);
    assert!(frame.gpu_span_ms.is_finite() && frame.gpu_span_ms >= longest, "{} < {longest}", frame.gpu_span_ms);
    assert!(frame.gpu_span_ms > 0.0);
}
