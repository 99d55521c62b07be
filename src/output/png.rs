//! Tonemapped sRGB PNG for looking at a render: exposure (automatic: the log-average
//! luminance maps to middle grey), a filmic curve, then the sRGB transfer function.

use std::path::Path;

use crate::error::{RenderError, Result};

fn luminance(c: [f32; 3]) -> f32 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

/// Exposure that maps the log-average luminance of the lit pixels to 0.18.
pub fn auto_exposure(pixels: &[[f32; 3]]) -> f32 {
    let (sum, n) = pixels
        .iter()
        .map(|&p| luminance(p))
        .filter(|l| l.is_finite() && *l > 1e-6)
        .fold((0.0f64, 0usize), |(s, n), l| (s + (l as f64).ln(), n + 1));
    if n == 0 {
        return 1.0;
    }
    (0.18 / (sum / n as f64).exp()) as f32
}

/// Narkowicz's fit of the ACES filmic curve: keeps highlights from clipping flat.
fn filmic(x: f32) -> f32 {
    ((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14)).clamp(0.0, 1.0)
}

fn srgb_encode(x: f32) -> f32 {
    if x <= 0.0031308 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

pub fn tonemap(pixels: &[[f32; 3]], exposure: f32) -> Vec<u8> {
    pixels.iter().flat_map(|p| p.map(|c| (srgb_encode(filmic(c.max(0.0) * exposure)) * 255.0 + 0.5) as u8)).collect()
}

pub fn write(path: &Path, width: u32, height: u32, pixels: &[[f32; 3]], exposure: Option<f32>) -> Result<()> {
    let exposure = exposure.unwrap_or_else(|| auto_exposure(pixels));
    let rgb = tonemap(pixels, exposure);
    image::save_buffer(path, &rgb, width, height, image::ExtendedColorType::Rgb8)
        .map_err(|e| RenderError::Output { path: path.display().to_string(), message: e.to_string() })
}
