//! What `bench motion` measures of a sequence of frames besides its error: how much it
//! flickers, on the screen and on the surfaces, and how much light lands in the dark beside lit
//! regions.

use crate::metrics::luminance;
use glam::{Mat4, Vec3, Vec4Swizzles};

/// Flicker as the screen sees it: the mean over frames, from the `settle`th on, of |ΔY| between
/// successive frames over the frame's mean Y. It counts the change the moving view makes too:
/// a perfect image of a camera walk flickers by this measure.
pub struct ScreenFlicker {
    settle: u32,
    sum: f64,
    counted: u32,
    last: Option<Vec<f64>>,
}

impl ScreenFlicker {
    pub fn new(settle: u32) -> Self {
        Self { settle, sum: 0.0, counted: 0, last: None }
    }

    pub fn add(&mut self, k: u32, image: &[[f32; 3]]) {
        let y: Vec<f64> = image.iter().map(luminance).collect();
        if let Some(prev) = &self.last {
            let mean = y.iter().sum::<f64>() / y.len() as f64;
            if k >= self.settle && mean > 0.0 {
                self.sum += y.iter().zip(prev).map(|(a, b)| (a - b).abs()).sum::<f64>() / y.len() as f64 / mean;
                self.counted += 1;
            }
        }
        self.last = Some(y);
    }

    pub fn mean(&self) -> f64 {
        self.sum / self.counted.max(1) as f64
    }
}

/// One frame as `SurfaceFlicker` remembers it.
pub struct SeenFrame<'a> {
    pub image: &'a [[f32; 3]],
    /// Each pixel's surface point and triangle + 1 (`RenderedFrame::surface`).
    pub surface: &'a [[f32; 4]],
    pub view_proj: Mat4,
    pub camera: Vec3,
    pub width: u32,
    pub height: u32,
}

struct Remembered {
    y: Vec<f64>,
    surface: Vec<[f32; 4]>,
    view_proj: Mat4,
}

/// Flicker on the surfaces: each pixel's surface point is found in the frame before (projected
/// with its camera, read bilinearly from the pixels that saw the same triangle or a point within
/// 1% of the view distance), and the change of its luminance counted; per frame Σ|ΔY| / ΣY over
/// the pixels found, averaged over the frames from the `settle`th on. Where neither the light
/// nor the surfaces move, a perfect image does not flicker by this measure: what remains is the
/// renderer's noise changing from frame to frame.
pub struct SurfaceFlicker {
    settle: u32,
    sum: f64,
    counted: u32,
    last: Option<Remembered>,
}

impl SurfaceFlicker {
    pub fn new(settle: u32) -> Self {
        Self { settle, sum: 0.0, counted: 0, last: None }
    }

    pub fn add(&mut self, k: u32, frame: SeenFrame<'_>) {
        let y: Vec<f64> = frame.image.iter().map(luminance).collect();
        if let Some(prev) = &self.last {
            if k >= self.settle {
                let (change, total) = change_on_surfaces(&frame, &y, prev);
                if total > 0.0 {
                    self.sum += change / total;
                    self.counted += 1;
                }
            }
        }
        self.last = Some(Remembered { y, surface: frame.surface.to_vec(), view_proj: frame.view_proj });
    }

    pub fn mean(&self) -> f64 {
        self.sum / self.counted.max(1) as f64
    }
}

/// (Σ|ΔY|, ΣY) over the pixels of `frame` whose surface point the frame before saw.
fn change_on_surfaces(frame: &SeenFrame<'_>, y: &[f64], prev: &Remembered) -> (f64, f64) {
    let (w, h) = (frame.width as i32, frame.height as i32);
    let (mut change, mut total) = (0.0, 0.0);
    for (i, s) in frame.surface.iter().enumerate() {
        if s[3] == 0.0 {
            continue;
        }
        let p = Vec3::new(s[0], s[1], s[2]);
        let clip = prev.view_proj * p.extend(1.0);
        if clip.w <= 0.0 {
            continue;
        }
        let at = (clip.xy() / clip.w * 0.5 + 0.5) * glam::Vec2::new(w as f32, h as f32) - 0.5;
        let base = at.floor();
        let f = at - base;
        let tolerance = 0.01 * (p - frame.camera).length();
        let (mut sum, mut weight) = (0.0, 0.0);
        for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
            let (qx, qy) = (base.x as i32 + dx, base.y as i32 + dy);
            if qx < 0 || qy < 0 || qx >= w || qy >= h {
                continue;
            }
            let q = (qy * w + qx) as usize;
            let t = prev.surface[q];
            let same = t[3] == s[3] || (t[3] != 0.0 && (Vec3::new(t[0], t[1], t[2]) - p).length() < tolerance);
            if !same {
                continue;
            }
            let wx = if dx == 1 { f.x } else { 1.0 - f.x };
            let wy = if dy == 1 { f.y } else { 1.0 - f.y };
            sum += (wx * wy) as f64 * prev.y[q];
            weight += (wx * wy) as f64;
        }
        if weight > 0.5 {
            change += (y[i] - sum / weight).abs();
            total += y[i];
        }
    }
    (change, total)
}

/// A reference pixel counts as dark under this fraction of its frame's mean luminance.
pub const DARK: f64 = 0.1;
/// The band: dark pixels within this many pixels of one lit above the frame's mean.
pub const BAND_PIXELS: i32 = 4;

/// Light a filter would carry out of lit regions lands in the dark pixels beside them: the
/// band's luminance summed over the frames, the frame's and the reference's, and its pixels.
///
/// The band is chosen on one estimate of the truth (`select`) and measured against another,
/// independent one (`measure`): a pixel chosen for being dark in a noisy reference is, on
/// average, darker there than the truth, and every image would seem bright against it.
#[derive(Default)]
pub struct DarkBand {
    frame: f64,
    reference: f64,
    pixels: usize,
}

impl DarkBand {
    pub fn add(&mut self, image: &[[f32; 3]], select: &[[f32; 3]], measure: &[[f32; 3]], w: u32, h: u32) {
        let y: Vec<f64> = select.iter().map(luminance).collect();
        let mean = y.iter().sum::<f64>() / y.len().max(1) as f64;
        let (w, h) = (w as i32, h as i32);
        let lit_near = |x: i32, yy: i32| {
            (-BAND_PIXELS..=BAND_PIXELS).any(|dy| {
                (-BAND_PIXELS..=BAND_PIXELS).any(|dx| {
                    let (qx, qy) = (x + dx, yy + dy);
                    qx >= 0 && qy >= 0 && qx < w && qy < h && y[(qy * w + qx) as usize] > mean
                })
            })
        };
        for yy in 0..h {
            for x in 0..w {
                let i = (yy * w + x) as usize;
                if y[i] < DARK * mean && lit_near(x, yy) {
                    self.frame += luminance(&image[i]);
                    self.reference += luminance(&measure[i]);
                    self.pixels += 1;
                }
            }
        }
    }

    /// The band's luminance over the reference's (None: no band).
    pub fn ratio(&self) -> Option<f64> {
        (self.reference > 0.0).then(|| self.frame / self.reference)
    }

    /// The band's pixels, summed over the frames.
    pub fn pixels(&self) -> usize {
        self.pixels
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An 8×8 image, lit (1) on the left half and dark on the right, with `dark` there.
    fn half_lit(dark: f32) -> Vec<[f32; 3]> {
        (0..64).map(|i| if i % 8 < 4 { [1.0; 3] } else { [dark; 3] }).collect()
    }

    #[test]
    fn the_dark_band_sees_light_carried_into_shadow() {
        let reference = half_lit(0.01);
        let mut same = DarkBand::default();
        same.add(&reference, &reference, &reference, 8, 8);
        assert_eq!(same.ratio(), Some(1.0));
        assert_eq!(same.pixels(), 32);
        // Chosen on one estimate, measured against another: a second estimate twice as dark
        // there halves what the image is measured against.
        let mut other = DarkBand::default();
        other.add(&reference, &reference, &half_lit(0.005), 8, 8);
        assert!((other.ratio().unwrap() - 2.0).abs() < 1e-6);
        // Light bled into the dark half doubles its luminance there.
        let mut bled = DarkBand::default();
        bled.add(&half_lit(0.02), &reference, &reference, 8, 8);
        assert!((bled.ratio().unwrap() - 2.0).abs() < 1e-6);
        // No dark pixel beside a lit one: no band.
        let mut none = DarkBand::default();
        none.add(&[[1.0; 3]; 64], &[[1.0; 3]; 64], &[[1.0; 3]; 64], 8, 8);
        assert_eq!(none.ratio(), None);
    }

    #[test]
    fn screen_flicker_counts_the_change_after_the_settling_frames() {
        let mut change = ScreenFlicker::new(2);
        change.add(0, &[[0.0; 3], [2.0; 3]]);
        // Frame 1's change (to a uniform 1) falls before frame 2: not counted.
        change.add(1, &[[1.0; 3], [1.0; 3]]);
        assert_eq!(change.mean(), 0.0);
        // Frame 2: |ΔY| = 0.5 on each pixel, over the mean 1.
        change.add(2, &[[0.5; 3], [1.5; 3]]);
        assert!((change.mean() - 0.5).abs() < 1e-9);
    }

    /// A 16×1 strip of pixels seeing the points x = 0…15 of a line at z = 0 on triangle 1,
    /// through a camera that maps x to pixel x - `shift`.
    fn strip(shift: f32) -> (Vec<[f32; 4]>, Mat4) {
        let surface = (0..16).map(|i| [i as f32 + shift, 0.0, 0.0, 1.0]).collect();
        // NDC x = 2 (x + 0.5) / 16 - 1 maps the point x to the centre of pixel x.
        let view_proj = Mat4::from_translation(Vec3::new(-1.0 + 1.0 / 16.0, 0.0, 0.0))
            * Mat4::from_scale(Vec3::new(2.0 / 16.0, 1.0, 1.0));
        let view_proj = view_proj * Mat4::from_translation(Vec3::new(-shift, 0.0, 0.0));
        (surface, view_proj)
    }

    /// What the strip's camera sees: `image` on `surface`.
    fn strip_frame<'a>(image: &'a [[f32; 3]], surface: &'a [[f32; 4]], view_proj: Mat4) -> SeenFrame<'a> {
        SeenFrame { image, surface, view_proj, camera: Vec3::new(0.0, 0.0, -10.0), width: 16, height: 1 }
    }

    #[test]
    fn surface_flicker_follows_the_surface_and_not_the_screen() {
        // Luminance bound to the surface: the point x has luminance x + 1.
        let shade = |surface: &[[f32; 4]]| -> Vec<[f32; 3]> { surface.iter().map(|s| [s[0] + 1.0; 3]).collect() };
        let mut screen = ScreenFlicker::new(0);
        let mut on_surfaces = SurfaceFlicker::new(0);
        for (k, shift) in [0.0, 1.0, 2.0].into_iter().enumerate() {
            let (surface, view_proj) = strip(shift);
            let image = shade(&surface);
            screen.add(k as u32, &image);
            on_surfaces.add(k as u32, strip_frame(&image, &surface, view_proj));
        }
        // The view slid by a pixel a frame: every pixel changed on the screen, no surface did.
        assert!(screen.mean() > 0.05);
        assert!(on_surfaces.mean() < 1e-5, "{}", on_surfaces.mean());
        // The light doubles: every surface point changes by its luminance.
        let (surface, view_proj) = strip(3.0);
        let image: Vec<[f32; 3]> = shade(&surface).iter().map(|p| [2.0 * p[0]; 3]).collect();
        let mut doubled = SurfaceFlicker::new(0);
        doubled.last = on_surfaces.last.take();
        doubled.add(3, strip_frame(&image, &surface, view_proj));
        assert!((doubled.mean() - 0.5).abs() < 1e-6, "{}", doubled.mean());
    }
}
