//! What a render leaves on disk: the layered EXR, the tonemapped PNG, the stats JSON. The
//! CLI's `render` and the app's captures write them the same way.

pub mod exr;
pub mod png;
pub mod stats;

use std::path::{Path, PathBuf};

use crate::error::Result;
use crate::{RenderedFrame, Renderer};
use exr::ExrLayer;

/// Where to write a render; `None` skips the file.
pub struct OutputPaths {
    pub exr: PathBuf,
    pub png: Option<PathBuf>,
    pub stats: Option<PathBuf>,
}

/// Writes the EXR (every layer, header attributes naming scene, method and parameters), and
/// the PNG and stats when asked; returns the files written. `command` goes into the stats.
pub fn write_render(
    paths: &OutputPaths,
    scene_path: &Path,
    renderer: &Renderer,
    frame: &RenderedFrame,
    command: Option<String>,
) -> Result<Vec<PathBuf>> {
    let layers = [
        ExrLayer { name: "", pixels: &frame.radiance },
        ExrLayer { name: "direct", pixels: &frame.direct },
        ExrLayer { name: "indirect", pixels: &frame.indirect },
        ExrLayer { name: "leaked", pixels: &frame.leaked },
    ];
    let settings = renderer.settings();
    let attributes = [
        ("leakless.scene", scene_path.display().to_string()),
        ("leakless.method", settings.method.name().to_string()),
        (
            "leakless.parameters",
            format!("{} backend={} frame_seed={}", settings.describe(), renderer.backend().name(), frame.seed),
        ),
        ("leakless.device", renderer.gpu().report().name.clone()),
    ];
    exr::write(&paths.exr, frame.width, frame.height, &layers, &attributes)?;
    let mut written = vec![paths.exr.clone()];
    if let Some(png) = &paths.png {
        png::write(png, frame.width, frame.height, &frame.display)?;
        written.push(png.clone());
    }
    if let Some(path) = &paths.stats {
        stats::write(path, &stats::Stats::new(renderer, frame, command))?;
        written.push(path.clone());
    }
    Ok(written)
}
