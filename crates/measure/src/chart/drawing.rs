//! What every chart draws with: the compiled-in font, the grey grid, log axes and their tick
//! labels, the methods' colours, lines and legends, the caption, and the output to SVG and PNG
//! from one drawing.
//!
//! PNG text is drawn by plotters' `ab_glyph` feature with DejaVu Sans compiled into the binary
//! (`assets/`, see its README), so no system font is needed; the SVG names `sans-serif`.

use std::path::Path;
use std::sync::Once;

use plotters::chart::MeshStyle;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::FontStyle;

use leakless::error::{RenderError, Result};
use leakless::Method;

/// DejaVu Sans, cut down to the characters a chart uses (`assets/README.md`).
static FONT: &[u8] = include_bytes!("../../../../assets/DejaVuSans-subset.ttf");
pub(super) const FAMILY: &str = "sans-serif";

pub(super) fn register_font() {
    static REGISTER: Once = Once::new();
    REGISTER.call_once(|| {
        // The font is compiled in: a parse failure is a build defect, caught by the tests.
        if plotters::style::register_font(FAMILY, FontStyle::Normal, FONT).is_err() {
            panic!("the compiled-in chart font does not parse");
        }
    });
}

/// The charts' grid: light and bold lines in greys, labels and axis titles in the chart font.
pub(super) fn grey_grid<'m, 'a, 'b, X: Ranged, Y: Ranged, DB: DrawingBackend>(
    mesh: &'m mut MeshStyle<'a, 'b, X, Y, DB>,
    labels: impl IntoTextStyle<'b>,
    titles: impl IntoTextStyle<'b>,
) -> &'m mut MeshStyle<'a, 'b, X, Y, DB> {
    mesh.label_style(labels)
        .axis_desc_style(titles)
        .light_line_style(RGBColor(238, 238, 238))
        .bold_line_style(RGBColor(200, 200, 200))
}

/// Refuses a chart size too small to read or too large to hold.
pub fn check_size(size: (u32, u32)) -> Result<()> {
    if size.0 < 200 || size.1 < 150 || size.0 > 8192 || size.1 > 8192 {
        return Err(RenderError::Settings(format!(
            "--chart-size {}x{} must be within 200x150..=8192x8192",
            size.0, size.1
        )));
    }
    Ok(())
}

/// A chart that can be drawn on any plotters backend (SVG and bitmap alike).
pub(super) trait Drawing {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> DrawResult<DB>;
}

/// Draws `drawing` into an SVG and a PNG, both `size` pixels.
pub(super) fn write_svg_png(drawing: &impl Drawing, svg: &Path, png: &Path, size: (u32, u32)) -> Result<()> {
    check_size(size)?;
    register_font();
    let fail = |path: &Path, e: &dyn std::fmt::Display| RenderError::Output {
        path: path.display().to_string(),
        message: e.to_string(),
    };
    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, size).into_drawing_area();
        drawing.draw(root).map_err(|e| fail(svg, &e))?;
    }
    std::fs::write(svg, text).map_err(|e| fail(svg, &e))?;
    let mut rgb = vec![0u8; size.0 as usize * size.1 as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area();
        drawing.draw(root).map_err(|e| fail(png, &e))?;
    }
    image::save_buffer(png, &rgb, size.0, size.1, image::ExtendedColorType::Rgb8).map_err(|e| fail(png, &e))
}

pub(super) fn method_colour(method: Method) -> RGBColor {
    match method.name() {
        "splat" => RGBColor(214, 39, 40),
        "leakless-capped" => RGBColor(230, 130, 0),
        "leakless" => RGBColor(31, 119, 180),
        "direct" => RGBColor(110, 110, 110),
        _ => RGBColor(148, 103, 189),
    }
}

/// A log axis range around `values`, padded a little; a decade around a single value.
pub(super) fn log_range(values: impl Iterator<Item = f64>) -> std::ops::Range<f64> {
    let (lo, hi) = values.fold((f64::INFINITY, 0.0f64), |(lo, hi), v| (lo.min(v), hi.max(v)));
    if !(lo.is_finite() && lo > 0.0) {
        return 0.1..10.0;
    }
    let (lo, hi) = if hi / lo < 1.5 { (lo / 2.0, hi * 2.0) } else { (lo, hi) };
    let pad = (hi / lo).powf(0.06);
    lo / pad..hi * pad
}

/// A tick label: plain decimals from 0.001 to 99999, else `1e-5`.
pub(super) fn tick(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 {
        return "0".into();
    }
    if (1e-3..1e5).contains(&a) {
        let decimals = (2.0 - a.log10().floor()).clamp(0.0, 5.0) as usize;
        let s = format!("{v:.decimals$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        let e = a.log10().floor();
        let m = v / 10f64.powf(e);
        if (m - m.round()).abs() < 1e-6 {
            format!("{}e{}", m.round(), e)
        } else {
            format!("{m:.1}e{e}")
        }
    }
}

/// Ticks of a log axis over `range`: labelled ticks at 1, 1–2–5, or 1–2–3–5 × 10^k (the
/// densest that gives at most `max` labels; every decade or every other when even powers of
/// ten are too many), grid lines at 1…9 × 10^k.
pub(super) fn log_ticks(range: &std::ops::Range<f64>, max: usize) -> (Vec<f64>, Vec<f64>) {
    let (lo, hi) = (range.start, range.end);
    let within = |v: &f64| *v >= lo * (1.0 - 1e-9) && *v <= hi * (1.0 + 1e-9);
    let (k0, k1) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    let at = |mantissas: &[f64], step: usize| -> Vec<f64> {
        (k0..=k1)
            .filter(|k| k.rem_euclid(step as i32) == 0)
            .flat_map(|k| mantissas.iter().map(move |m| m * 10f64.powi(k)))
            .filter(within)
            .collect()
    };
    let candidates =
        [at(&[1.0, 2.0, 3.0, 5.0], 1), at(&[1.0, 2.0, 5.0], 1), at(&[1.0], 1), at(&[1.0], 2), at(&[1.0], 3)];
    let bold = candidates.iter().find(|c| c.len() <= max).cloned().unwrap_or_else(|| candidates[4].clone());
    // Short ranges: the densest set, however many, rather than fewer than two labels; where
    // even that has fewer (1032–1570 MiB: no 1-2-3-5 value inside), evenly spaced values.
    let bold = match bold.len() {
        0 | 1 if candidates[0].len() >= 2 => candidates[0].clone(),
        0 | 1 => linear_ticks(lo, hi, max),
        _ => bold,
    };
    let light = if k1 - k0 <= 8 { at(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0], 1) } else { at(&[1.0], 1) };
    (bold, light)
}

/// Multiples of the smallest 1-2-5 step that puts at most `max` (and at least two, where the
/// range is not empty) within `lo..=hi`.
fn linear_ticks(lo: f64, hi: f64, max: usize) -> Vec<f64> {
    if !(hi > lo && lo.is_finite() && hi.is_finite()) {
        return Vec::new();
    }
    let mut k = ((hi - lo) / max.max(2) as f64).log10().floor() as i32 - 1;
    loop {
        for m in [1.0, 2.0, 5.0] {
            let step = m * 10f64.powi(k);
            let (first, last) = ((lo / step).ceil() as i64, (hi / step).floor() as i64);
            if last - first < max.max(2) as i64 {
                return (first..=last).map(|i| i as f64 * step).collect();
            }
        }
        k += 1;
    }
}

/// How text and marks scale with a chart's size, against the size it was designed at.
#[derive(Clone, Copy)]
pub(super) struct Scale(f64);

impl Scale {
    /// Clears `root` to white; its scale against the design size `design`, and its size.
    pub(super) fn clear<DB: DrawingBackend>(
        root: &DrawingArea<DB, Shift>,
        design: (f64, f64),
    ) -> std::result::Result<(Scale, u32, u32), DrawingAreaErrorKind<DB::ErrorType>> {
        root.fill(&WHITE)?;
        let (w, h) = root.dim_in_pixel();
        Ok((Scale((w as f64 / design.0).min(h as f64 / design.1).max(0.4)), w, h))
    }

    /// `v` design pixels, at least one.
    pub(super) fn px(self, v: f64) -> i32 {
        ((v * self.0).round() as i32).max(1)
    }

    /// The charts' font at `v` design points, never below 7.
    pub(super) fn font(self, v: f64) -> (&'static str, f64) {
        (FAMILY, (v * self.0).max(7.0))
    }
}

/// A log axis over `range` with bold and light ticks (see [`log_ticks`]).
pub(super) fn log_axis(
    range: std::ops::Range<f64>,
    (bold, light): (Vec<f64>, Vec<f64>),
) -> plotters::coord::combinators::WithKeyPoints<plotters::coord::combinators::LogCoord<f64>> {
    range.log_scale().with_key_points(bold).with_light_points(light)
}

/// The grey of notes and reference marks.
pub(super) const GREY: RGBColor = RGBColor(90, 90, 90);

/// A chart at the design size 800×600: `root` cleared and split into the main area, titled
/// `title`, and a foot `foot_lines` 12-point lines high for notes. Returns the scale, the
/// width, the main area and the foot.
#[allow(clippy::type_complexity)]
pub(super) fn titled_with_foot<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    foot_lines: f64,
) -> std::result::Result<
    (Scale, u32, DrawingArea<DB, Shift>, DrawingArea<DB, Shift>),
    DrawingAreaErrorKind<DB::ErrorType>,
> {
    let (scale, w, h) = Scale::clear(root, (800.0, 600.0))?;
    let (main, foot) = root.split_vertically(h.saturating_sub((foot_lines * scale.font(12.0).1) as u32));
    Ok((scale, w, main.titled(title, scale.font(21.0))?, foot))
}

pub(super) type DrawResult<DB> = std::result::Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

/// A white chart with a one-line `caption` along its foot; the area above it, to draw in.
pub(super) fn captioned<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    caption: &str,
) -> std::result::Result<DrawingArea<DB, Shift>, DrawingAreaErrorKind<DB::ErrorType>> {
    root.fill(&WHITE)?;
    let h = root.dim_in_pixel().1;
    let (main, foot) = root.split_vertically(h.saturating_sub(26));
    foot.draw(&Text::new(caption.to_string(), (12, 4), (FAMILY, 13.0).into_font().color(&GREY)))?;
    Ok(main)
}

/// The legend of `cc`'s labelled series, at `position`, in the charts' one style.
pub(super) fn draw_legend<'a, DB: DrawingBackend + 'a, CT: plotters::coord::CoordTranslate>(
    cc: &mut ChartContext<'a, DB, CT>,
    position: SeriesLabelPosition,
    font_size: f64,
) -> DrawResult<DB> {
    cc.configure_series_labels()
        .position(position)
        .label_font((FAMILY, font_size))
        .background_style(WHITE.mix(0.85))
        .border_style(RGBColor(200, 200, 200))
        .draw()
}

/// One labelled line of `points` in `colour`, solid or dashed, with its legend entry.
pub(super) fn draw_line<'a, DB: DrawingBackend + 'a, CT: plotters::coord::CoordTranslate<From = (f64, f64)>>(
    cc: &mut ChartContext<'a, DB, CT>,
    points: Vec<(f64, f64)>,
    colour: RGBColor,
    dashed: bool,
    label: String,
) -> DrawResult<DB> {
    let style = colour.stroke_width(2);
    if dashed {
        cc.draw_series(DashedLineSeries::new(points, 6, 4, style))?
    } else {
        cc.draw_series(LineSeries::new(points, style))?
    }
    .label(label)
    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2)));
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks() {
        assert_eq!(tick(1.0), "1");
        assert_eq!(tick(10.0), "10");
        assert_eq!(tick(250.0), "250");
        assert_eq!(tick(0.5), "0.5");
        assert_eq!(tick(0.02), "0.02");
        assert_eq!(tick(0.001), "0.001");
        assert_eq!(tick(1e-4), "1e-4");
        assert_eq!(tick(3e-5), "3e-5");
        assert_eq!(tick(1e6), "1e6");
    }

    #[test]
    fn ranges() {
        let r = log_range([1.0, 100.0].into_iter());
        assert!(r.start < 1.0 && r.start > 0.7 && r.end > 100.0 && r.end < 140.0, "{r:?}");
        let r = log_range([5.0].into_iter());
        assert!(r.start < 2.5 && r.end > 10.0, "{r:?}");
        assert_eq!(log_range(std::iter::empty()), 0.1..10.0);
    }

    #[test]
    fn log_axis_ticks() {
        // Three decades: 1-2-5 would be 7 labels; at most 7 allowed.
        let (bold, light) = log_ticks(&(0.9..1100.0), 7);
        assert_eq!(bold, [1.0, 10.0, 100.0, 1000.0]);
        assert_eq!(light.len(), 1 + 9 * 3 + 1); // 0.9, 1…900, 1000
        let (bold, _) = log_ticks(&(0.9..1100.0), 12);
        assert_eq!(bold.len(), 10); // 1 2 5 10 20 50 100 200 500 1000
                                    // Less than a decade: 1-2-3-5.
        let (bold, _) = log_ticks(&(15.0..120.0), 7);
        assert_eq!(bold, [20.0, 30.0, 50.0, 100.0]);
        // Nothing in range at 1-2-3-5 (the H200's memory chart, 1032–1570 MiB, had no label):
        // evenly spaced labels, at most `max`, at least two.
        let (bold, _) = log_ticks(&(6.0..9.0), 7);
        assert_eq!(bold, [6.0, 6.5, 7.0, 7.5, 8.0, 8.5, 9.0]);
        let (bold, _) = log_ticks(&(1032.0..1570.0), 9);
        assert_eq!(bold, [1100.0, 1200.0, 1300.0, 1400.0, 1500.0]);
        let (bold, _) = log_ticks(&(1032.0..1570.0), 3);
        assert_eq!(bold, [1200.0, 1400.0]);
        // Twelve decades: every other or third power.
        let (bold, _) = log_ticks(&(1e-6..1e6), 7);
        assert!(bold.len() <= 7 && bold.len() >= 4, "{bold:?}");
    }

    #[test]
    fn font_parses() {
        register_font();
    }
}
