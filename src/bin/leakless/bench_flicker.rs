//! `leakless bench flicker`: temporal stability per scene and method — flicker of a still view
//! with fresh photons every frame, and how each frame of an accumulation changes the image.

use std::path::PathBuf;

use anyhow::Context;
use leakless::{BackendChoice, Method, RenderSettings, Renderer, Scene, SplatSettings};
use leakless_measure::flicker::{
    accumulation_changes, flicker_of, grain_of, noise_grain_of, single_frames, FLICKER_FRAMES,
};

pub fn run(
    scenes: &[PathBuf],
    (w, h): (u32, u32),
    paths: u32,
    backend: BackendChoice,
    frames: u32,
    fixed: crate::options::FixedRadius,
) -> anyhow::Result<()> {
    let open = || {
        leakless::Gpu::new(&leakless::GpuOptions {
            validation: None,
            ray_tracing: backend.wants_ray_queries(),
            window: None,
        })
    };
    println!(
        "bench flicker ({w}x{h}, {paths} paths): per pixel, temporal std / mean of luminance over {FLICKER_FRAMES} frames with fresh photons, averaged over lit pixels"
    );
    println!("whole disk: leakless without its visible-disk estimate (--whole-disk)");
    println!(
        "{:<14} {:>9} {:>16} {:>9} {:>17} {:>11}   accumulation: change made by frame N (N = 2, 4, 8, 16, 32 ...)",
        "scene", "splat", "leakless-capped", "leakless", "leakless / splat", "whole disk"
    );
    let (mut grain_rows, mut noise_rows) = (Vec::new(), Vec::new());
    for path in scenes {
        let scene = Scene::load(path).with_context(|| format!("loading {}", path.display()))?;
        let settings = |method, visible_disk| RenderSettings {
            width: w,
            height: h,
            backend,
            method,
            splat: SplatSettings { paths, visible_disk, radius: fixed.radius(&scene), ..Default::default() },
            ..Default::default()
        };
        let mut renderer = Renderer::new(open()?, &scene, settings(Method::Splat, true))?;
        let (mut values, mut grains, mut noise_grains) = (Vec::new(), Vec::new(), Vec::new());
        // The last: leakless without its visible-disk estimate (`--whole-disk`), to tell what
        // that estimate adds.
        for (method, visible_disk) in
            [(Method::Splat, true), (Method::LeakLessCapped, true), (Method::LeakLess, true), (Method::LeakLess, false)]
        {
            renderer.set_settings(settings(method, visible_disk))?;
            let frames = single_frames(&mut renderer, FLICKER_FRAMES)?;
            values.push(flicker_of(&frames));
            grains.push(grain_of(&frames, w as usize));
            noise_grains.push(noise_grain_of(&frames, w as usize));
        }
        renderer.set_settings(settings(Method::LeakLess, true))?;
        let changes = accumulation_changes(&mut renderer, frames)?;
        renderer.gpu().check_validation()?;
        let at_powers: Vec<String> = (1..)
            .map(|k| 1usize << k)
            .take_while(|&n| n <= changes.len() + 1)
            .map(|n| format!("{:.4}", changes[n - 2]))
            .collect();
        println!(
            "{:<14} {:>9.4} {:>16.4} {:>9.4} {:>16.2}x {:>11.4}   {}",
            scene.name,
            values[0],
            values[1],
            values[2],
            values[2] / values[0].max(1e-12),
            values[3],
            at_powers.join(" ")
        );
        grain_rows.push(row(&scene.name, &grains));
        noise_rows.push(row(&scene.name, &noise_grains));
    }
    table(
        "grain, the same frames: per frame, mean |L - median of its 3x3 neighbourhood| over the mean luminance (pixel-scale noise)",
        &grain_rows,
    );
    table(
        &format!("grain of the noise alone: the same, of each frame less the {FLICKER_FRAMES} frames' mean (what every frame shares, such as a thin line or a contact shadow, is the image and does not count)"),
        &noise_rows,
    );
    Ok(())
}

/// A scene's row of a grain table: splat, leakless-capped, leakless, leakless over splat, and
/// leakless without its visible disk.
fn row(scene: &str, v: &[f64]) -> String {
    format!("{:<14} {:>9.4} {:>16.4} {:>9.4} {:>16.2}x {:>11.4}", scene, v[0], v[1], v[2], v[2] / v[0].max(1e-12), v[3])
}

fn table(title: &str, rows: &[String]) {
    println!();
    println!("{title}");
    println!(
        "{:<14} {:>9} {:>16} {:>9} {:>17} {:>11}",
        "scene", "splat", "leakless-capped", "leakless", "leakless / splat", "whole disk"
    );
    for row in rows {
        println!("{row}");
    }
}
