//! HDR-FLIP (Andersson et al., "Visualizing Errors in Rendered High Dynamic Range Images",
//! Eurographics 2021): the perceptual error of a linear HDR image against a reference, as the
//! per-pixel maximum of LDR-FLIP over a range of exposures that the reference's luminance
//! decides, averaged over the image.
//!
//! The `nv-flip` crate wraps NVIDIA's own FLIP implementation but exposes only LDR-FLIP on
//! 8-bit sRGB images, so the HDR part (exposure range, ACES tone mapping, the maximum) is done
//! here as the paper describes it. The 8-bit quantisation of each exposure adds at most half a
//! code value of difference, far below the errors measured.

use crate::metrics::luminance;

/// The ACES fit FLIP tone-maps with: t(x) = (a x² + b x + c) / (d x² + e x + f), with the 0.6
/// pre-exposure of the fit folded in (as in FLIP's own coefficient table).
const ACES: [f64; 6] = [0.6 * 0.6 * 2.51, 0.6 * 0.03, 0.0, 0.6 * 0.6 * 2.43, 0.6 * 0.59, 0.14];

fn tonemap(x: f64) -> f64 {
    let [a, b, c, d, e, f] = ACES;
    ((a * x * x + b * x + c) / (d * x * x + e * x + f)).clamp(0.0, 1.0)
}

fn srgb8(linear: f64) -> u8 {
    let v = if linear <= 0.003_130_8 { 12.92 * linear } else { 1.055 * linear.powf(1.0 / 2.4) - 0.055 };
    (v.clamp(0.0, 1.0) * 255.0).round() as u8
}

/// The exposures (log2 scale factors) HDR-FLIP evaluates for `reference`: from the one that
/// maps its maximum luminance to where the tone mapper reaches 0.85, to the one that maps its
/// median there: ⌈stops between them⌉ exposures, at least two, evenly spaced (as FLIP does). `None` for a black reference.
pub fn exposures(reference: &[[f32; 3]]) -> Option<Vec<f64>> {
    let mut lum: Vec<f64> = reference.iter().map(luminance).filter(|l| l.is_finite()).collect();
    if lum.is_empty() {
        return None;
    }
    lum.sort_by(f64::total_cmp);
    let max = *lum.last().expect("not empty");
    let median = if lum.len() >= 2 { 0.5 * (lum[lum.len() / 2 - 1] + lum[lum.len() / 2]) } else { lum[0] };
    if max <= 0.0 {
        return None;
    }
    // t(x) = 0.85: (a − t d) x² + (b − t e) x + (c − t f) = 0, the positive root.
    let t = 0.85;
    let [a, b, c, d, e, f] = ACES;
    let (qa, qb, qc) = (a - t * d, b - t * e, c - t * f);
    let x_max = (-qb + (qb * qb - 4.0 * qa * qc).sqrt()) / (2.0 * qa);
    let start = (x_max / max).log2();
    // A median of 0 (mostly black image): stop at the maximum's exposure plus the usual span.
    let stop = if median > 0.0 { (x_max / median).log2() } else { start + 1.0 };
    let n = ((stop - start).ceil() as usize).max(2);
    let step = (stop - start) / (n - 1) as f64;
    Some((0..n).map(|i| start + i as f64 * step).collect())
}

/// Mean HDR-FLIP error of `test` against `reference` (linear RGB, `width`×`height`, row-major
/// from the top left), at the crate's default pixels per degree. 0 when the two are equal; a
/// black reference is compared at exposure 0.
pub fn hdr_flip(test: &[[f32; 3]], reference: &[[f32; 3]], width: u32, height: u32) -> f64 {
    assert_eq!(test.len(), reference.len());
    assert_eq!(test.len(), (width * height) as usize);
    let exposures = exposures(reference).unwrap_or_else(|| vec![0.0]);
    let ldr = |image: &[[f32; 3]], exposure: f64| -> Vec<u8> {
        let m = exposure.exp2();
        image.iter().flat_map(|p| p.map(|c| srgb8(tonemap(c.max(0.0) as f64 * m)))).collect()
    };
    let mut max_error = vec![0.0f32; test.len()];
    for &e in &exposures {
        let r = nv_flip::FlipImageRgb8::with_data(width, height, &ldr(reference, e));
        let t = nv_flip::FlipImageRgb8::with_data(width, height, &ldr(test, e));
        let errors = nv_flip::flip(r, t, nv_flip::DEFAULT_PIXELS_PER_DEGREE).to_vec();
        for (m, v) in max_error.iter_mut().zip(errors) {
            *m = m.max(v);
        }
    }
    max_error.iter().map(|&v| v as f64).sum::<f64>() / max_error.len().max(1) as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(w: u32, h: u32, f: impl Fn(u32, u32) -> f32) -> Vec<[f32; 3]> {
        (0..h).flat_map(|y| (0..w).map(move |x| (x, y))).map(|(x, y)| [f(x, y); 3]).collect()
    }

    #[test]
    fn equal_images_score_zero_and_more_noise_scores_more() {
        let (w, h) = (32, 32);
        let reference = image(w, h, |x, y| 0.1 + 2.0 * (x + y) as f32 / 64.0);
        assert_eq!(hdr_flip(&reference, &reference, w, h), 0.0);
        let noisy = |amount: f32| {
            image(w, h, |x, y| {
                (0.1 + 2.0 * (x + y) as f32 / 64.0)
                    * (1.0 + amount * if (x * 7 + y * 13) % 3 == 0 { 1.0 } else { -0.5 })
            })
        };
        let small = hdr_flip(&noisy(0.05), &reference, w, h);
        let large = hdr_flip(&noisy(0.5), &reference, w, h);
        assert!(0.0 < small && small < large && large < 1.0, "{small} {large}");
    }

    #[test]
    fn exposures_span_maximum_to_median_in_stops() {
        // Max luminance 16, median 1: four stops apart, so four exposures spanning them.
        let mut reference = vec![[1.0f32; 3]; 9];
        reference[8] = [16.0; 3];
        let e = exposures(&reference).unwrap();
        assert_eq!(e.len(), 4);
        assert!((e[3] - e[0] - 4.0).abs() < 1e-9, "{e:?}");
        assert!(exposures(&[[0.0; 3]; 4]).is_none());
    }
}
