//! The charts: error (log) against frame time (log), one series per method × backend, as SVG
//! and PNG. Colour tells the method, marker and line style the backend (ray queries: circles,
//! solid line; compute BVH: triangles, dashed line), marker size the gather radius. Each
//! series' line joins its Pareto front: the points with a lower error than every faster point
//! of the series, i.e. the best error that series reaches within a time budget.

use std::path::Path;

use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::drawing::{
    grey_grid, log_axis, log_range, log_ticks, method_colour, tick, titled_with_foot, write_svg_png, DrawResult,
    Drawing, GREY,
};
use super::{Point, SceneChart};
use leakless::error::Result;
use leakless::trace::Backend;
use leakless::Method;

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

struct MetricChart<'a>(&'a SceneChart, Metric);

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

impl Drawing for MetricChart<'_> {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> DrawResult<DB> {
        let (chart, metric) = (self.0, self.1);
        let title = format!("{}: {} against frame time", chart.scene, metric.name());
        let (scale, w, main, foot) = titled_with_foot(&root, &title, 2.9)?;
        let (px, font) = (|v| scale.px(v), |v| scale.font(v));
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
            .build_cartesian_2d(log_axis(x_range, (x_bold, x_light)), log_axis(y_range, (y_bold, y_light)))?;
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
                        s.points
                            .iter()
                            .map(|&(x, y, r)| TriangleMarker::new((x, y_at(y)), marker(r) + 1, colour.filled())),
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
                legend_area.draw(&Circle::new((sym_x, y), marker(Some(*r)), GREY.filled()))?;
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
        let style = TextStyle::from(font(11.5)).color(&GREY);
        for (i, line) in lines.iter().enumerate() {
            let y = (i as f64 * 1.3 * font(11.5).1) as i32 + px(4.0);
            foot.draw(&Text::new(line.as_str(), (px(10.0), y), style.clone()))?;
        }
        root.present()?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pareto() {
        let p = |x, y| (x, y, None);
        let front = pareto_front(&[p(3.0, 0.5), p(1.0, 1.0), p(2.0, 2.0), p(4.0, 0.1), p(5.0, 0.2)]);
        assert_eq!(front, [(1.0, 1.0), (3.0, 0.5), (4.0, 0.1)]);
    }
}
