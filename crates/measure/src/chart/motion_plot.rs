//! The chart of `bench motion`: each displayed frame's error against the path tracer's image
//! of the same time and view, against the frame's index: relMSE (left) and HDR-FLIP (right),
//! log scale, one colour per scene, reuse on solid and off dashed.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::drawing::{
    captioned, draw_legend, draw_line, grey_grid, log_axis, log_range, log_ticks, tick, write_svg_png, DrawResult,
    Drawing, FAMILY,
};
use leakless::error::Result;

/// One scene's run with reuse on or off: per frame, (relMSE, HDR-FLIP).
#[derive(Clone, Debug)]
pub struct MotionRun {
    pub scene: String,
    pub reuse: bool,
    pub errors: Vec<(f64, f64)>,
}

struct MotionChart<'a> {
    runs: &'a [MotionRun],
    caption: &'a str,
}

impl Drawing for MotionChart<'_> {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> DrawResult<DB> {
        draw(root, self)
    }
}

/// Writes the chart of `runs` as an SVG and a PNG; `caption` says how they were made.
pub fn plot_motion(runs: &[MotionRun], caption: &str, svg: &Path, png: &Path) -> Result<()> {
    write_svg_png(&MotionChart { runs, caption }, svg, png, (1200, 520))
}

const COLOURS: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(23, 190, 207),
];

fn panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    runs: &[MotionRun],
    value: fn(&(f64, f64)) -> f64,
) -> DrawResult<DB> {
    let font = |v: f64| (FAMILY, v);
    let area = area.titled(title, font(18.0))?;
    let frames = runs.iter().map(|r| r.errors.len()).max().unwrap_or(1).max(2);
    let y_range = log_range(runs.iter().flat_map(|r| r.errors.iter().map(value)).filter(|v| *v > 0.0));
    let (y_bold, y_light) = log_ticks(&y_range, 9);
    let mut cc = ChartBuilder::on(&area)
        .margin(12)
        .x_label_area_size(44)
        .y_label_area_size(60)
        .build_cartesian_2d(0.0..(frames - 1) as f64, log_axis(y_range, (y_bold, y_light)))?;
    grey_grid(
        cc.configure_mesh()
            .x_desc("frame")
            .y_desc(title)
            .x_label_formatter(&|v| if v.fract() == 0.0 { format!("{v:.0}") } else { String::new() })
            .y_label_formatter(&|v| tick(*v)),
        font(12.0),
        font(13.0),
    )
    .draw()?;
    let mut scenes: Vec<&str> = Vec::new();
    for run in runs {
        if !scenes.contains(&run.scene.as_str()) {
            scenes.push(&run.scene);
        }
        let colour = COLOURS[scenes.iter().position(|s| *s == run.scene).unwrap_or(0) % COLOURS.len()];
        let line: Vec<(f64, f64)> =
            run.errors.iter().enumerate().map(|(k, e)| (k as f64, value(e))).filter(|p| p.1 > 0.0).collect();
        let label = format!("{}, reuse {}", run.scene, if run.reuse { "on" } else { "off (dashed)" });
        draw_line(&mut cc, line, colour, !run.reuse, label)?;
    }
    draw_legend(&mut cc, SeriesLabelPosition::UpperLeft, 11.0)?;
    Ok(())
}

fn draw<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, chart: &MotionChart<'_>) -> DrawResult<DB> {
    let main = captioned(root, chart.caption)?;
    let (left, right) = main.split_horizontally(main.dim_in_pixel().0 / 2);
    panel(&left, "relMSE", chart.runs, |e| e.0)?;
    panel(&right, "HDR-FLIP", chart.runs, |e| e.1)?;
    Ok(())
}
