//! Raster figures (basins, two-parameter maps): equal-colour runs of a row merged into one
//! rectangle, marks, an optional colour bar and the legend column of [`crate::figure`].

use crate::colors::colormap;
use crate::figure::{
    axis_range, axis_tick, draw_legend, legend_width, padded, pixel_area, titled_area,
    write_png_svg, Draw, Err, FigureError, LegendEntry,
};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// A raster figure (basins, two-parameter maps).
#[derive(Clone, Debug, Default)]
pub struct RasterFigure {
    /// Title.
    pub title: String,
    /// X-axis label.
    pub x_label: String,
    /// Y-axis label.
    pub y_label: String,
    /// X extent of the cells `(min edge, max edge, cells)`.
    pub x: (f64, f64, usize),
    /// Y extent of the cells.
    pub y: (f64, f64, usize),
    /// Cell colours, row-major from the lowest y.
    pub colors: Vec<RGBColor>,
    /// Legend entries (right column).
    pub legend: Vec<LegendEntry>,
    /// Legend heading.
    pub legend_title: String,
    /// Colour bar of [`colormap`] `(min, max, label)`, drawn above the legend.
    pub colorbar: Option<(f64, f64, String)>,
    /// Points marked with a white-edged black cross (e.g. attractor points).
    pub marks: Vec<(f64, f64)>,
}

fn draw_raster<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    fig: &RasterFigure,
) -> Result<(), Err> {
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    let root = titled_area(root, &fig.title)?;
    let (w, _) = root.dim_in_pixel();
    let lw = legend_width(&fig.legend, &fig.legend_title).max(if fig.colorbar.is_some() {
        150
    } else {
        0
    });
    let (main, side) = root.split_horizontally(w.saturating_sub(lw));
    let (nx, ny) = (fig.x.2.max(1), fig.y.2.max(1));
    let (xr, yr) = (axis_range(fig.x.0, fig.x.1), axis_range(fig.y.0, fig.y.1));
    let mut ctx = ChartBuilder::on(&main)
        .margin(10)
        .x_label_area_size(44)
        .y_label_area_size(70)
        .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)
        .map_err(|x| x.to_string())?;
    let (xs, ys) = ((xr.1 - xr.0) / 10.0, (yr.1 - yr.0) / 10.0);
    let fmt = |v: &f64| axis_tick(*v, xs);
    let fmt_y = |v: &f64| axis_tick(*v, ys);
    ctx.configure_mesh()
        .disable_mesh()
        .x_labels(10)
        .y_labels(10)
        .x_label_formatter(&fmt)
        .y_label_formatter(&fmt_y)
        .x_desc(fig.x_label.as_str())
        .y_desc(fig.y_label.as_str())
        .label_style(("sans-serif", 13))
        .axis_desc_style(("sans-serif", 15))
        .draw()
        .map_err(|x| x.to_string())?;
    let (pixel, map, _) = pixel_area(&ctx);
    let (dx, dy) = ((xr.1 - xr.0) / nx as f64, (yr.1 - yr.0) / ny as f64);
    for iy in 0..ny {
        let mut ix = 0;
        while ix < nx {
            let c = iy * nx + ix;
            let Some(&col) = fig.colors.get(c) else {
                break;
            };
            let mut end = ix + 1;
            while end < nx && fig.colors.get(iy * nx + end) == Some(&col) {
                end += 1;
            }
            let a = map(xr.0 + ix as f64 * dx, yr.0 + (iy + 1) as f64 * dy);
            let b = map(xr.0 + end as f64 * dx, yr.0 + iy as f64 * dy);
            pixel
                .draw(&Rectangle::new([a, b], col.filled()))
                .map_err(e)?;
            ix = end;
        }
    }
    let inside = |x: f64, y: f64| x >= xr.0 && x <= xr.1 && y >= yr.0 && y <= yr.1;
    for &(x, y) in fig.marks.iter().filter(|p| inside(p.0, p.1)) {
        let p = map(x, y);
        for (style, s) in [(WHITE.stroke_width(4), 6), (BLACK.stroke_width(2), 5)] {
            pixel
                .draw(&PathElement::new(
                    vec![(p.0 - s, p.1), (p.0 + s, p.1)],
                    style,
                ))
                .map_err(e)?;
            pixel
                .draw(&PathElement::new(
                    vec![(p.0, p.1 - s), (p.0, p.1 + s)],
                    style,
                ))
                .map_err(e)?;
        }
    }
    let side = if let Some((lo, hi, label)) = &fig.colorbar {
        let (_, sh) = side.dim_in_pixel();
        let (bar, rest) = side.split_vertically(if fig.legend.is_empty() {
            sh
        } else {
            sh * 11 / 20
        });
        let (lo, hi) = if hi > lo {
            axis_range(*lo, *hi)
        } else {
            padded(*lo, *hi)
        };
        let mut cb = ChartBuilder::on(&bar)
            .margin_top(16)
            .margin_bottom(16)
            .margin_right(8)
            .caption(label.as_str(), ("sans-serif", 13))
            .y_label_area_size(64)
            .build_cartesian_2d(0.0..1.0, lo..hi)
            .map_err(|x| x.to_string())?;
        cb.configure_mesh()
            .disable_x_axis()
            .disable_mesh()
            .y_labels(8)
            .y_label_formatter(&|v: &f64| axis_tick(*v, (hi - lo) / 8.0))
            .label_style(("sans-serif", 12))
            .draw()
            .map_err(|x| x.to_string())?;
        let n = 64;
        cb.draw_series((0..n).map(|i| {
            let (a, b) = (
                lo + (hi - lo) * i as f64 / n as f64,
                lo + (hi - lo) * (i + 1) as f64 / n as f64,
            );
            Rectangle::new(
                [(0.0, a), (1.0, b)],
                colormap((i as f64 + 0.5) / n as f64).filled(),
            )
        }))
        .map_err(|x| x.to_string())?;
        rest
    } else {
        side
    };
    if !fig.legend.is_empty() {
        draw_legend(&side, &fig.legend_title, &fig.legend)?;
    }
    root.present().map_err(e)
}

/// Writes a raster as `stem.png` and `stem.svg` (equal-colour runs merged).
pub fn write_raster(stem: &Path, fig: &RasterFigure) -> Result<(), FigureError> {
    write_png_svg(stem, (1050, 760), fig)
}

impl Draw for RasterFigure {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), Err> {
        draw_raster(root, self)
    }
}
