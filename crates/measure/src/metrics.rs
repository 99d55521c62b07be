//! Error of an image against a reference, as `leakless chart` plots it.
//!
//! All sums are over pixels *and* the three colour channels, in `f64`:
//!
//! * **relMSE** = mean over (pixel, channel) of `(x − r)² / (r² + ε)`, with one `ε` per image
//!   pair: `ε = 10⁻² · m²`, `m` = mean of the reference over *every* pixel and channel of the
//!   image ([`epsilon`]). ε keeps near-black pixels from dominating, and because it comes from
//!   the whole image, the relMSE of the dark pixels (whose `r` is about 0) is about their mean
//!   squared error over `(m / 10)²`: leaked light measured against the image's brightness.
//!   A black reference (`m = 0`, e.g. a camera in a sealed, unlit room) has no scale to be
//!   relative to: its relMSE is `None` (undefined), and its RMSE measures the leaks.
//! * **RMSE** = square root of the mean over (pixel, channel) of `(x − r)²`.
//! * **Dark pixels** ([`dark_mask`]): pixels with a surface whose reference *indirect* light
//!   `(R + G + B) / 3` is at most 1% ([`DARK_FRACTION`]) of that value's mean over the pixels
//!   with a surface (all of them when that mean is 0). Indirect light there is mostly leaked
//!   light in a method's image, so these are where leaks show.
//!
//! Each metric is evaluated on the final radiance (direct + indirect) over all pixels, and
//! over the dark pixels only. Over an empty set a metric is `None`.

/// Dark pixels: reference indirect light at most this fraction of its mean.
pub const DARK_FRACTION: f64 = 0.01;

/// ε of the relMSE, relative to the squared mean of the reference.
pub const EPSILON_SCALE: f64 = 1e-2;

/// `EPSILON_SCALE · m²`, `m` the mean of `reference` over every pixel and channel.
pub fn epsilon(reference: &[[f32; 3]]) -> f64 {
    EPSILON_SCALE * mean_value(reference).powi(2)
}

pub use leakless::photon_lights::luminance as rgb_luminance;

/// Luminance of a linear RGB pixel.
pub fn luminance(p: &[f32; 3]) -> f64 {
    rgb_luminance(p.map(f64::from))
}

/// Mean luminance of a layer's pixels (0 for an empty layer).
pub fn mean_luminance(layer: &[[f32; 3]]) -> f64 {
    layer.iter().map(luminance).sum::<f64>() / layer.len().max(1) as f64
}

/// Mean over every pixel and channel (0 for an empty image).
pub fn mean_value(layer: &[[f32; 3]]) -> f64 {
    if layer.is_empty() {
        return 0.0;
    }
    layer.iter().flat_map(|p| p.iter()).map(|&c| c as f64).sum::<f64>() / (3 * layer.len()) as f64
}

fn selected<'a>(
    x: &'a [[f32; 3]],
    r: &'a [[f32; 3]],
    mask: Option<&'a [bool]>,
) -> impl Iterator<Item = (&'a [f32; 3], &'a [f32; 3])> + 'a {
    assert_eq!(x.len(), r.len(), "image and reference differ in size");
    if let Some(m) = mask {
        assert_eq!(m.len(), r.len(), "mask and reference differ in size");
    }
    x.iter().zip(r).enumerate().filter(move |(i, _)| mask.is_none_or(|m| m[*i])).map(|(_, p)| p)
}

/// Mean of `f(x, r)` over the selected pixels and their channels; `None` if none is selected.
fn mean_over(x: &[[f32; 3]], r: &[[f32; 3]], mask: Option<&[bool]>, f: impl Fn(f64, f64) -> f64) -> Option<f64> {
    let (mut sum, mut n) = (0.0f64, 0usize);
    for (a, b) in selected(x, r, mask) {
        for c in 0..3 {
            sum += f(a[c] as f64, b[c] as f64);
        }
        n += 3;
    }
    (n > 0).then(|| sum / n as f64)
}

/// Relative MSE of `x` against `r` over the pixels `mask` selects (all with `None`):
/// mean of `(x − r)² / (r² + eps)`; `None` over no pixel or with `eps ≤ 0` (undefined where
/// `r = 0`).
pub fn rel_mse(x: &[[f32; 3]], r: &[[f32; 3]], mask: Option<&[bool]>, eps: f64) -> Option<f64> {
    if eps.is_nan() || eps <= 0.0 {
        return None;
    }
    mean_over(x, r, mask, |a, b| rel_squared_error(a, b, eps))
}

/// Pixels on each side of a pixel whose references' mean makes its denominator in
/// [`rel_mse_without_reference_noise`] and [`reference_noise`].
pub const DENOMINATOR_RADIUS: usize = 2;

/// The noise of `r̄`, the mean of two independent, unbiased estimates `r1` and `r2` of a truth,
/// `width` pixels wide, in [`rel_mse_without_reference_noise`]'s terms: mean of
/// `((r1 − r2) / 2)² / (s² + eps)`, `s` as there. The numerator's expectation is `r̄`'s
/// variance, which every image's error against `r̄` includes.
pub fn reference_noise(r1: &[[f32; 3]], r2: &[[f32; 3]], width: usize, eps: f64) -> Option<f64> {
    noise_terms(r1, r1, r2, width, eps).map(|(_, noise)| noise)
}

/// The relMSE of `x` against the truth that `r1` and `r2` (independent, unbiased estimates of
/// it, `width` pixels wide) estimate: mean of `(x − r1)(x − r2) / (s² + eps)`. The product's
/// expectation is `x`'s squared error without the references' variance. `s` is `r̄` averaged
/// over the pixels around each pixel ([`DENOMINATOR_RADIUS`] on each side), not the pixel
/// itself: a noisy reference's own denominator is small where its noise happens to be dark and
/// weighs those pixels' errors many times over, while the neighbours' mean is steady and
/// independent of the pixel's noise. Where the light changes within the window the weights
/// blur, alike for every image compared. A single image's figure may be negative.
pub fn rel_mse_without_reference_noise(
    x: &[[f32; 3]],
    r1: &[[f32; 3]],
    r2: &[[f32; 3]],
    width: usize,
    eps: f64,
) -> Option<f64> {
    noise_terms(x, r1, r2, width, eps).map(|(product, _)| product)
}

/// Means over (pixel, channel) of `(x − r1)(x − r2)` and of `((r1 − r2) / 2)²`, each over
/// `s² + eps`.
fn noise_terms(x: &[[f32; 3]], r1: &[[f32; 3]], r2: &[[f32; 3]], width: usize, eps: f64) -> Option<(f64, f64)> {
    assert!(x.len() == r1.len() && r1.len() == r2.len(), "image and references differ in size");
    if eps.is_nan() || eps <= 0.0 || x.is_empty() || width == 0 {
        return None;
    }
    assert_eq!(x.len() % width, 0, "the image is not `width` pixels wide");
    let mean: Vec<[f64; 3]> =
        r1.iter().zip(r2).map(|(a, b)| std::array::from_fn(|c| 0.5 * (a[c] as f64 + b[c] as f64))).collect();
    let scale = neighbours_mean(&mean, width, DENOMINATOR_RADIUS);
    let (mut product, mut noise) = (0.0f64, 0.0f64);
    for (i, (a, (b1, b2))) in x.iter().zip(r1.iter().zip(r2)).enumerate() {
        for c in 0..3 {
            let (a, b1, b2) = (a[c] as f64, b1[c] as f64, b2[c] as f64);
            let denominator = scale[i][c] * scale[i][c] + eps;
            product += (a - b1) * (a - b2) / denominator;
            noise += (0.5 * (b1 - b2)).powi(2) / denominator;
        }
    }
    let n = (3 * x.len()) as f64;
    Some((product / n, noise / n))
}

/// Each pixel's mean of the other pixels within `radius` of it (clipped to the image); the
/// pixel's own value where it has none.
fn neighbours_mean(image: &[[f64; 3]], width: usize, radius: usize) -> Vec<[f64; 3]> {
    let height = image.len() / width;
    let mut out = Vec::with_capacity(image.len());
    for y in 0..height {
        for x in 0..width {
            let (mut sum, mut n) = ([0.0f64; 3], 0usize);
            for v in y.saturating_sub(radius)..(y + radius + 1).min(height) {
                for u in x.saturating_sub(radius)..(x + radius + 1).min(width) {
                    if (u, v) != (x, y) {
                        let p = image[v * width + u];
                        (0..3).for_each(|c| sum[c] += p[c]);
                        n += 1;
                    }
                }
            }
            let own = image[y * width + x];
            out.push(if n == 0 { own } else { sum.map(|s| s / n as f64) });
        }
    }
    out
}

/// One channel's term of [`rel_mse`]: `(a − b)² / (b² + eps)`.
pub fn rel_squared_error(a: f64, b: f64, eps: f64) -> f64 {
    (a - b).powi(2) / (b * b + eps)
}

/// Root-mean-square error of `x` against `r` over the pixels `mask` selects (all with `None`).
pub fn rmse(x: &[[f32; 3]], r: &[[f32; 3]], mask: Option<&[bool]>) -> Option<f64> {
    mean_over(x, r, mask, |a, b| (a - b).powi(2)).map(f64::sqrt)
}

/// The dark pixels: `covered` (a surface there; every pixel with `None`) and reference indirect
/// light `(R + G + B) / 3` at most `fraction` × its mean over the covered pixels.
pub fn dark_mask(reference_indirect: &[[f32; 3]], covered: Option<&[bool]>, fraction: f64) -> Vec<bool> {
    if let Some(c) = covered {
        assert_eq!(c.len(), reference_indirect.len(), "coverage and image differ in size");
    }
    let is_covered = |i: usize| covered.is_none_or(|c| c[i]);
    let level = |p: &[f32; 3]| (p[0] as f64 + p[1] as f64 + p[2] as f64) / 3.0;
    let (mut sum, mut n) = (0.0f64, 0usize);
    for (i, p) in reference_indirect.iter().enumerate() {
        if is_covered(i) {
            sum += level(p);
            n += 1;
        }
    }
    let threshold = fraction * sum / n.max(1) as f64;
    reference_indirect.iter().enumerate().map(|(i, p)| is_covered(i) && level(p) <= threshold).collect()
}

/// The four errors of one image against the reference; `None` where undefined: over an empty
/// image or no dark pixel, and the relMSE of a black reference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Errors {
    pub relmse: Option<f64>,
    pub rmse: Option<f64>,
    pub relmse_dark: Option<f64>,
    pub rmse_dark: Option<f64>,
}

/// relMSE and RMSE of `radiance` against `reference` over every pixel and over `dark`, with
/// ε from the whole reference ([`epsilon`]).
pub fn errors(radiance: &[[f32; 3]], reference: &[[f32; 3]], dark: &[bool]) -> Errors {
    let eps = epsilon(reference);
    Errors {
        relmse: rel_mse(radiance, reference, None, eps),
        rmse: rmse(radiance, reference, None),
        relmse_dark: rel_mse(radiance, reference, Some(dark), eps),
        rmse_dark: rmse(radiance, reference, Some(dark)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const R: [[f32; 3]; 2] = [[1.0, 1.0, 1.0], [0.0, 0.0, 0.0]];
    const X: [[f32; 3]; 2] = [[2.0, 1.0, 1.0], [0.0, 0.5, 0.0]];

    #[test]
    fn mean_and_epsilon() {
        assert_eq!(mean_value(&R), 0.5);
        assert_eq!(epsilon(&R), 0.01 * 0.25);
        assert_eq!(mean_value(&[]), 0.0);
    }

    #[test]
    fn rmse_exact() {
        // Squared errors 1, 0, 0, 0, 0.25, 0 over 6 values: mean 1.25 / 6.
        assert_eq!(rmse(&X, &R, None), Some((1.25f64 / 6.0).sqrt()));
        assert_eq!(rmse(&X, &R, Some(&[true, false])), Some((1.0f64 / 3.0).sqrt()));
        assert_eq!(rmse(&X, &R, Some(&[false, true])), Some((0.25f64 / 3.0).sqrt()));
        assert_eq!(rmse(&X, &R, Some(&[false, false])), None);
        assert_eq!(rmse(&R, &R, None), Some(0.0));
    }

    #[test]
    fn rel_mse_exact() {
        let eps = 0.5;
        // Pixel 0: 1/(1 + 0.5) and two zeros; pixel 1: 0.25/(0 + 0.5) and two zeros.
        let p0 = 1.0 / 1.5;
        let p1 = 0.25 / 0.5;
        assert_eq!(rel_mse(&X, &R, None, eps), Some((p0 + p1) / 6.0));
        assert_eq!(rel_mse(&X, &R, Some(&[true, false]), eps), Some(p0 / 3.0));
        assert_eq!(rel_mse(&X, &R, Some(&[false, true]), eps), Some(p1 / 3.0));
        assert_eq!(rel_mse(&X, &R, Some(&[false, false]), eps), None);
        assert_eq!(rel_mse(&X, &R, None, 0.0), None);
        // Relative: scaling image and reference by k scales ε by k² and leaves relMSE as is.
        let k = 4.0f32;
        let scale = |l: &[[f32; 3]]| l.iter().map(|p| p.map(|c| c * k)).collect::<Vec<_>>();
        let a = rel_mse(&X, &R, None, epsilon(&R)).unwrap();
        let b = rel_mse(&scale(&X), &scale(&R), None, epsilon(&scale(&R))).unwrap();
        assert!((a - b).abs() < 1e-12 * a, "{a} vs {b}");
    }

    #[test]
    fn dark_mask_exact() {
        // Levels (mean of channels): 3, 0.02, 0, 0.03, 1 → mean 0.81, 1% = 0.0081.
        let indirect = [[3.0, 3.0, 3.0], [0.0, 0.06, 0.0], [0.0, 0.0, 0.0], [0.09, 0.0, 0.0], [1.0, 1.0, 1.0]];
        assert_eq!(dark_mask(&indirect, None, 0.01), [false, false, true, false, false]);
        // At 3% (threshold 0.0243): 0.02 is dark too, 0.03 is not.
        assert_eq!(dark_mask(&indirect, None, 0.03), [false, true, true, false, false]);
        // Pixels without a surface are never dark and leave the mean: covered levels 3, 0,
        // 0.03 → mean 1.01, 1% = 0.0101.
        let covered = [true, false, true, true, false];
        assert_eq!(dark_mask(&indirect, Some(&covered), 0.01), [false, false, true, false, false]);
        assert_eq!(dark_mask(&indirect, Some(&covered), 0.03), [false, false, true, true, false]);
        // Uniform light: nothing is below 1% of the mean.
        assert_eq!(dark_mask(&[[1.0; 3]; 3], None, 0.01), [false; 3]);
        // No indirect light at all (a sealed room): every covered pixel is dark.
        assert_eq!(dark_mask(&[[0.0; 3]; 3], Some(&[true, false, true]), 0.01), [true, false, true]);
    }

    #[test]
    fn errors_exact() {
        let e = errors(&X, &R, &[false, true]);
        let eps = 0.01 * 0.25; // 1% of the reference's mean (0.5) squared
        assert_eq!(e.relmse, Some((1.0 / (1.0 + eps) + 0.25 / eps) / 6.0));
        assert_eq!(e.rmse, Some((1.25f64 / 6.0).sqrt()));
        assert_eq!(e.relmse_dark, Some(0.25 / eps / 3.0));
        assert_eq!(e.rmse_dark, Some((0.25f64 / 3.0).sqrt()));
        let none = errors(&X, &R, &[false, false]);
        assert_eq!((none.relmse_dark, none.rmse_dark), (None, None));
        let same = errors(&R, &R, &[true, true]);
        assert_eq!(same, Errors { relmse: Some(0.0), rmse: Some(0.0), relmse_dark: Some(0.0), rmse_dark: Some(0.0) });
        // A black reference: relative errors undefined, absolute ones not.
        let black = errors(&X, &[[0.0; 3]; 2], &[true, true]);
        assert_eq!((black.relmse, black.relmse_dark), (None, None));
        assert_eq!(black.rmse, Some((6.25f64 / 6.0).sqrt()));
        assert_eq!(black.rmse_dark, black.rmse);
    }

    /// Against two noisy estimates of a truth, the estimator finds the image's own error, where
    /// relMSE against their mean adds the mean's variance.
    #[test]
    fn rel_mse_without_reference_noise_removes_the_references_variance() {
        // A ±0.5 noise on a truth of 1, independent between the references and the pixels
        // (a hash's bits), and an image 0.1 above the truth.
        let (width, n) = (256, 256 * 256);
        // splitmix64's finaliser: every output bit depends on every input bit.
        let hash = |i: usize| {
            let mut z = (i as u64).wrapping_add(0x9E37_79B9_7F4A_7C15);
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^ (z >> 31)
        };
        let bit = |i: usize, k: u32| hash(i) >> k & 1;
        let noise = |i: usize, k: u32| if bit(i, k) == 0 { 0.5 } else { -0.5 };
        let r1: Vec<[f32; 3]> = (0..n).map(|i| [1.0 + noise(i, 0); 3]).collect();
        let r2: Vec<[f32; 3]> = (0..n).map(|i| [1.0 + noise(i, 7); 3]).collect();
        let x = vec![[1.1f32; 3]; n];
        let mean: Vec<[f32; 3]> = r1.iter().zip(&r2).map(|(a, b)| [0.5 * (a[0] + b[0]); 3]).collect();
        // `eps` = 100 keeps every denominator about 101: against the mean, the image's 0.01
        // and the mean's variance, 0.125.
        let eps = 100.0;
        let with_noise = (1.0 + eps) * rel_mse(&x, &mean, None, eps).unwrap();
        let without = (1.0 + eps) * rel_mse_without_reference_noise(&x, &r1, &r2, width, eps).unwrap();
        let noise = (1.0 + eps) * reference_noise(&r1, &r2, width, eps).unwrap();
        assert!((with_noise - 0.135).abs() < 0.003, "{with_noise}");
        assert!((without - 0.01).abs() < 0.003, "{without}");
        assert!((noise - 0.125).abs() < 0.003, "{noise}");
        // A small `eps`: the mean's own denominators (0.25 to 2.25) would weigh its dark pixels
        // ninefold; the neighbours' mean is steady, and the image's 0.01 is found again.
        let eps = 1e-4;
        assert!(rel_mse(&x, &mean, None, eps).unwrap() > 0.3);
        let without = rel_mse_without_reference_noise(&x, &r1, &r2, width, eps).unwrap();
        assert!((without - 0.01).abs() < 0.003, "{without}");
        // Identical references are a noise-free truth: on a flat image the estimator is
        // rel_mse exactly.
        let flat = vec![[2.0f32; 3]; n];
        let noisy = rel_mse_without_reference_noise(&x, &flat, &flat, width, eps);
        assert_eq!(noisy, rel_mse(&x, &flat, None, eps));
        assert_eq!(rel_mse_without_reference_noise(&x, &flat, &flat, width, 0.0), None);
    }
}
