//! The report's timed sections: frames of each method at each size and path count, rays per
//! second, and the sweeps that choose a GPU's tuning. Every frame is the second of two (the
//! first compiles and warms), timed as the device tuning says (GPU timestamps in one
//! submission on a GPU).

use std::path::Path;

use anyhow::Context;
use serde::Serialize;

use leakless::passes::names::group;
use leakless::{DeviceTuning, Method, Primary, RenderSettings, Renderer, Scene, SplatSettings, TuningChoice};

use super::{Matrix, Report};
use leakless_measure::bench::{self, Measured};

/// One measured frame.
#[derive(Serialize, Clone)]
pub struct FrameRow {
    pub scene: String,
    pub width: u32,
    pub height: u32,
    pub method: String,
    pub paths: u32,
    /// What varies in a sweep ("B = 16", "ray queue 64"); empty in the matrix.
    pub variant: String,
    pub frame_ms: f64,
    /// Summed time per group of passes (photons, hierarchy, splat, …), in frame order.
    pub groups: Vec<(String, f64)>,
    pub passes: Vec<(String, f64)>,
    pub photons_stored: u64,
    pub list_entries: u64,
    pub candidate_tests: u64,
    /// The most candidates one sample tested: a GPU's gather waits for its longest samples.
    pub candidates_most: u64,
    pub visibility_rays: u64,
    pub proven_clear: u64,
}

#[derive(Serialize)]
pub struct RayRow {
    pub scene: String,
    pub backend: String,
    pub set: String,
    pub query: String,
    pub rays: usize,
    pub mrays_per_s: f64,
    /// The compute traversal's mean nodes processed and triangles tested per ray (None on ray
    /// queries): the same on every device for the same tree, so a change of traversal shows.
    pub nodes_per_ray: Option<f64>,
    pub triangles_per_ray: Option<f64>,
}

/// The groups of a frame, in the order its passes first appear.
fn groups(m: &Measured) -> Vec<(String, f64)> {
    let mut out: Vec<(String, f64)> = Vec::new();
    for (_, g, ms) in &m.passes {
        match out.iter_mut().find(|(name, _)| name == g) {
            Some((_, sum)) => *sum += ms,
            None => out.push((g.to_string(), *ms)),
        }
    }
    out
}

fn row(scene: &Scene, m: &Measured, variant: &str) -> FrameRow {
    let s = &m.settings;
    let stats = m.frame.splat.as_ref();
    let count = |f: fn(&leakless::splatting::SplatStats) -> u64| stats.map_or(0, f);
    FrameRow {
        scene: scene.name.clone(),
        width: s.width,
        height: s.height,
        method: s.method.name().to_string(),
        paths: s.splat.paths,
        variant: variant.to_string(),
        frame_ms: m.frame_ms(),
        groups: groups(m),
        passes: m.passes.iter().map(|(n, _, ms)| (n.clone(), *ms)).collect(),
        photons_stored: count(|s| s.photons_stored as u64),
        list_entries: count(|s| s.list_entries as u64),
        candidate_tests: count(|s| s.candidate_tests),
        candidates_most: count(|s| s.candidates_most as u64),
        visibility_rays: count(|s| s.visibility_rays),
        proven_clear: count(|s| s.proven_clear),
    }
}

fn settings((width, height): (u32, u32), method: Method, paths: u32) -> RenderSettings {
    RenderSettings { width, height, method, splat: SplatSettings { paths, ..Default::default() }, ..Default::default() }
}

fn load(root: &Path, path: &str) -> anyhow::Result<Scene> {
    Scene::load(&root.join(path)).with_context(|| format!("loading {path}"))
}

/// Each scene × size × method × paths, one renderer per scene and size.
pub fn frames(report: &mut Report, root: &Path, matrix: &Matrix) -> anyhow::Result<()> {
    for path in &matrix.scenes {
        let scene = load(root, path)?;
        for &size in &matrix.sizes {
            let mut renderer =
                Renderer::new(super::open(matrix.validate)?, &scene, settings(size, Method::Splat, 1000))?;
            for method in [Method::Splat, Method::LeakLessCapped, Method::LeakLess] {
                for &paths in &matrix.paths {
                    renderer.set_settings(settings(size, method, paths))?;
                    let m = Measured::best_of_renderer(&mut renderer, method.name(), 1)?;
                    let r = row(&scene, &m, "");
                    println!("  {} {}x{} {} {}: {:.2} ms", r.scene, r.width, r.height, r.method, paths, r.frame_ms);
                    report.frames.push(r);
                }
            }
        }
    }
    Ok(())
}

pub fn rays(report: &mut Report, root: &Path, matrix: &Matrix) -> anyhow::Result<()> {
    let gpu = super::open(matrix.validate)?;
    for path in &matrix.scenes {
        let scene = load(root, path)?;
        for r in bench::rays(&gpu, &scene, matrix.ray_size, matrix.ray_size, 3)? {
            println!("  {} {} {} {}: {:.1} Mrays/s", scene.name, r.backend.name(), r.set, r.query, r.mrays_per_s());
            report.rays.push(RayRow {
                scene: scene.name.clone(),
                backend: r.backend.name().to_string(),
                set: r.set.to_string(),
                query: r.query.to_string(),
                rays: r.rays,
                mrays_per_s: r.mrays_per_s(),
                nodes_per_ray: r.work_per_ray.map(|w| w.0),
                triangles_per_ray: r.work_per_ray.map(|w| w.1),
            });
        }
    }
    Ok(())
}

/// Branching factors, the view samples by raster and by rays, then each choice of the device's
/// tuning toggled, on the first scene.
pub fn sweeps(report: &mut Report, root: &Path, matrix: &Matrix) -> anyhow::Result<()> {
    let scene = load(root, matrix.scenes[0])?;
    let (size, paths) = matrix.sweep;
    let base = settings(size, Method::LeakLess, paths);
    let mut renderer = Renderer::new(super::open(matrix.validate)?, &scene, base.clone())?;
    for b in [8, 16, 32] {
        let mut s = base.clone();
        s.splat.branching = Some(b);
        renderer.set_settings(s)?;
        let r = row(&scene, &Measured::best_of_renderer(&mut renderer, "leakless", 1)?, &format!("B = {b}"));
        println!("  {}: {:.2} ms", r.variant, r.frame_ms);
        report.branching.push(r);
    }
    // `--primary auto` casts rays on a GPU without ray queries, by this measurement on an H200.
    for primary in [Primary::Raster, Primary::Rays] {
        renderer.set_settings(RenderSettings { primary, ..base.clone() })?;
        let variant = format!("view samples: {}", primary.name());
        let r = row(&scene, &Measured::best_of_renderer(&mut renderer, "leakless", 1)?, &variant);
        println!("  {}: {:.2} ms", r.variant, r.frame_ms);
        report.primary.push(r);
    }
    let device = DeviceTuning::choose(renderer.gpu().report(), TuningChoice::Auto);
    let arithmetic = renderer.gpu().report().subgroup_arithmetic;
    let shared_bytes = renderer.gpu().report().limits.max_compute_shared_memory_size;
    renderer.set_settings(base.clone())?;
    for (variant, tuning) in variants(&device, arithmetic, shared_bytes) {
        renderer.set_tuning(tuning)?;
        let r = row(&scene, &Measured::best_of_renderer(&mut renderer, "leakless", 1)?, &variant);
        println!("  {}: {:.2} ms", r.variant, r.frame_ms);
        report.tuning_sweep.push(r);
    }
    // No choice of the tuning may change what is stored and listed: on a driver where the
    // subgroup counters' lanes did not reconverge, slots would be handed out twice. Testing a
    // wide leaf's samples lists fewer photons (none that a sample gathers): the rays stay.
    let counts = |r: &FrameRow| (r.photons_stored, r.visibility_rays, r.proven_clear);
    let lists = |r: &FrameRow| (r.list_entries, r.candidate_tests);
    let leaf = |r: &FrameRow| r.variant.starts_with(LEAF_SAMPLES_VARIANT);
    if let Some(first) = report.tuning_sweep.first() {
        let differ: Vec<&str> = report
            .tuning_sweep
            .iter()
            .filter(|r| counts(r) != counts(first) || (!leaf(r) && lists(r) != lists(first)))
            .map(|r| r.variant.as_str())
            .collect();
        anyhow::ensure!(differ.is_empty(), "these tuning variants change the counters: {}", differ.join(", "));
    }
    Ok(())
}

/// The sweep's variant that toggles the splat's test of a wide leaf's samples.
const LEAF_SAMPLES_VARIANT: &str = "leaf samples tested";

/// The device's tuning, then each of its choices changed alone. Where the walk is shared, the
/// ray queues are pooled in shared memory (`shared_bytes` of it): the queue sweep stops where
/// they no longer fit, and turning the walk on takes the largest queue that does.
fn variants(device: &DeviceTuning, subgroup_arithmetic: bool, shared_bytes: u32) -> Vec<(String, DeviceTuning)> {
    let with = |f: &dyn Fn(&mut DeviceTuning)| {
        let mut t = device.clone();
        f(&mut t);
        t
    };
    let on = |b: bool| if b { "on" } else { "off" };
    let other_paths = if device.paths_per_thread == 1 { 8 } else { 1 };
    let mut v = vec![
        ("device tuning".to_string(), device.clone()),
        (format!("emission order {}", on(!device.emission_order)), with(&|t| t.emission_order ^= true)),
        (format!("photon order {}", on(!device.photon_order)), with(&|t| t.photon_order ^= true)),
        (format!("{other_paths} paths/thread"), with(&|t| t.paths_per_thread = other_paths)),
        (format!("{LEAF_SAMPLES_VARIANT} {}", on(!device.leaf_samples)), with(&|t| t.leaf_samples ^= true)),
        ("gather workgroup 32".to_string(), with(&|t| t.gather_workgroup = 32)),
        ("gather workgroup 128".to_string(), with(&|t| t.gather_workgroup = 128)),
    ];
    let fits = |t: &DeviceTuning| 4 * t.ray_pool_words() <= shared_bytes;
    for queue in [16, 64, 128, 256, 512, 1024].into_iter().filter(|&q| q != device.ray_queue) {
        let t = with(&|t| t.ray_queue = queue);
        if fits(&t) {
            v.push((format!("ray queue {queue}"), t));
        }
    }
    if subgroup_arithmetic {
        let lanes = if device.splat_lanes == 1 { 8.min(device.subgroup_size) } else { 1 };
        if lanes != device.splat_lanes {
            v.push((format!("splat lanes {lanes}"), with(&|t| t.splat_lanes = lanes)));
        }
        let counters = !device.subgroup_counters;
        v.push((format!("subgroup counters {}", on(counters)), with(&|t| t.subgroup_counters = counters)));
        let walk = !device.shared_walk;
        let mut t = with(&|t| t.shared_walk = walk);
        while !fits(&t) && t.ray_queue > 1 {
            t.ray_queue /= 2;
        }
        let queue =
            if t.ray_queue == device.ray_queue { String::new() } else { format!(" (ray queue {})", t.ray_queue) };
        let clusters = match t.walk_cluster {
            c if walk && c != 0 => format!(" in clusters of {c}"),
            _ => String::new(),
        };
        v.push((format!("shared walk {}{clusters}{queue}", on(walk)), t));
    }
    v
}

/// The frame of `method` at `paths` and `size` on `scene`, if the matrix measured it.
pub fn find<'a>(rows: &'a [FrameRow], scene: &str, size: (u32, u32), method: &str, paths: u32) -> Option<&'a FrameRow> {
    rows.iter().find(|r| r.scene == scene && (r.width, r.height) == size && r.method == method && r.paths == paths)
}

/// The groups the Markdown tables show, in frame order.
pub const SHOWN_GROUPS: [&str; 8] = [
    group::PHOTONS,
    group::PHOTON_ORDER,
    group::HIERARCHY,
    group::SPLAT,
    group::CLEARANCE,
    group::SAMPLE_CLEARANCE,
    group::VISIBLE_DISK,
    group::GATHER,
];
