//! `leakless bench animation`: what moving costs. Per backend, frames of a scene whose
//! animation advances every frame (instance transforms and world vertices on the host, the
//! vertex copy, the TLAS rebuild and the compute backend's top level in the frame) against the
//! same frames of the scene frozen at those times, interleaved, in one process: the door half
//! open lets in more light than the door shut, so only the same frames compare.

use leakless::passes::names;
use std::path::Path;
use std::time::Instant;

use anyhow::{bail, Context};
use leakless::{Backend, BackendChoice, Method, RenderSettings, Renderer, Scene, SplatSettings};

pub fn run(
    path: &Path,
    (w, h): (u32, u32),
    paths: u32,
    frames: u32,
    fixed: crate::options::FixedRadius,
) -> anyhow::Result<()> {
    let scene = Scene::load(path).with_context(|| format!("loading {}", path.display()))?;
    if !scene.is_animated() || scene.instances.is_empty() {
        bail!("{}: no animated mesh node: nothing moves, so there is nothing to measure", path.display());
    }
    let gpu = crate::open_gpu(BackendChoice::Auto)?;
    let mut backends = vec![(BackendChoice::Compute, Backend::Compute)];
    if gpu.capabilities().ray_query {
        backends.insert(0, (BackendChoice::RayQuery, Backend::RayQuery));
    }
    println!(
        "bench animation {} ({} instances, {} of {} triangles moving; {:.2} s of animation) on {}",
        path.display(),
        scene.instances.len(),
        scene.triangle_count() - scene.static_triangle_count(),
        scene.triangle_count(),
        scene.duration(),
        gpu.report().name
    );
    println!(
        "leakless, {w}x{h}, {paths} paths; mean host time per frame over the same {} frames, animated and frozen interleaved",
        3 * frames.div_ceil(3).max(1)
    );
    println!(
        "{:<9} {:>12} {:>12} {:>8} {:>14} {:>17} {:>15}",
        "backend", "animated ms", "frozen ms", "ratio", "host update ms", "vertex copy ms", "tlas rebuild ms"
    );
    drop(gpu);
    let duration = scene.duration();
    for (choice, backend) in backends {
        let settings = RenderSettings {
            width: w,
            height: h,
            backend: choice,
            method: Method::LeakLess,
            splat: SplatSettings { paths, radius: fixed.radius(&scene), ..Default::default() },
            ..Default::default()
        };
        let mut animated = Renderer::new(crate::open_gpu(choice)?, &scene, settings.clone())?;
        animated.render_frame(None)?;
        animated.wait_idle()?;
        let (mut a_ms, mut f_ms, mut update_ms) = (Vec::new(), Vec::new(), Vec::new());
        // The same frames: at each of `times` times, the scene frozen there against the
        // animated scene moved there anew every frame (by a step of 0.1 ms of animation, so
        // every frame updates and the image is the same frame's).
        let times = frames.div_ceil(3).max(1);
        for i in 0..times {
            let t = duration * (i as f32 + 0.5) / times as f32;
            let mut frozen = Renderer::new(crate::open_gpu(choice)?, &scene.frozen_at(t), settings.clone())?;
            frozen.render_frame(None)?;
            frozen.wait_idle()?;
            for k in 0..3 {
                let start = Instant::now();
                animated.set_time(t + 1e-4 * (k + 1) as f32)?;
                animated.render_frame(None)?;
                animated.wait_idle()?;
                a_ms.push(start.elapsed().as_secs_f64() * 1e3);
                update_ms.push(animated.pose_update_ms());
                let start = Instant::now();
                frozen.render_frame(None)?;
                frozen.wait_idle()?;
                f_ms.push(start.elapsed().as_secs_f64() * 1e3);
            }
            frozen.gpu().check_validation()?;
        }
        // One more moving frame, for the update passes' own times: each pass submitted alone on
        // a CPU device, GPU timestamps on a GPU (the tuning's timing).
        animated.set_timing(animated.tuning().timing);
        animated.set_time(0.25 * duration)?;
        animated.render_frame(None)?;
        animated.wait_idle()?;
        let pass_ms = |name: &str| {
            let report = animated.last_report();
            report.and_then(|r| r.timings.iter().find(|t| t.name == name)).map(|t| t.wall_ms.unwrap_or(t.ms))
        };
        let show = |v: Option<f64>| v.map_or("-".to_string(), |ms| format!("{ms:.3}"));
        animated.gpu().check_validation()?;
        let (a, f): (f64, f64) = (a_ms.iter().sum(), f_ms.iter().sum());
        let n = a_ms.len() as f64;
        println!(
            "{:<9} {:>12.1} {:>12.1} {:>7.3}x {:>14.3} {:>17} {:>15}",
            backend.name(),
            a / n,
            f / n,
            a / f,
            median(&mut update_ms),
            show(pass_ms(names::INSTANCE_VERTICES.label)),
            show(pass_ms(leakless_accel::rayquery::TLAS_REBUILD.label))
        );
    }
    Ok(())
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}
