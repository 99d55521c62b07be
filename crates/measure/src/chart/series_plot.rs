//! The convergence charts of `chart --series`: one error against wall time, log–log, one line
//! per method through its checkpoints (1, 2, 4, … frames or spp), as SVG and PNG.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::drawing::{
    draw_legend, grey_grid, log_axis, log_range, log_ticks, method_colour, tick, titled_with_foot, write_svg_png,
    DrawResult, Drawing, GREY,
};
use super::series::{SceneSeries, SeriesPoint, SERIES_METHODS};
use leakless::error::Result;

/// An error of a checkpoint.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SeriesMetric {
    RelMse,
    Flip,
}

impl SeriesMetric {
    pub const ALL: [SeriesMetric; 2] = [SeriesMetric::RelMse, SeriesMetric::Flip];

    pub fn value(self, p: &SeriesPoint) -> Option<f64> {
        match self {
            SeriesMetric::RelMse => p.relmse,
            SeriesMetric::Flip => Some(p.flip),
        }
        .filter(|v| v.is_finite() && *v > 0.0)
    }

    pub fn file_suffix(self) -> &'static str {
        match self {
            SeriesMetric::RelMse => "relmse",
            SeriesMetric::Flip => "flip",
        }
    }

    fn name(self) -> &'static str {
        match self {
            SeriesMetric::RelMse => "relMSE",
            SeriesMetric::Flip => "HDR-FLIP",
        }
    }
}

struct SeriesChart<'a>(&'a SceneSeries, SeriesMetric);

/// Writes `series`' `metric` against wall time as an SVG and a PNG, both `size` pixels.
pub fn plot_series(series: &SceneSeries, metric: SeriesMetric, svg: &Path, png: &Path, size: (u32, u32)) -> Result<()> {
    write_svg_png(&SeriesChart(series, metric), svg, png, size)
}

impl Drawing for SeriesChart<'_> {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> DrawResult<DB> {
        let (series, metric) = (self.0, self.1);
        let title = format!("{}: {} against wall time", series.scene, metric.name());
        // Three lines: the settings, leakless's partial disks, then the truth and the device.
        let (scale, _, main, foot) = titled_with_foot(&root, &title, 4.25)?;
        let (px, font) = (|v| scale.px(v), |v| scale.font(v));

        let points = |m| {
            series
                .points
                .iter()
                .filter(move |p| p.method == m)
                .filter_map(|p| metric.value(p).map(|v| (p.wall_ms / 1e3, v, p.frames)))
        };
        let x_range = log_range(series.points.iter().map(|p| p.wall_ms / 1e3).filter(|t| *t > 0.0));
        let y_range = log_range(SERIES_METHODS.iter().flat_map(|&m| points(m).map(|p| p.1)));
        let (x_bold, x_light) = log_ticks(&x_range, 7);
        let (y_bold, y_light) = log_ticks(&y_range, 9);
        let mut cc = ChartBuilder::on(&main)
            .margin(px(12.0))
            .x_label_area_size(px(46.0))
            .y_label_area_size(px(64.0))
            .build_cartesian_2d(log_axis(x_range, (x_bold, x_light)), log_axis(y_range, (y_bold, y_light)))?;
        grey_grid(
            cc.configure_mesh()
                .x_desc("wall time, s (accumulating while the view is still)")
                .y_desc(metric.name())
                .x_label_formatter(&|v| tick(*v))
                .y_label_formatter(&|v| tick(*v)),
            font(13.0),
            font(14.0),
        )
        .draw()?;
        for method in SERIES_METHODS {
            let colour = method_colour(method);
            let line: Vec<(f64, f64)> = points(method).map(|p| (p.0, p.1)).collect();
            if line.is_empty() {
                continue;
            }
            // The points sit at 1, 2, 4, … frames; the reference's are labelled with its samples.
            let unit = if method.splats() { "frames 1, 2, 4 …" } else { "spp after frames 1, 2, 4 …" };
            cc.draw_series(LineSeries::new(line.clone(), colour.stroke_width(px(2.0) as u32)))?
                .label(format!("{} ({unit})", method.name()))
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2)));
            cc.draw_series(line.iter().map(|&p| Circle::new(p, px(3.5), colour.filled())))?;
            // Label the first and last checkpoints with their frame or sample counts.
            let all: Vec<_> = points(method).collect();
            for p in [all.first(), all.last()].into_iter().flatten() {
                let style = TextStyle::from(font(11.0)).color(&colour).pos(Pos::new(HPos::Left, VPos::Bottom));
                cc.draw_series(std::iter::once(Text::new(format!("{}", p.2), (p.0, p.1), style)))?;
            }
        }
        draw_legend(&mut cc, SeriesLabelPosition::UpperRight, 13.0)?;
        let settings = format!(
            "{}×{}; batches of {} paths; {}, shrinking from {}× it after frame 1",
            series.width,
            series.height,
            series.paths,
            series.radius_label(),
            leakless::splatting::ACCUMULATION_RADIUS_SCALE,
        );
        let partial = format!(
            "leakless's partial disks: grown up to {}× the radius in frame 1, shrunk down to {}× it after",
            leakless::splatting::MAX_RADIUS_SHARE,
            leakless::splatting::MIN_RADIUS_SHARE,
        );
        let truth =
            format!("truth: {} jittered frames × {} spp; {}", series.truth_frames, series.truth_spp, series.device);
        let style = TextStyle::from(font(11.5)).color(&GREY);
        let line = (1.35 * font(12.0).1) as i32;
        for (k, text) in [settings, partial, truth].into_iter().enumerate() {
            foot.draw(&Text::new(text, (px(10.0), px(2.0) + k as i32 * line), style.clone()))?;
        }
        root.present()?;
        Ok(())
    }
}
