//! Figures of reports and sweeps that stay readable and small.
//!
//! * Stacked panels share one x axis; tick labels of the x axis only under the last panel; a
//!   panel whose data are constant gets a padded range and few ticks (no repeated labels).
//! * The legend has its own column right of the panels, never over the data.
//! * Scatter layers are merged per pixel: every point is mapped to its pixel, duplicates are
//!   dropped and vertical runs of occupied pixels in a pixel column are drawn as one rectangle —
//!   a bifurcation diagram of a hundred thousand points is a few thousand SVG elements.
//!   Lines are reduced to the first, lowest, highest and last point of each pixel column.
//! * Rasters (basins, maps) merge horizontal runs of equal colour into one rectangle.
//! * [`palette`] gives many distinct colours (Okabe–Ito, then Kelly's colours of maximum
//!   contrast), so that a diagram with twenty attractors does not cycle through eight colours.
//!
//! PNG and SVG are drawn by the same code (plotters, embedded DejaVu Sans).

use crate::plot::{colormap, register_font};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::collections::BTreeMap;
use std::path::Path;

/// Figure failure.
#[derive(Debug, thiserror::Error)]
#[error("cannot draw {path}: {msg}")]
pub struct FigureError {
    path: String,
    msg: String,
}

/// Colour of chaotic motions.
pub const CHAOTIC: RGBColor = RGBColor(0, 0, 0);
/// Colour of quasi-periodic motions.
pub const QUASI: RGBColor = RGBColor(90, 90, 90);
/// Colour of undecided (unsettled) motions.
pub const UNSETTLED: RGBColor = RGBColor(175, 175, 175);
/// Colour of failed runs and of a remainder group.
pub const OTHER: RGBColor = RGBColor(205, 205, 205);

const DISTINCT: [RGBColor; 24] = [
    // Okabe–Ito (without black)
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(240, 228, 66),
    // then colours chosen to differ from those and from each other (after Kelly's list)
    RGBColor(135, 86, 146),
    RGBColor(190, 0, 50),
    RGBColor(128, 128, 0),
    RGBColor(194, 178, 128),
    RGBColor(0, 0, 128),
    RGBColor(0, 200, 200),
    RGBColor(249, 147, 121),
    RGBColor(150, 220, 100),
    RGBColor(255, 0, 255),
    RGBColor(179, 68, 108),
    RGBColor(70, 70, 200),
    RGBColor(136, 45, 23),
    RGBColor(141, 182, 0),
    RGBColor(200, 160, 255),
    RGBColor(0, 90, 50),
    RGBColor(255, 200, 150),
    RGBColor(160, 0, 200),
];

/// Number of distinct colours of [`palette`] before it repeats.
pub const DISTINCT_COLORS: usize = DISTINCT.len();

/// The `k`-th of [`DISTINCT_COLORS`] distinct colours (repeats after that; callers group the
/// rest as "other").
pub fn palette(k: usize) -> RGBColor {
    DISTINCT[k % DISTINCT.len()]
}

/// How a layer is drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Style {
    /// Polyline of the given width; a non-finite point breaks it.
    Line(u32),
    /// Filled square dots of the given half-size in pixels, merged per pixel.
    Dots(u32),
}

/// One layer of a panel.
#[derive(Clone, Debug)]
pub struct Layer {
    /// Points `(x, y)`.
    pub points: Vec<(f64, f64)>,
    /// Style.
    pub style: Style,
    /// Colour.
    pub color: RGBColor,
}

/// One panel.
#[derive(Clone, Debug, Default)]
pub struct Panel {
    /// Y-axis label.
    pub y_label: String,
    /// Layers, drawn in order.
    pub layers: Vec<Layer>,
    /// Fixed y range (default: the data, padded).
    pub y_range: Option<(f64, f64)>,
    /// Horizontal reference lines (drawn light grey under the data).
    pub hlines: Vec<f64>,
    /// Relative height (default 1).
    pub weight: f64,
}

/// A legend entry.
#[derive(Clone, Debug, PartialEq)]
pub struct LegendEntry {
    /// Text.
    pub text: String,
    /// Colour.
    pub color: RGBColor,
    /// Drawn as a line sample (else a filled square).
    pub line: bool,
}

impl LegendEntry {
    /// A filled-square entry.
    pub fn dot(text: impl Into<String>, color: RGBColor) -> Self {
        LegendEntry {
            text: text.into(),
            color,
            line: false,
        }
    }
    /// A line entry.
    pub fn line(text: impl Into<String>, color: RGBColor) -> Self {
        LegendEntry {
            text: text.into(),
            color,
            line: true,
        }
    }
}

/// A figure of stacked panels sharing the x axis.
#[derive(Clone, Debug, Default)]
pub struct Figure {
    /// Title.
    pub title: String,
    /// X-axis label.
    pub x_label: String,
    /// X range (default: the data).
    pub x_range: Option<(f64, f64)>,
    /// Panels, top to bottom.
    pub panels: Vec<Panel>,
    /// Legend (its own column right of the panels; none when empty).
    pub legend: Vec<LegendEntry>,
    /// Legend heading.
    pub legend_title: String,
    /// Width of the image in pixels (default 1100).
    pub width: u32,
    /// Height of a panel of weight 1 in pixels (default 230).
    pub panel_height: u32,
}

/// A tick label for people: at most four significant digits, no trailing zeros, no `-0`.
pub fn tick(v: f64) -> String {
    if !v.is_finite() {
        return String::new();
    }
    if v.abs() < 1e-12 {
        return "0".into();
    }
    let a = v.abs();
    if !(1e-4..1e5).contains(&a) {
        return format!("{v:.2e}");
    }
    let decimals = (3 - a.log10().floor() as i32).clamp(0, 8) as usize;
    let s = format!("{v:.decimals$}");
    let s = if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    };
    if s == "-0" {
        "0".into()
    } else {
        s
    }
}

/// A finite range covering `lo..hi` with 4 % padding; a degenerate range (constant data) is
/// widened to a visible band around the value.
pub fn padded(lo: f64, hi: f64) -> (f64, f64) {
    if !(lo.is_finite() && hi.is_finite()) || lo > hi {
        return (0.0, 1.0);
    }
    let w = hi - lo;
    if w <= 1e-9 * lo.abs().max(hi.abs()).max(1e-12) {
        let s = (0.1 * lo.abs()).max(0.5);
        return (lo - s, hi + s);
    }
    (lo - 0.04 * w, hi + 0.04 * w)
}

fn data_range(points: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let mut r = (f64::INFINITY, f64::NEG_INFINITY);
    for v in points.filter(|v| v.is_finite()) {
        r.0 = r.0.min(v);
        r.1 = r.1.max(v);
    }
    (r.0 <= r.1).then_some(r)
}

fn legend_width(fig_legend: &[LegendEntry], title: &str) -> u32 {
    if fig_legend.is_empty() {
        return 0;
    }
    let chars = fig_legend
        .iter()
        .map(|e| e.text.chars().count())
        .chain(std::iter::once(title.chars().count()))
        .max()
        .unwrap_or(0) as u32;
    (chars * 7 + 44).clamp(120, 380)
}

/// Pixels of a scatter layer merged: `(column, first row, last row)` runs.
fn merged_runs(pixels: &mut [(i32, i32)], gap: i32) -> Vec<(i32, i32, i32)> {
    pixels.sort_unstable();
    let mut runs: Vec<(i32, i32, i32)> = Vec::new();
    for &(x, y) in pixels.iter() {
        match runs.last_mut() {
            Some(r) if r.0 == x && y <= r.2 + gap => r.2 = r.2.max(y),
            _ => runs.push((x, y, y)),
        }
    }
    runs
}

/// A polyline reduced to at most four points per pixel column (first, min, max, last), broken
/// at non-finite points; in pixel coordinates.
fn reduced_polyline(
    points: &[(f64, f64)],
    map: impl Fn(f64, f64) -> (i32, i32),
) -> Vec<Vec<(i32, i32)>> {
    let mut out: Vec<Vec<(i32, i32)>> = Vec::new();
    let mut cur: Vec<(i32, i32)> = Vec::new();
    let mut col: Vec<(i32, i32)> = Vec::new();
    let flush_col = |col: &mut Vec<(i32, i32)>, cur: &mut Vec<(i32, i32)>| {
        if col.is_empty() {
            return;
        }
        let first = col[0];
        let last = *col.last().unwrap_or(&first);
        let lo = *col.iter().min_by_key(|p| p.1).unwrap_or(&first);
        let hi = *col.iter().max_by_key(|p| p.1).unwrap_or(&first);
        for p in [first, lo, hi, last] {
            if cur.last() != Some(&p) {
                cur.push(p);
            }
        }
        col.clear();
    };
    for &(x, y) in points {
        if !(x.is_finite() && y.is_finite()) {
            flush_col(&mut col, &mut cur);
            if cur.len() > 1 {
                out.push(std::mem::take(&mut cur));
            } else {
                cur.clear();
            }
            continue;
        }
        let p = map(x, y);
        if let Some(c) = col.first() {
            if c.0 != p.0 {
                flush_col(&mut col, &mut cur);
            }
        }
        col.push(p);
    }
    flush_col(&mut col, &mut cur);
    if cur.len() > 1 {
        out.push(cur);
    }
    out
}

type Err = String;

fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    entries: &[LegendEntry],
) -> Result<(), Err> {
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    let (_, h) = area.dim_in_pixel();
    let mut y = 14i32;
    if !title.is_empty() {
        area.draw(&Text::new(
            title.to_string(),
            (6, y),
            ("sans-serif", 14).into_font().color(&BLACK),
        ))
        .map_err(e)?;
        y += 22;
    }
    let row = 18i32;
    let room = ((h as i32 - y - 10) / row).max(1) as usize;
    let shown = if entries.len() > room {
        room.saturating_sub(1)
    } else {
        entries.len()
    };
    for en in &entries[..shown] {
        if en.line {
            area.draw(&PathElement::new(
                vec![(8, y + 6), (28, y + 6)],
                en.color.stroke_width(3),
            ))
            .map_err(e)?;
        } else {
            area.draw(&Rectangle::new(
                [(10, y + 1), (24, y + 11)],
                en.color.filled(),
            ))
            .map_err(e)?;
            area.draw(&Rectangle::new(
                [(10, y + 1), (24, y + 11)],
                RGBColor(80, 80, 80),
            ))
            .map_err(e)?;
        }
        area.draw(&Text::new(
            en.text.clone(),
            (34, y - 1),
            ("sans-serif", 13).into_font().color(&BLACK),
        ))
        .map_err(e)?;
        y += row;
    }
    if shown < entries.len() {
        area.draw(&Text::new(
            format!("... {} more (see the CSV)", entries.len() - shown),
            (10, y - 1),
            ("sans-serif", 13).into_font().color(&RGBColor(90, 90, 90)),
        ))
        .map_err(e)?;
    }
    Ok(())
}

fn draw_figure<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, fig: &Figure) -> Result<(), Err> {
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    root.fill(&WHITE).map_err(e)?;
    let root = root.titled(&fig.title, ("sans-serif", 20)).map_err(e)?;
    let (w, _) = root.dim_in_pixel();
    let lw = legend_width(&fig.legend, &fig.legend_title);
    let (main, side) = root.split_horizontally(w.saturating_sub(lw));
    if lw > 0 {
        draw_legend(&side, &fig.legend_title, &fig.legend)?;
    }
    let xr = fig
        .x_range
        .or_else(|| {
            data_range(
                fig.panels
                    .iter()
                    .flat_map(|p| p.layers.iter().flat_map(|l| l.points.iter().map(|q| q.0))),
            )
        })
        .map_or((0.0, 1.0), |(a, b)| {
            if fig.x_range.is_some() && b > a {
                (a, b)
            } else {
                padded(a, b)
            }
        });
    let n = fig.panels.len().max(1);
    let weights: Vec<f64> = fig
        .panels
        .iter()
        .map(|p| if p.weight > 0.0 { p.weight } else { 1.0 })
        .collect();
    let total: f64 = weights.iter().sum::<f64>().max(1e-9);
    let (_, mh) = main.dim_in_pixel();
    let bottom_extra = 40.0;
    let avail = (mh as f64 - bottom_extra).max(50.0);
    let mut breaks: Vec<i32> = Vec::new();
    let mut acc = 0.0;
    for wgt in weights.iter().take(n.saturating_sub(1)) {
        acc += avail * wgt / total;
        breaks.push(acc.round() as i32);
    }
    let areas = main.split_by_breakpoints(Vec::<i32>::new(), breaks);
    for (k, (area, panel)) in areas.into_iter().zip(&fig.panels).enumerate() {
        let last = k + 1 == fig.panels.len();
        let yr = panel.y_range.unwrap_or_else(|| {
            data_range(
                panel
                    .layers
                    .iter()
                    .flat_map(|l| l.points.iter().map(|q| q.1))
                    .chain(panel.hlines.iter().copied()),
            )
            .map_or((0.0, 1.0), |(a, b)| padded(a, b))
        });
        let (_, ph) = area.dim_in_pixel();
        let y_ticks = ((ph as usize) / 28).clamp(2, 8);
        let mut ctx = ChartBuilder::on(&area)
            .margin_top(6)
            .margin_bottom(4)
            .margin_left(8)
            .margin_right(12)
            .x_label_area_size(if last { 44 } else { 6 })
            .y_label_area_size(70)
            .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)
            .map_err(|x| x.to_string())?;
        let fmt = |v: &f64| tick(*v);
        let blank = |_: &f64| String::new();
        let mut mesh = ctx.configure_mesh();
        mesh.x_labels(10)
            .y_labels(y_ticks)
            .x_label_formatter(&fmt)
            .y_label_formatter(&fmt)
            .y_desc(panel.y_label.as_str())
            .label_style(("sans-serif", 13))
            .axis_desc_style(("sans-serif", 14))
            .light_line_style(RGBColor(242, 242, 242))
            .bold_line_style(RGBColor(225, 225, 225));
        if last {
            mesh.x_desc(fig.x_label.as_str());
        } else {
            mesh.x_label_formatter(&blank);
        }
        mesh.draw().map_err(|x| x.to_string())?;
        let plot = ctx.plotting_area();
        let (px, py) = plot.get_pixel_range();
        let pixel = plot.strip_coord_spec();
        let map = |x: f64, y: f64| {
            let (a, b) = ctx.backend_coord(&(x, y));
            (a - px.start, b - py.start)
        };
        let (pw, ph) = (px.end - px.start, py.end - py.start);
        let inside = |p: &(i32, i32)| p.0 >= 0 && p.0 < pw && p.1 >= 0 && p.1 < ph;
        for &h in &panel.hlines {
            if h >= yr.0 && h <= yr.1 {
                let y = map(xr.0, h).1;
                pixel
                    .draw(&PathElement::new(
                        vec![(0, y), (pw - 1, y)],
                        RGBColor(150, 150, 150).stroke_width(1),
                    ))
                    .map_err(e)?;
            }
        }
        for layer in &panel.layers {
            match layer.style {
                Style::Dots(r) => {
                    let r = r.max(1) as i32;
                    let mut pixels: Vec<(i32, i32)> = layer
                        .points
                        .iter()
                        .filter(|p| p.0.is_finite() && p.1.is_finite())
                        .map(|&(x, y)| map(x, y))
                        .filter(inside)
                        .collect();
                    let runs = merged_runs(&mut pixels, r);
                    let style = layer.color.filled();
                    for &(x, y0, y1) in &runs {
                        pixel
                            .draw(&Rectangle::new(
                                [(x - r + 1, y0 - r + 1), (x + r, y1 + r)],
                                style,
                            ))
                            .map_err(e)?;
                    }
                }
                Style::Line(wd) => {
                    for run in reduced_polyline(&layer.points, map) {
                        let run: Vec<(i32, i32)> = run
                            .into_iter()
                            .map(|(x, y)| (x.clamp(-pw, 2 * pw), y.clamp(-ph, 2 * ph)))
                            .collect();
                        pixel
                            .draw(&PathElement::new(run, layer.color.stroke_width(wd.max(1))))
                            .map_err(e)?;
                    }
                }
            }
        }
    }
    root.present().map_err(e)
}

fn figure_height(fig: &Figure) -> u32 {
    let ph = if fig.panel_height > 0 {
        fig.panel_height
    } else {
        230
    };
    let total: f64 = fig
        .panels
        .iter()
        .map(|p| if p.weight > 0.0 { p.weight } else { 1.0 })
        .sum();
    let legend_rows = fig.legend.len() as u32 * 18 + 60;
    ((total * ph as f64) as u32 + 90)
        .max(legend_rows.min(900))
        .max(260)
}

/// Writes `stem.png` and `stem.svg`.
pub fn write_figure(stem: &Path, fig: &Figure) -> Result<(), FigureError> {
    register_font();
    let w = if fig.width > 0 { fig.width } else { 1100 };
    let h = figure_height(fig);
    let png = stem.with_extension("png");
    let svg = stem.with_extension("svg");
    let err = |p: &Path, msg: String| FigureError {
        path: p.display().to_string(),
        msg,
    };
    crate::safe_write::draw_to(&png, |tmp| {
        draw_figure(BitMapBackend::new(tmp, (w, h)).into_drawing_area(), fig)
    })
    .map_err(|m| err(&png, m))?;
    crate::safe_write::draw_to(&svg, |tmp| {
        draw_figure(SVGBackend::new(tmp, (w, h)).into_drawing_area(), fig)
    })
    .map_err(|m| err(&svg, m))?;
    Ok(())
}

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
    root.fill(&WHITE).map_err(e)?;
    let root = root.titled(&fig.title, ("sans-serif", 20)).map_err(e)?;
    let (w, _) = root.dim_in_pixel();
    let lw = legend_width(&fig.legend, &fig.legend_title).max(if fig.colorbar.is_some() {
        150
    } else {
        0
    });
    let (main, side) = root.split_horizontally(w.saturating_sub(lw));
    let (nx, ny) = (fig.x.2.max(1), fig.y.2.max(1));
    let mut ctx = ChartBuilder::on(&main)
        .margin(10)
        .x_label_area_size(44)
        .y_label_area_size(70)
        .build_cartesian_2d(fig.x.0..fig.x.1, fig.y.0..fig.y.1)
        .map_err(|x| x.to_string())?;
    let fmt = |v: &f64| tick(*v);
    ctx.configure_mesh()
        .disable_mesh()
        .x_labels(10)
        .y_labels(10)
        .x_label_formatter(&fmt)
        .y_label_formatter(&fmt)
        .x_desc(fig.x_label.as_str())
        .y_desc(fig.y_label.as_str())
        .label_style(("sans-serif", 13))
        .axis_desc_style(("sans-serif", 15))
        .draw()
        .map_err(|x| x.to_string())?;
    let plot = ctx.plotting_area();
    let (px, py) = plot.get_pixel_range();
    let pixel = plot.strip_coord_spec();
    let map = |x: f64, y: f64| {
        let (a, b) = ctx.backend_coord(&(x, y));
        (a - px.start, b - py.start)
    };
    let (dx, dy) = (
        (fig.x.1 - fig.x.0) / nx as f64,
        (fig.y.1 - fig.y.0) / ny as f64,
    );
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
            let a = map(fig.x.0 + ix as f64 * dx, fig.y.0 + (iy + 1) as f64 * dy);
            let b = map(fig.x.0 + end as f64 * dx, fig.y.0 + iy as f64 * dy);
            pixel
                .draw(&Rectangle::new([a, b], col.filled()))
                .map_err(e)?;
            ix = end;
        }
    }
    for &(x, y) in &fig.marks {
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
            (*lo, *hi)
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
            .y_label_formatter(&fmt)
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
    register_font();
    let png = stem.with_extension("png");
    let svg = stem.with_extension("svg");
    let err = |p: &Path, msg: String| FigureError {
        path: p.display().to_string(),
        msg,
    };
    let size = (1050, 760);
    crate::safe_write::draw_to(&png, |tmp| {
        draw_raster(BitMapBackend::new(tmp, size).into_drawing_area(), fig)
    })
    .map_err(|m| err(&png, m))?;
    crate::safe_write::draw_to(&svg, |tmp| {
        draw_raster(SVGBackend::new(tmp, size).into_drawing_area(), fig)
    })
    .map_err(|m| err(&svg, m))?;
    Ok(())
}

/// A named, coloured group of points.
pub type Group = (String, RGBColor, Vec<(f64, f64)>);

/// Points of one name, or none.
pub type PointsOf<'a> = &'a dyn Fn(&str) -> Option<Vec<(f64, f64)>>;

/// Groups of a categorical layer: `(name, points)` in order of first appearance, with their
/// colours; beyond [`DISTINCT_COLORS`] groups, the rarest are merged into one "other" group.
pub fn categorical(
    groups: BTreeMap<String, Vec<(f64, f64)>>,
    order: &[String],
    fixed: &dyn Fn(&str) -> Option<RGBColor>,
) -> Vec<Group> {
    let mut named: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    let mut groups = groups;
    for name in order {
        if let Some(p) = groups.remove(name) {
            named.push((name.clone(), p));
        }
    }
    named.extend(groups);
    let mut out = Vec::new();
    let mut other: Vec<(f64, f64)> = Vec::new();
    let mut others = 0;
    let mut k = 0;
    for (name, pts) in named {
        if let Some(c) = fixed(&name) {
            out.push((name, c, pts));
        } else if k < DISTINCT_COLORS {
            out.push((name, palette(k), pts));
            k += 1;
        } else {
            others += 1;
            other.extend(pts);
        }
    }
    if others > 0 {
        out.push((format!("{others} other labels"), OTHER, other));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_short() {
        assert_eq!(tick(0.30000000000000004), "0.3");
        assert_eq!(tick(1.4), "1.4");
        assert_eq!(tick(-0.0), "0");
        assert_eq!(tick(1234.5678), "1235");
        assert_eq!(tick(0.012345), "0.01235");
        assert_eq!(tick(2e-7), "2.00e-7");
    }

    #[test]
    fn palette_is_distinct() {
        let d = |a: RGBColor, b: RGBColor| {
            let s = |x: u8, y: u8| (x as f64 - y as f64).powi(2);
            (s(a.0, b.0) + s(a.1, b.1) + s(a.2, b.2)).sqrt()
        };
        for i in 0..DISTINCT_COLORS {
            for j in 0..i {
                assert!(d(palette(i), palette(j)) > 50.0, "{i} {j}");
            }
            for fixed in [CHAOTIC, QUASI, UNSETTLED] {
                assert!(d(palette(i), fixed) > 50.0, "{i}");
            }
        }
    }

    #[test]
    fn constant_ranges_are_widened() {
        let (a, b) = padded(1.0, 1.0);
        assert!(a < 1.0 && b > 1.0 && b - a >= 0.2);
    }

    #[test]
    fn scatter_is_merged_per_pixel() {
        let mut px = vec![(1, 1), (1, 2), (1, 2), (1, 3), (1, 9), (2, 1)];
        let runs = merged_runs(&mut px, 1);
        assert_eq!(runs, vec![(1, 1, 3), (1, 9, 9), (2, 1, 1)]);
    }

    #[test]
    fn big_scatter_svg_stays_small() {
        let dir = std::env::temp_dir().join(format!("geardyn-figure-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        // 200 values x 2000 points: a dense chaotic band
        let mut pts = Vec::new();
        let mut s = 1u64;
        for i in 0..200 {
            for _ in 0..2000 {
                s = s.wrapping_mul(6364136223846793005).wrapping_add(1);
                pts.push((i as f64, (s >> 11) as f64 / (1u64 << 53) as f64));
            }
        }
        let fig = Figure {
            title: "t".into(),
            x_label: "p".into(),
            panels: vec![Panel {
                y_label: "x".into(),
                layers: vec![Layer {
                    points: pts,
                    style: Style::Dots(1),
                    color: palette(0),
                }],
                ..Default::default()
            }],
            legend: vec![LegendEntry::dot("chaotic", CHAOTIC)],
            ..Default::default()
        };
        let stem = dir.join("big");
        write_figure(&stem, &fig).unwrap();
        let svg = std::fs::metadata(stem.with_extension("svg")).unwrap().len();
        assert!(svg < 200_000, "{svg}");
        std::fs::remove_dir_all(dir).ok();
    }
}
