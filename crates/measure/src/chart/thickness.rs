//! The wall-thickness chart of `leakless stability`: light found in the dark room and the
//! image's RMSE against the partition's thickness, one line per method, as SVG and PNG.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::drawing::{draw_legend, method_colour, tick, write_svg_png, DrawResult, Drawing, Scale};
use leakless::error::Result;
use leakless::Method;

/// One point: a method at one thickness.
#[derive(Clone, Debug)]
pub struct ThicknessPoint {
    pub thickness_mm: f64,
    pub method: Method,
    /// Mean luminance in the dark room (the reference's is 0).
    pub dark_radiance: f64,
    pub rmse: f64,
}

struct ThicknessChart<'a> {
    points: &'a [ThicknessPoint],
    caption: &'a str,
}

impl Drawing for ThicknessChart<'_> {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> DrawResult<DB> {
        draw(root, self.points, self.caption)
    }
}

/// Writes the chart of `points` as an SVG and a PNG, `size` pixels each.
pub fn plot_thickness(
    points: &[ThicknessPoint],
    caption: &str,
    svg: &Path,
    png: &Path,
    size: (u32, u32),
) -> Result<()> {
    write_svg_png(&ThicknessChart { points, caption }, svg, png, size)
}

fn draw<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, points: &[ThicknessPoint], caption: &str) -> DrawResult<DB> {
    let (scale, w, h) = Scale::clear(&root, (900.0, 450.0))?;
    let (px, font) = (|v| scale.px(v), |v| scale.font(v));
    let root = root.titled("leaks against partition thickness", font(20.0))?;
    let (foot_area, panels) = {
        let (top, bottom) = root.split_vertically(h.saturating_sub((1.8 * font(12.0).1) as u32 + px(30.0) as u32));
        (bottom, top)
    };
    let (left, right) = panels.split_horizontally(w / 2);
    let mut thicknesses: Vec<f64> = points.iter().map(|p| p.thickness_mm).collect();
    thicknesses.sort_by(f64::total_cmp);
    thicknesses.dedup();
    let slot = |t: f64| thicknesses.iter().position(|x| *x == t).unwrap_or(0) as f64;
    let mut methods: Vec<Method> = points.iter().map(|p| p.method).collect();
    methods.dedup();
    methods.sort_by_key(|m| m.name());
    methods.dedup();
    for (area, title, value) in [
        (
            &left,
            "mean radiance in the dark room (reference: 0)",
            (|p: &ThicknessPoint| p.dark_radiance) as fn(&ThicknessPoint) -> f64,
        ),
        (
            &right,
            "RMSE of the image against the reference",
            (|p: &ThicknessPoint| p.rmse) as fn(&ThicknessPoint) -> f64,
        ),
    ] {
        let max = points.iter().map(value).fold(0.0f64, f64::max).max(1e-9) * 1.1;
        let mut cc = ChartBuilder::on(area)
            .margin(px(12.0))
            .caption(title, font(14.0))
            .x_label_area_size(px(40.0))
            .y_label_area_size(px(60.0))
            .build_cartesian_2d(-0.3..(thicknesses.len() as f64 - 0.7), 0.0..max)?;
        cc.configure_mesh()
            .x_labels(thicknesses.len())
            .x_label_formatter(&|x| {
                let i = x.round();
                if (x - i).abs() < 1e-6 && i >= 0.0 && (i as usize) < thicknesses.len() {
                    match thicknesses[i as usize] {
                        0.0 => "0 (a quad)".to_string(),
                        t => format!("{} mm", tick(t)),
                    }
                } else {
                    String::new()
                }
            })
            .y_label_formatter(&|v| tick(*v))
            .x_desc("partition thickness")
            .label_style(font(12.0))
            .axis_desc_style(font(13.0))
            .light_line_style(RGBColor(238, 238, 238))
            .draw()?;
        for &method in &methods {
            let colour = method_colour(method);
            let mut line: Vec<(f64, f64)> =
                points.iter().filter(|p| p.method == method).map(|p| (slot(p.thickness_mm), value(p))).collect();
            line.sort_by(|a, b| a.0.total_cmp(&b.0));
            cc.draw_series(LineSeries::new(line.clone(), colour.stroke_width(px(2.0) as u32)))?
                .label(method.name())
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2)));
            cc.draw_series(line.iter().map(|&p| Circle::new(p, px(4.0), colour.filled())))?;
        }
        draw_legend(&mut cc, SeriesLabelPosition::UpperRight, 12.0)?;
    }
    foot_area.draw(&Text::new(
        caption.to_string(),
        (px(10.0), px(6.0)),
        TextStyle::from(font(11.5)).color(&RGBColor(90, 90, 90)),
    ))?;
    Ok(())
}
