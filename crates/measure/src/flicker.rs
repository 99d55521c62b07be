//! Temporal stability of a still view (docs/architecture.md §5): how much it flickers when
//! every frame traces fresh photons, and how quickly an accumulation settles.

use crate::metrics::luminance;
use leakless::error::Result;
use leakless::Renderer;

/// Frames the flicker metric looks at.
pub const FLICKER_FRAMES: u32 = 16;

/// Flicker: `frames` frames of the renderer's current view and settings, each with fresh
/// photons (the next seed) and no accumulation; each pixel's temporal standard deviation of
/// luminance over its temporal mean, averaged over the pixels whose mean is above zero (a pixel
/// that is black in every frame does not flicker). The method's own flicker: without temporal
/// reuse, which would average the frames. Leaves the renderer without accumulation or reuse.
pub fn flicker(renderer: &mut Renderer, frames: u32) -> Result<f64> {
    Ok(flicker_of(&single_frames(renderer, frames)?))
}

/// The luminance images of `frames` single frames with fresh photons, as [`flicker`] renders
/// them.
pub fn single_frames(renderer: &mut Renderer, frames: u32) -> Result<Vec<Vec<f64>>> {
    renderer.set_progressive(false);
    renderer.update(|s| (s.frames, s.reuse) = (1, false))?;
    renderer.set_advance_seed(true);
    let mut series = Vec::with_capacity(frames as usize);
    for _ in 0..frames {
        let frame = renderer.capture_frame()?;
        series.push(frame.radiance.iter().map(luminance).collect::<Vec<f64>>());
    }
    Ok(series)
}

/// Grain: noise at the scale of a pixel, which flicker (per pixel, over frames) and relMSE
/// (dominated by kernel-sized blotches) both blur. Per frame, the mean over the pixels not on
/// the image's border of |L − the median of L's 3×3 neighbourhood|; averaged over the frames
/// and divided by the mean luminance of all of them, so that a method that is darker is not
/// less grainy for it. 0 for a smooth or constant image.
pub fn grain_of(series: &[Vec<f64>], width: usize) -> f64 {
    let Some(first) = series.first() else { return 0.0 };
    let mean = series.iter().flatten().sum::<f64>() / (series.len() * first.len()).max(1) as f64;
    if mean <= 0.0 {
        return 0.0;
    }
    deviation_from_median(series, width) / mean
}

/// The mean over the frames and their pixels not on the border of |v − the median of v's 3×3
/// neighbourhood|; 0 for images narrower or lower than 3 pixels.
fn deviation_from_median(series: &[Vec<f64>], width: usize) -> f64 {
    let Some(first) = series.first() else { return 0.0 };
    let height = first.len() / width.max(1);
    if width < 3 || height < 3 {
        return 0.0;
    }
    let mut total = 0.0;
    for image in series {
        for y in 1..height - 1 {
            for x in 1..width - 1 {
                let mut window = [0.0; 9];
                for (k, w) in window.iter_mut().enumerate() {
                    *w = image[(y + k / 3 - 1) * width + x + k % 3 - 1];
                }
                window.sort_by(f64::total_cmp);
                total += (image[y * width + x] - window[4]).abs();
            }
        }
    }
    total / (series.len() * (width - 2) * (height - 2)) as f64
}

/// [`grain_of`] the noise alone: each frame less the frames' mean image, scaled by
/// `√(n / (n − 1))` (the mean holds `1/n` of each frame's noise), over the frames' mean
/// luminance. What every frame shares (a thin bright line, a corner, the contact shadow of a
/// baluster, which a 3×3 median does not keep) is the image, not noise, and does not count.
pub fn noise_grain_of(series: &[Vec<f64>], width: usize) -> f64 {
    let Some(first) = series.first() else { return 0.0 };
    let n = series.len();
    let total = series.iter().flatten().sum::<f64>();
    if n < 2 || total <= 0.0 {
        return 0.0;
    }
    let mean_image: Vec<f64> = (0..first.len()).map(|i| series.iter().map(|f| f[i]).sum::<f64>() / n as f64).collect();
    let scale = (n as f64 / (n - 1) as f64).sqrt();
    let noise: Vec<Vec<f64>> =
        series.iter().map(|f| f.iter().zip(&mean_image).map(|(l, m)| scale * (l - m)).collect()).collect();
    // grain_of divides by its series' mean luminance, which the noise does not have.
    let mean = total / (n * first.len()) as f64;
    deviation_from_median(&noise, width) / mean
}

/// [`flicker`] of per-frame luminance images (each the same length).
pub fn flicker_of(series: &[Vec<f64>]) -> f64 {
    let Some(first) = series.first() else { return 0.0 };
    let n = series.len() as f64;
    let (mut sum, mut count) = (0.0, 0usize);
    for i in 0..first.len() {
        let mean = series.iter().map(|f| f[i]).sum::<f64>() / n;
        if mean <= 0.0 {
            continue;
        }
        let var = series.iter().map(|f| (f[i] - mean).powi(2)).sum::<f64>() / n;
        sum += var.sqrt() / mean;
        count += 1;
    }
    if count == 0 {
        0.0
    } else {
        sum / count as f64
    }
}

/// How much each frame of an accumulation changes the image: for N = 2..=`frames`, the RMS
/// of (image after N frames − image after N − 1) over the RMS of the image after N, in
/// luminance. Starts a new accumulation (progressive, from the renderer's seed).
pub fn accumulation_changes(renderer: &mut Renderer, frames: u32) -> Result<Vec<f64>> {
    renderer.set_advance_seed(false);
    renderer.set_progressive(false);
    renderer.set_progressive(true); // a change of mode restarts the accumulation
    let mut last: Option<Vec<f64>> = None;
    let mut changes = Vec::new();
    for _ in 0..frames {
        let image: Vec<f64> = renderer.capture_frame()?.radiance.iter().map(luminance).collect();
        if let Some(prev) = &last {
            let diff = image.iter().zip(prev).map(|(a, b)| (a - b).powi(2)).sum::<f64>();
            let norm = image.iter().map(|a| a * a).sum::<f64>();
            changes.push((diff / norm.max(1e-300)).sqrt());
        }
        last = Some(image);
    }
    renderer.set_progressive(false);
    Ok(changes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flicker_is_the_mean_relative_deviation_of_lit_pixels() {
        // Pixel 0: constant (0); pixel 1: 1, 3 (mean 2, deviation 1: 0.5); pixel 2: black.
        let series = vec![vec![5.0, 1.0, 0.0], vec![5.0, 3.0, 0.0]];
        assert_eq!(flicker_of(&series), 0.25);
        assert_eq!(flicker_of(&[vec![0.0; 4], vec![0.0; 4]]), 0.0);
        assert_eq!(flicker_of(&[]), 0.0);
    }

    #[test]
    fn grain_is_the_deviation_from_the_local_median() {
        // A ramp is its own median everywhere: no grain. One bright pixel of 10 in a 1-valued
        // 4×4 image: the inner 2×2 pixels deviate by 9 (that one) and 0 (its neighbours'
        // medians stay 1), over 4 inner pixels and a mean of 25/16.
        let ramp: Vec<f64> = (0..16).map(|i| (i % 4) as f64 + 1.0).collect();
        assert_eq!(grain_of(&[ramp], 4), 0.0);
        let mut spot = vec![1.0; 16];
        spot[5] = 10.0;
        assert!((grain_of(&[spot], 4) - 9.0 / 4.0 / (25.0 / 16.0)).abs() < 1e-12);
        assert_eq!(grain_of(&[vec![0.0; 16]], 4), 0.0);
    }

    #[test]
    fn noise_grain_counts_what_changes_between_frames_only() {
        // A bright pixel every frame shares is the image: grain sees it, noise grain does not.
        let mut spot = vec![1.0; 16];
        spot[5] = 10.0;
        let still = vec![spot.clone(), spot.clone()];
        assert!((grain_of(&still, 4) - 9.0 / 4.0 / (25.0 / 16.0)).abs() < 1e-12);
        assert_eq!(noise_grain_of(&still, 4), 0.0);
        // A spike of +2 in one frame of two at pixel 5: the frames less their mean are +1 and
        // −1 there (× √2), and each inner pixel's median stays 0; over 2 frames × 4 inner
        // pixels and a mean luminance of (32 + 2) / 32.
        let mut spiked = vec![1.0; 16];
        spiked[5] = 3.0;
        let noisy = vec![spiked, vec![1.0; 16]];
        let expected = 2.0 * 2f64.sqrt() / 8.0 / (34.0 / 32.0);
        assert!((noise_grain_of(&noisy, 4) - expected).abs() < 1e-12, "{}", noise_grain_of(&noisy, 4));
        assert_eq!(noise_grain_of(&[vec![0.0; 16], vec![0.0; 16]], 4), 0.0);
        assert_eq!(noise_grain_of(&noisy[..1], 4), 0.0);
    }
}
