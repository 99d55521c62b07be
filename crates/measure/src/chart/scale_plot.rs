//! The chart of `bench scale`: against the scene's triangle count (log–log), the host's load,
//! each backend's trace-structure build and leakless frame (left), and the device memory the
//! renderer has allocated (right).

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::drawing::{
    captioned, draw_legend, draw_line, grey_grid, log_axis, log_range, log_ticks, tick, write_svg_png, DrawResult,
    Drawing, FAMILY,
};
use leakless::error::Result;
use leakless::trace::Backend;

/// One scene on one backend.
#[derive(Clone, Debug)]
pub struct ScalePoint {
    pub scene: String,
    pub triangles: u64,
    pub load_ms: f64,
    pub backend: Backend,
    /// Renderer creation: uploads and the trace structure.
    pub setup_ms: f64,
    /// The trace structure's build alone (BVH on the host, or BLAS and TLAS on the device).
    pub build_ms: f64,
    pub memory_mib: f64,
    /// The fastest leakless frame, host wall time.
    pub frame_ms: f64,
}

struct ScaleChart<'a> {
    points: &'a [ScalePoint],
    device: &'a str,
    size: (u32, u32),
}

impl Drawing for ScaleChart<'_> {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> DrawResult<DB> {
        draw(root, self)
    }
}

/// Writes the chart of `points` as an SVG and a PNG.
pub fn plot_scale(points: &[ScalePoint], device: &str, size: (u32, u32), svg: &Path, png: &Path) -> Result<()> {
    write_svg_png(&ScaleChart { points, device, size }, svg, png, (1200, 560))
}

fn backend_colour(backend: Backend) -> RGBColor {
    match backend {
        Backend::Compute => RGBColor(31, 119, 180),
        Backend::RayQuery => RGBColor(44, 160, 44),
    }
}

type Line = (String, RGBColor, bool, Vec<(f64, f64)>);

/// One log–log panel of `lines` (label, colour, dashed, points) against triangles.
fn panel<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, title: &str, unit: &str, lines: &[Line]) -> DrawResult<DB> {
    let font = |v: f64| (FAMILY, v);
    let area = area.titled(title, font(18.0))?;
    let x_range = log_range(lines.iter().flat_map(|l| l.3.iter().map(|p| p.0)));
    let y_range = log_range(lines.iter().flat_map(|l| l.3.iter().map(|p| p.1)));
    let (x_bold, x_light) = log_ticks(&x_range, 7);
    let (y_bold, y_light) = log_ticks(&y_range, 9);
    let mut cc = ChartBuilder::on(&area)
        .margin(12)
        .x_label_area_size(44)
        .y_label_area_size(60)
        .build_cartesian_2d(log_axis(x_range, (x_bold, x_light)), log_axis(y_range, (y_bold, y_light)))?;
    grey_grid(
        cc.configure_mesh()
            .x_desc("triangles")
            .y_desc(unit)
            .x_label_formatter(&|v| tick(*v))
            .y_label_formatter(&|v| tick(*v)),
        font(12.0),
        font(13.0),
    )
    .draw()?;
    for (label, colour, dashed, line) in lines {
        if line.is_empty() {
            continue;
        }
        let colour = *colour;
        draw_line(&mut cc, line.clone(), colour, *dashed, label.clone())?;
        cc.draw_series(line.iter().map(|&p| Circle::new(p, 3, colour.filled())))?;
    }
    draw_legend(&mut cc, SeriesLabelPosition::UpperLeft, 12.0)?;
    Ok(())
}

fn draw<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, chart: &ScaleChart<'_>) -> DrawResult<DB> {
    let note = format!(
        "{} · leakless {}×{}, fastest frame after a warm-up (host wall time) · `leakless bench scale`",
        chart.device, chart.size.0, chart.size.1
    );
    let main = captioned(root, &note)?;
    let (left, right) = main.split_horizontally(main.dim_in_pixel().0 * 3 / 5);
    let backends: Vec<Backend> = [Backend::Compute, Backend::RayQuery]
        .into_iter()
        .filter(|b| chart.points.iter().any(|p| p.backend == *b))
        .collect();
    let series = |b: Backend, value: fn(&ScalePoint) -> f64| -> Vec<(f64, f64)> {
        let mut v: Vec<(f64, f64)> = chart
            .points
            .iter()
            .filter(|p| p.backend == b)
            .map(|p| (p.triangles as f64, value(p)))
            .filter(|p| p.1 > 0.0)
            .collect();
        v.sort_by(|a, b| a.0.total_cmp(&b.0));
        v
    };
    // The load is the backend's business only in that each backend loads the same file: one line.
    let mut times: Vec<Line> = Vec::new();
    if let Some(&first) = backends.first() {
        times.push(("load (host)".into(), RGBColor(120, 120, 120), false, series(first, |p| p.load_ms)));
    }
    for &b in &backends {
        let colour = backend_colour(b);
        times.push((format!("build, {} (dashed)", b.name()), colour, true, series(b, |p| p.build_ms)));
        times.push((format!("leakless frame, {}", b.name()), colour, false, series(b, |p| p.frame_ms)));
    }
    panel(&left, "time against scene size", "ms", &times)?;
    let memory: Vec<Line> = backends
        .iter()
        .map(|&b| (b.name().to_string(), backend_colour(b), false, series(b, |p| p.memory_mib)))
        .collect();
    panel(&right, "device memory allocated", "MiB", &memory)?;
    Ok(())
}
