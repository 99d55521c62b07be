//! The charts: error (log) against frame time (log), one series per method × backend, as SVG
//! and PNG. Colour tells the method, marker and line style the backend (ray queries: circles,
//! solid line; compute BVH: triangles, dashed line), marker size the gather radius. Each
//! series' line joins its Pareto front: the points with a lower error than every faster point
//! of the series, i.e. the best error that series reaches within a time budget.
//!
//! PNG text is drawn by plotters' `ab_glyph` feature with DejaVu Sans compiled into the binary
//! (`assets/`, see its README), so no system font is needed; the SVG names `sans-serif`.

use std::path::Path;
use std::sync::Once;

use plotters::chart::MeshStyle;
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::FontStyle;

use super::{Point, SceneChart};
use leakless::error::{RenderError, Result};
use leakless::trace::Backend;
use leakless::Method;

/// DejaVu Sans, cut down to the characters a chart uses (`assets/README.md`).
static FONT: &[u8] = include_bytes!("../../../../../assets/DejaVuSans-subset.ttf");
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

/// Which error a chart plots.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Metric {
    RelMse,
    RelMseDark,
    Rmse,
    RmseDark,
}

impl Metric {
    pub const ALL: [Metric; 4] = [Metric::RelMse, Metric::RelMseDark, Metric::Rmse, Metric::RmseDark];

    /// The value of a point, if it has a finite one (≥ 0: the chart shows 0 on a floor line
    /// below the log axis' range).
    pub fn value(self, p: &Point) -> Option<f64> {
        let e = &p.errors;
        let v = match self {
            Metric::RelMse => e.relmse,
            Metric::RelMseDark => e.relmse_dark,
            Metric::Rmse => e.rmse,
            Metric::RmseDark => e.rmse_dark,
        }?;
        (v.is_finite() && v >= 0.0).then_some(v)
    }

    /// Output file suffix: `PREFIX-<scene>-<suffix>.svg`.
    pub fn file_suffix(self) -> &'static str {
        match self {
            Metric::RelMse => "relmse",
            Metric::RelMseDark => "relmse-dark",
            Metric::Rmse => "rmse",
            Metric::RmseDark => "rmse-dark",
        }
    }

    /// What the chart's title calls it.
    pub fn name(self) -> &'static str {
        match self {
            Metric::RelMse => "relMSE",
            Metric::RelMseDark => "relMSE of the dark pixels",
            Metric::Rmse => "RMSE",
            Metric::RmseDark => "RMSE of the dark pixels",
        }
    }

    /// The y-axis description.
    pub fn axis_label(self) -> &'static str {
        match self {
            Metric::RelMse => "relMSE vs reference, all pixels",
            Metric::RelMseDark => "relMSE vs reference, dark pixels",
            Metric::Rmse => "RMSE vs reference, all pixels",
            Metric::RmseDark => "RMSE vs reference, dark pixels",
        }
    }
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

struct MetricChart<'a>(&'a SceneChart, Metric);

impl Drawing for MetricChart<'_> {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> DrawResult<DB> {
        draw(root, self.0, self.1)
    }
}

/// Writes `chart`'s `metric` against frame time as an SVG and a PNG, both `size` pixels.
pub fn plot(chart: &SceneChart, metric: Metric, svg: &Path, png: &Path, size: (u32, u32)) -> Result<()> {
    write_svg_png(&MetricChart(chart, metric), svg, png, size)
}

/// One method × backend: its points (x = frame ms, y = error, radius).
struct Series {
    method: Method,
    backend: Backend,
    points: Vec<(f64, f64, Option<f32>)>,
}

fn series(chart: &SceneChart, metric: Metric) -> Vec<Series> {
    let mut out: Vec<Series> = Vec::new();
    for p in &chart.points {
        let Some(y) = metric.value(p) else { continue };
        if !(p.frame_ms.is_finite() && p.frame_ms > 0.0) {
            continue;
        }
        let i = match out.iter().position(|s| s.method == p.method && s.backend == p.backend) {
            Some(i) => i,
            None => {
                out.push(Series { method: p.method, backend: p.backend, points: vec![] });
                out.len() - 1
            }
        };
        out[i].points.push((p.frame_ms, y, p.radius));
    }
    out
}

/// The points with a lower error than every faster point, fastest first.
fn pareto_front(points: &[(f64, f64, Option<f32>)]) -> Vec<(f64, f64)> {
    let mut sorted: Vec<(f64, f64)> = points.iter().map(|p| (p.0, p.1)).collect();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let mut best = f64::INFINITY;
    sorted.into_iter().filter(|p| (p.1 < best).then(|| best = p.1).is_some()).collect()
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
    // Short ranges: the densest set, however many, rather than fewer than two labels.
    let bold = if bold.len() < 2 { candidates[0].clone() } else { bold };
    let light = if k1 - k0 <= 8 { at(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0], 1) } else { at(&[1.0], 1) };
    (bold, light)
}

pub(super) type DrawResult<DB> = std::result::Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

fn draw<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, chart: &SceneChart, metric: Metric) -> DrawResult<DB> {
    root.fill(&WHITE)?;
    let (w, h) = root.dim_in_pixel();
    // Text and marks scale with the chart; 800×600 is the design size.
    let k = (w as f64 / 800.0).min(h as f64 / 600.0).max(0.4);
    let px = |v: f64| ((v * k).round() as i32).max(1);
    let font = |v: f64| (FAMILY, (v * k).max(7.0));
    let grey = RGBColor(90, 90, 90);

    let foot_h = (2.9 * font(12.0).1) as u32;
    let (main, foot) = root.split_vertically(h.saturating_sub(foot_h));
    let title = format!("{}: {} against frame time", chart.scene, metric.name());
    let main = main.titled(&title, font(21.0))?;
    let legend_w = px(205.0) as u32;
    let (plot_area, legend_area) = main.split_horizontally(w.saturating_sub(legend_w));

    let series = series(chart, metric);
    let all = || series.iter().flat_map(|s| s.points.iter());
    // Every point's time, plotted or not: a scene's charts share their x axis.
    let x_range = log_range(chart.points.iter().map(|p| p.frame_ms).filter(|t| t.is_finite() && *t > 0.0));
    let positive = log_range(all().map(|p| p.1).filter(|y| *y > 0.0));
    let (x_bold, x_light) = log_ticks(&x_range, 7);
    let (mut y_bold, y_light) = log_ticks(&positive, 9);
    // Exact results (error 0, e.g. no leak where the reference is black) sit on a floor line
    // labelled 0, a third of a decade below the positive values.
    let zero_at = all().any(|p| p.1 == 0.0).then(|| positive.start / 10f64.powf(1.0 / 3.0));
    let y_range = match zero_at {
        Some(z) => {
            y_bold.insert(0, z);
            z / 10f64.powf(0.06)..positive.end
        }
        None => positive,
    };
    let y_at = |y: f64| if y > 0.0 { y } else { zero_at.unwrap_or(y) };
    let y_tick = |v: &f64| match zero_at {
        Some(z) if (v / z - 1.0).abs() < 1e-9 => "0".to_string(),
        _ => tick(*v),
    };
    let mut radii: Vec<f32> = chart.points.iter().filter_map(|p| p.radius).collect();
    radii.sort_by(f32::total_cmp);
    radii.dedup();
    let marker = |r: Option<f32>| -> i32 {
        let rank = r.and_then(|r| radii.iter().position(|x| *x == r));
        match (rank, radii.len()) {
            (Some(i), n) if n > 1 => px(3.0 + 4.0 * i as f64 / (n - 1) as f64),
            _ => px(5.0),
        }
    };

    let mut cc = ChartBuilder::on(&plot_area)
        .margin(px(10.0))
        .x_label_area_size(px(46.0))
        .y_label_area_size(px(64.0))
        .build_cartesian_2d(
            x_range.log_scale().with_key_points(x_bold).with_light_points(x_light),
            y_range.log_scale().with_key_points(y_bold).with_light_points(y_light),
        )?;
    let x_desc = if chart.cpu_device { "frame time, ms (CPU time on this CPU device)" } else { "frame time, ms" };
    grey_grid(
        cc.configure_mesh()
            .x_desc(x_desc)
            .y_desc(metric.axis_label())
            .x_label_formatter(&|v| tick(*v))
            .y_label_formatter(&y_tick),
        font(13.0),
        font(14.0),
    )
    .draw()?;

    for s in &series {
        let colour = method_colour(s.method);
        let line = colour.stroke_width(px(2.0) as u32);
        let front: Vec<(f64, f64)> = pareto_front(&s.points).into_iter().map(|(x, y)| (x, y_at(y))).collect();
        match s.backend {
            Backend::RayQuery => {
                cc.draw_series(LineSeries::new(front, line))?;
                cc.draw_series(
                    s.points.iter().map(|&(x, y, r)| Circle::new((x, y_at(y)), marker(r), colour.filled())),
                )?;
            }
            Backend::Compute => {
                cc.draw_series(DashedLineSeries::new(front, px(7.0), px(4.0), line))?;
                cc.draw_series(
                    s.points.iter().map(|&(x, y, r)| TriangleMarker::new((x, y_at(y)), marker(r) + 1, colour.filled())),
                )?;
            }
        }
    }
    if series.is_empty() {
        let why: &[&str] = match metric {
            Metric::RelMseDark | Metric::RmseDark if chart.dark_pixels == 0 => &["no dark pixels in the reference"],
            Metric::RelMse | Metric::RelMseDark if chart.reference_mean <= 0.0 => &[
                "the reference is black here:",
                "relative errors are undefined",
                "(the RMSE charts measure the leaks)",
            ],
            _ => &["no point with a positive, finite error"],
        };
        let (pw, ph) = plot_area.dim_in_pixel();
        for (i, line) in why.iter().enumerate() {
            let at = (pw as i32 / 2, ph as i32 / 2 + i as i32 * px(24.0));
            let style = TextStyle::from(font(16.0)).pos(Pos::new(HPos::Center, VPos::Center));
            plot_area.draw(&Text::new(*line, at, style))?;
        }
    }

    // The legend, beside the plot: series, then what marker size and lines mean.
    let text = |s: String, x: i32, y: i32, size: f64| {
        Text::new(s, (x, y), TextStyle::from(font(size)).pos(Pos::new(HPos::Left, VPos::Center)))
    };
    let row = px(21.0);
    let (x0, mut y) = (px(4.0), px(22.0));
    let (seg, tx) = (px(11.0), px(32.0));
    let sym_x = x0 + seg;
    for s in &series {
        let colour = method_colour(s.method);
        let line = colour.stroke_width(px(2.0) as u32);
        let ends = vec![(x0, y), (x0 + 2 * seg, y)];
        match s.backend {
            Backend::RayQuery => {
                legend_area.draw(&PathElement::new(ends, line))?;
                legend_area.draw(&Circle::new((sym_x, y), px(4.0), colour.filled()))?;
            }
            Backend::Compute => {
                legend_area.draw(&DashedPathElement::new(ends, px(5.0), px(3.0), line))?;
                legend_area.draw(&TriangleMarker::new((sym_x, y), px(5.0), colour.filled()))?;
            }
        }
        legend_area.draw(&text(format!("{} ({})", s.method.name(), s.backend.name()), tx, y, 13.0))?;
        y += row;
    }
    if radii.len() > 1 {
        y += row / 2;
        legend_area.draw(&text("gather radius".into(), x0, y, 13.0))?;
        for r in &radii {
            y += row;
            legend_area.draw(&Circle::new((sym_x, y), marker(Some(*r)), grey.filled()))?;
            let auto = r / chart.auto_radius;
            legend_area.draw(&text(format!("{} ({}× auto)", tick(*r as f64), tick(auto as f64)), tx, y, 12.0))?;
        }
    }
    if !series.is_empty() {
        y += row * 3 / 2;
        legend_area.draw(&text("lines: Pareto front".into(), x0, y, 12.0))?;
        legend_area.draw(&text("(least error so far".into(), x0, y + row * 4 / 5, 12.0))?;
        legend_area.draw(&text("at that frame time)".into(), x0, y + row * 8 / 5, 12.0))?;
    }

    let lines = [
        format!(
            "{}×{}; reference: path tracer, {} spp; dark (indirect ≤ {}× mean): {} of {} pixels; {}",
            chart.width,
            chart.height,
            chart.ref_spp,
            tick(chart.dark_fraction),
            chart.dark_pixels,
            chart.covered_pixels,
            chart.device
        ),
        "frame time: wall times of the passes of the 2nd frame, each submitted alone, summed".to_string(),
    ];
    let style = TextStyle::from(font(11.5)).color(&grey);
    for (i, line) in lines.iter().enumerate() {
        let y = (i as f64 * 1.3 * font(11.5).1) as i32 + px(4.0);
        foot.draw(&Text::new(line.as_str(), (px(10.0), y), style.clone()))?;
    }
    root.present()?;
    Ok(())
}

/// A white chart with a one-line `caption` along its foot; the area above it, to draw in.
pub(super) fn captioned<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    caption: &str,
) -> std::result::Result<DrawingArea<DB, Shift>, DrawingAreaErrorKind<DB::ErrorType>> {
    root.fill(&WHITE)?;
    let h = root.dim_in_pixel().1;
    let (main, foot) = root.split_vertically(h.saturating_sub(26));
    foot.draw(&Text::new(caption.to_string(), (12, 4), (FAMILY, 13.0).into_font().color(&RGBColor(90, 90, 90))))?;
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
    fn pareto() {
        let p = |x, y| (x, y, None);
        let front = pareto_front(&[p(3.0, 0.5), p(1.0, 1.0), p(2.0, 2.0), p(4.0, 0.1), p(5.0, 0.2)]);
        assert_eq!(front, [(1.0, 1.0), (3.0, 0.5), (4.0, 0.1)]);
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
        // Nothing labelled in range at 1-2-3-5: the densest set anyway, never panics.
        let (bold, _) = log_ticks(&(6.0..9.0), 7);
        assert!(bold.is_empty());
        // Twelve decades: every other or third power.
        let (bold, _) = log_ticks(&(1e-6..1e6), 7);
        assert!(bold.len() <= 7 && bold.len() >= 4, "{bold:?}");
    }

    #[test]
    fn font_parses() {
        register_font();
    }
}
