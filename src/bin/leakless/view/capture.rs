//! Captures (F12, or `capture` in a script): the next frame of the current state rendered
//! with a readback, written as `render` writes a render (layered EXR, PNG, stats JSON), with
//! the `leakless render` command that renders the same image again in the JSON.

use std::path::{Path, PathBuf};

use anyhow::Context;
use leakless::output::{self, OutputPaths};
use leakless::{Method, RenderSettings, Scene};

use super::Running;
use crate::options::CameraSpec;

/// `captures/<scene>-<n>.exr` for the first `n` not taken.
pub fn next_path(scene: &str) -> anyhow::Result<PathBuf> {
    let dir = PathBuf::from("captures");
    std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
    let path = (1..).map(|n| dir.join(format!("{scene}-{n}.exr"))).find(|p| !p.exists()).expect("unbounded");
    Ok(path)
}

/// Captures the next frame to `exr` (+ `.png`, `.json` beside it). Returns why not when the
/// frame cannot be captured, for the app to say as it says a refused key (`refusal`).
pub fn capture(r: &mut Running, scene: &Scene, exr: &Path) -> anyhow::Result<Option<String>> {
    // Paused since a change: the window shows an image of the state before it, which no
    // command renders.
    if r.renderer.paused() && r.renderer.accumulated() == 0 {
        return Ok(Some(
            "capture: paused since the last change, the window shows the state before it (Space resumes)".into(),
        ));
    }
    if let Some(dir) = exr.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    // The frame captured holds no temporal history, which depends on the path the camera
    // took: it is what the recorded command renders. (Reuse starts again from it.)
    r.renderer.forget_history();
    let frame = r.renderer.capture_frame().context("capturing")?;
    let light = r.light_moved.then(|| r.renderer.lights()[0].position);
    let view = View { camera: r.camera.spec(), light, time: r.renderer.time(), progressive: r.renderer.accumulating() };
    let start = Start { first_paths: r.renderer.first_frame_paths(), radii: r.renderer.accumulation_radii() };
    let command = command(r.renderer.settings(), r.renderer.backend(), scene, &frame, view, start, exr);
    let paths = OutputPaths {
        exr: exr.to_path_buf(),
        png: Some(exr.with_extension("png")),
        stats: Some(exr.with_extension("json")),
    };
    let scene_path = scene_path(scene);
    for path in output::write_render(&paths, &scene_path, &r.renderer, &frame, Some(command))? {
        println!("captured {}", path.display());
    }
    Ok(None)
}

/// The scene's file as the command line names it (the app was started with it).
fn scene_path(scene: &Scene) -> PathBuf {
    std::env::args_os()
        .skip(2)
        .map(PathBuf::from)
        .find(|p| p.file_stem().is_some_and(|s| s.to_string_lossy() == scene.name) && p.exists())
        .unwrap_or_else(|| PathBuf::from(format!("{}.gltf", scene.name)))
}

/// Where the captured frame looks from, and when.
struct View {
    camera: CameraSpec,
    /// The first light's position, when it was moved.
    light: Option<glam::Vec3>,
    /// The scene's clock.
    time: f32,
    /// Whether frames accumulate (else each frame is the image; a reference's frames then add
    /// samples to one unjittered image).
    progressive: bool,
}

/// How the captured accumulation started: its first frame's paths (the budget's), and its
/// first frame's radius and the one its later batches shrink from.
struct Start {
    first_paths: Option<u32>,
    radii: Option<(f32, f32)>,
}

/// The `leakless render` command that renders `frame` again: every setting explicit, the
/// frame's own seed, the view, the animation time and (if moved) the light.
fn command(
    s: &RenderSettings,
    backend: leakless::Backend,
    scene: &Scene,
    frame: &leakless::RenderedFrame,
    view: View,
    start: Start,
    exr: &Path,
) -> String {
    let View { camera, light, time, progressive } = view;
    let Start { first_paths, radii } = start;
    let mut c = vec![
        "leakless".to_string(),
        "render".into(),
        scene_path(scene).display().to_string(),
        format!("--size {}x{}", s.width, s.height),
        format!("--method {}", s.method.name()),
        format!("--backend {}", backend.name()),
        format!("--max-bounces {}", s.max_bounces),
        format!("--seed {}", frame.seed),
    ];
    if s.method.splats() {
        // The frame budget chose the paths of the accumulation's first frame.
        match first_paths.filter(|p| *p != s.splat.paths) {
            Some(first) if progressive && frame.accumulated > 1 => {
                c.push(format!("--paths {} --first-frame-paths {first}", s.splat.paths));
            }
            Some(first) => c.push(format!("--paths {first}")),
            None => c.push(format!("--paths {}", s.splat.paths)),
        }
        // The radii the frame used: the count-following radius comes from the frames before
        // it, which the command does not render.
        match radii {
            Some((first, batches)) if progressive && frame.accumulated > 1 && first != batches => {
                c.push(format!("--radius {batches} --first-frame-radius {first}"));
            }
            Some((first, _)) => c.push(format!("--radius {first}")),
            None => {}
        }
        if s.tuning != leakless::TuningChoice::Auto {
            c.push(format!("--tuning {}", s.tuning.name()));
        }
        if let Some(b) = s.splat.branching {
            c.push(format!("--branching {b}"));
        }
        if !s.splat.trivial_accept {
            c.push("--no-trivial-accept".into());
        }
        if let Some(cap) = s.splat.cap {
            c.push(format!("--cap {cap}"));
        }
        if let Some(n) = s.splat.list_capacity {
            c.push(format!("--list-capacity {n}"));
        }
    }
    match (s.method, progressive) {
        (Method::Reference, true) => c.push(format!("--spp {}", s.spp)),
        (Method::Reference, false) => c.push(format!("--spp {}", frame.accumulated)),
        _ => {}
    }
    if progressive && frame.accumulated > 1 {
        c.push(format!("--frames {}", frame.accumulated));
        if s.max_batches != leakless::settings::DEFAULT_MAX_BATCHES {
            c.push(format!("--max-batches {}", s.max_batches));
        }
    }
    if s.primary != leakless::Primary::Auto {
        c.push(format!("--primary {}", s.primary.name()));
    }
    if time != 0.0 {
        c.push(format!("--time {time}"));
    }
    c.push(format!("--camera {}", camera.flag()));
    if let Some(p) = light {
        c.push(format!("--light-position {},{},{}", p.x, p.y, p.z));
    }
    c.push(format!("--out {}", exr.display()));
    c.join(" ")
}
