//! The PNG of a render: the GPU tonemap's 8-bit sRGB image (automatic exposure maps the
//! log-average luminance of the lit pixels to middle grey, then the filmic curve; see
//! `passes/tonemap.rs`), the same image the window shows.

use std::path::Path;

use crate::error::{RenderError, Result};

pub fn write(path: &Path, width: u32, height: u32, rgba: &[[u8; 4]]) -> Result<()> {
    let rgb: Vec<u8> = rgba.iter().flat_map(|p| [p[0], p[1], p[2]]).collect();
    image::save_buffer(path, &rgb, width, height, image::ExtendedColorType::Rgb8)
        .map_err(|e| RenderError::Output { path: path.display().to_string(), message: e.to_string() })
}
