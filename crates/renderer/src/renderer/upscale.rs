//! A frame rendered smaller than its output (dynamic resolution in `render --sequence`),
//! resampled to the output's size: the layers bilinearly, each pixel read at its centre, and
//! the surfaces by the nearest pixel (a position or a triangle is not blended).

use super::readback::RenderedFrame;

/// Where output pixel `i` of `to` samples an axis of `from` pixels: the two source pixels and
/// the second's weight.
fn taps(i: u32, from: u32, to: u32) -> (usize, usize, f32) {
    let x = ((i as f32 + 0.5) * from as f32 / to as f32 - 0.5).clamp(0.0, (from - 1) as f32);
    let lo = x.floor() as usize;
    (lo, (lo + 1).min(from as usize - 1), x - lo as f32)
}

fn bilinear<const N: usize>(layer: &[[f32; N]], (w, h): (u32, u32), (to_w, to_h): (u32, u32)) -> Vec<[f32; N]> {
    let mut out = Vec::with_capacity(to_w as usize * to_h as usize);
    for y in 0..to_h {
        let (y0, y1, fy) = taps(y, h, to_h);
        for x in 0..to_w {
            let (x0, x1, fx) = taps(x, w, to_w);
            let at = |xx: usize, yy: usize| layer[yy * w as usize + xx];
            let (a, b, c, d) = (at(x0, y0), at(x1, y0), at(x0, y1), at(x1, y1));
            out.push(std::array::from_fn(|k| {
                let top = a[k] + (b[k] - a[k]) * fx;
                let bottom = c[k] + (d[k] - c[k]) * fx;
                top + (bottom - top) * fy
            }));
        }
    }
    out
}

fn nearest<T: Copy>(layer: &[T], (w, h): (u32, u32), (to_w, to_h): (u32, u32)) -> Vec<T> {
    let pick =
        |i: u32, from: u32, to: u32| (((i as f32 + 0.5) * from as f32 / to as f32) as usize).min(from as usize - 1);
    (0..to_h)
        .flat_map(|y| (0..to_w).map(move |x| (x, y)))
        .map(|(x, y)| layer[pick(y, h, to_h) * w as usize + pick(x, w, to_w)])
        .collect()
}

impl RenderedFrame {
    /// This frame at `width` × `height`; itself when it is that size already.
    pub fn resampled(self, width: u32, height: u32) -> RenderedFrame {
        if (self.width, self.height) == (width, height) {
            return self;
        }
        let (from, to) = ((self.width, self.height), (width, height));
        let display: Vec<[f32; 4]> = self.display.iter().map(|p| p.map(f32::from)).collect();
        RenderedFrame {
            width,
            height,
            radiance: bilinear(&self.radiance, from, to),
            direct: bilinear(&self.direct, from, to),
            indirect: bilinear(&self.indirect, from, to),
            leaked: bilinear(&self.leaked, from, to),
            surface: nearest(&self.surface, from, to),
            display: bilinear(&display, from, to).into_iter().map(|p| p.map(|c| c.round() as u8)).collect(),
            ..self
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A ramp doubled keeps its values at the ends and its mean, and a constant stays exactly
    /// itself; surfaces are copied, never blended.
    #[test]
    fn doubling_a_ramp_keeps_its_ends_and_its_mean() {
        let ramp: Vec<[f32; 3]> = (0..4).map(|x| [x as f32; 3]).collect();
        let out = bilinear(&ramp, (4, 1), (8, 1));
        assert_eq!(out.first().unwrap()[0], 0.0);
        assert_eq!(out.last().unwrap()[0], 3.0);
        let mean = out.iter().map(|p| p[0]).sum::<f32>() / 8.0;
        assert!((mean - 1.5).abs() < 1e-6, "{mean}");
        let constant = vec![[0.25f32; 3]; 6];
        assert!(bilinear(&constant, (3, 2), (7, 5)).iter().all(|p| *p == [0.25; 3]));
        let ids: Vec<[f32; 4]> = (0..4).map(|i| [0.0, 0.0, 0.0, i as f32]).collect();
        let picked = nearest(&ids, (2, 2), (4, 4));
        assert!(picked.iter().all(|p| ids.contains(p)));
        assert_eq!(picked[0], ids[0]);
        assert_eq!(picked[15], ids[3]);
    }
}
