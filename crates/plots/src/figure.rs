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
//! * Broken data never stop a figure: non-finite points are skipped (they break a line), axis
//!   ranges stay finite and ordered ([`axis_range`]), far points are clipped.
//!
//! PNG and SVG are drawn by the same code (plotters, with the DejaVu Sans font embedded in the
//! binary: `assets/`, Bitstream Vera licence; no system fonts or libraries).

use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
pub use plotters::style::RGBColor;
use std::path::Path;
use std::sync::Once;

pub use crate::colors::{
    categorical, categorical_keyed, class_color, colormap, palette, Group, LabelColors,
    BROKEN_PAIR, CHAOTIC, DISTINCT_COLORS, HEALTHY_PAIR, INADMISSIBLE, LEGEND_MAX, OTHER, QUASI,
    UNSETTLED,
};
pub use crate::raster::{write_raster, RasterFigure};

static FONT: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");
static REGISTER: Once = Once::new();

/// Registers the embedded font under the family name `sans-serif` (idempotent).
pub fn register_font() {
    REGISTER.call_once(|| {
        // the embedded file is a valid TTF; a failure here is a build defect
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

/// Figure failure.
#[derive(Debug, thiserror::Error)]
#[error("cannot draw {path}: {msg}")]
pub struct FigureError {
    path: String,
    msg: String,
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
    fixed(v, decimals)
}

/// `v` with `decimals` decimals, trailing zeros (and a trailing point) dropped, never `-0`.
pub fn fixed(v: f64, decimals: usize) -> String {
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

/// A tick label of an axis whose ticks are about `step` apart: [`tick`], with as many decimals
/// as the step needs when four significant digits cannot tell neighbouring ticks apart (a time
/// axis near 1e5 with ticks 10 apart reads `100030`, not `1.00e5`).
pub fn axis_tick(v: f64, step: f64) -> String {
    let a = v.abs();
    if !(v.is_finite() && step.is_finite() && step > 0.0 && (1e-12..1e12).contains(&a)) {
        return tick(v);
    }
    if step >= a * 2e-4 && a < 1e5 {
        return tick(v);
    }
    let decimals = (-step.log10()).ceil().clamp(0.0, 8.0) as usize;
    fixed(v, decimals)
}

/// A finite range covering `lo..hi` with 4 % padding; a degenerate range (constant data) is
/// widened to a visible band around the value.
pub fn padded(lo: f64, hi: f64) -> (f64, f64) {
    if !(lo.is_finite() && hi.is_finite()) || lo > hi {
        return (0.0, 1.0);
    }
    let (lo, hi) = (
        lo.clamp(-AXIS_LIMIT, AXIS_LIMIT),
        hi.clamp(-AXIS_LIMIT, AXIS_LIMIT),
    );
    let w = hi - lo;
    if w <= 1e-9 * lo.abs().max(hi.abs()).max(1e-12) {
        let s = (0.1 * lo.abs()).max(0.5);
        return (lo - s, hi + s);
    }
    (lo - 0.04 * w, hi + 0.04 * w)
}

/// Largest magnitude of an axis end: wider data are drawn clipped. Keeps every axis width (and
/// the tick spacing derived from it) finite: an axis from -1e308 to 1e308 is infinitely wide in
/// `f64`, and the tick search never ends on it.
pub const AXIS_LIMIT: f64 = 1e300;

/// A finite, ordered axis range of non-zero width from the ends `lo`, `hi` (as given by a caller):
/// NaN ends are dropped (both: `(0, 1)`), infinite or larger ends clamped to [`AXIS_LIMIT`], a
/// width below `1e-12` of the magnitude widened about the centre.
pub fn axis_range(lo: f64, hi: f64) -> (f64, f64) {
    let clamp = |v: f64| (!v.is_nan()).then(|| v.clamp(-AXIS_LIMIT, AXIS_LIMIT));
    let (lo, hi) = match (clamp(lo), clamp(hi)) {
        (Some(a), Some(b)) => (a.min(b), a.max(b)),
        (Some(a), None) | (None, Some(a)) => (a, a),
        (None, None) => return (0.0, 1.0),
    };
    let min_w = 1e-12 * lo.abs().max(hi.abs()).max(1.0);
    if hi - lo >= min_w {
        (lo, hi)
    } else {
        let m = 0.5 * lo + 0.5 * hi;
        (m - 0.5 * min_w, m + 0.5 * min_w)
    }
}

/// The plot box extended by its own size on every side: data are clipped to it, so that no pixel
/// coordinate is far outside the image (the rasteriser walks a line pixel by pixel, unclipped).
#[derive(Clone, Copy, Debug)]
struct ClipBox {
    x: (f64, f64),
    y: (f64, f64),
}

impl ClipBox {
    fn around(x: (f64, f64), y: (f64, f64)) -> Self {
        let (wx, wy) = (x.1 - x.0, y.1 - y.0);
        ClipBox {
            x: (x.0 - wx, x.1 + wx),
            y: (y.0 - wy, y.1 + wy),
        }
    }

    fn contains(&self, p: (f64, f64)) -> bool {
        p.0 >= self.x.0 && p.0 <= self.x.1 && p.1 >= self.y.0 && p.1 <= self.y.1
    }

    /// The part of the segment `a`-`b` inside the box (Liang–Barsky). The ends of a segment
    /// inside the box are returned exactly; a cut point lies exactly on the border it crosses,
    /// its other coordinate interpolated from the nearer end and kept inside the box (far ends
    /// cancel digits: the cut may then be off along the border, never outside it).
    fn clip(&self, a: (f64, f64), b: (f64, f64)) -> Option<((f64, f64), (f64, f64))> {
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        if !(dx.is_finite() && dy.is_finite()) {
            return None;
        }
        // entry and exit parameters along a -> b, and the border (0..4) that set each
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        let (mut k0, mut k1) = (None, None);
        for (k, (p, q)) in [
            (-dx, a.0 - self.x.0),
            (dx, self.x.1 - a.0),
            (-dy, a.1 - self.y.0),
            (dy, self.y.1 - a.1),
        ]
        .into_iter()
        .enumerate()
        {
            if p == 0.0 {
                if q < 0.0 {
                    return None;
                }
            } else if p < 0.0 {
                if q / p > t0 {
                    t0 = q / p;
                    k0 = Some(k);
                }
            } else if q / p < t1 {
                t1 = q / p;
                k1 = Some(k);
            }
        }
        if t0 > t1 {
            return None;
        }
        let border = [self.x.0, self.x.1, self.y.0, self.y.1];
        let cut = |t: f64, k: Option<usize>, end: (f64, f64)| match k {
            None => end,
            Some(k) => {
                // interpolate from the nearer end
                let (p, q, u) = if t <= 0.5 { (a, b, t) } else { (b, a, 1.0 - t) };
                let v = (p.0 + u * (q.0 - p.0), p.1 + u * (q.1 - p.1));
                if k < 2 {
                    (border[k], v.1.clamp(self.y.0, self.y.1))
                } else {
                    (v.0.clamp(self.x.0, self.x.1), border[k])
                }
            }
        };
        Some((cut(t0, k0, a), cut(t1, k1, b)))
    }

    /// The pieces of a polyline inside the box: a non-finite point breaks it, segments leaving
    /// the box are cut at its border.
    fn polyline(&self, points: &[(f64, f64)]) -> Vec<Vec<(f64, f64)>> {
        let mut runs = vec![];
        let mut cur: Vec<(f64, f64)> = vec![];
        let mut prev: Option<(f64, f64)> = None;
        let flush = |cur: &mut Vec<(f64, f64)>, runs: &mut Vec<Vec<(f64, f64)>>| {
            if cur.len() > 1 {
                runs.push(std::mem::take(cur));
            } else {
                cur.clear();
            }
        };
        for &p in points {
            if !(p.0.is_finite() && p.1.is_finite()) {
                flush(&mut cur, &mut runs);
                prev = None;
                continue;
            }
            if let Some(a) = prev {
                match self.clip(a, p) {
                    None => flush(&mut cur, &mut runs),
                    Some((c, d)) => {
                        if cur.last() != Some(&c) {
                            flush(&mut cur, &mut runs);
                            cur.push(c);
                        }
                        cur.push(d);
                        if d != p {
                            flush(&mut cur, &mut runs);
                        }
                    }
                }
            } else if self.contains(p) {
                cur.push(p);
            }
            prev = Some(p);
        }
        flush(&mut cur, &mut runs);
        runs
    }
}

fn data_range(points: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let mut r = (f64::INFINITY, f64::NEG_INFINITY);
    for v in points.filter(|v| v.is_finite()) {
        r.0 = r.0.min(v);
        r.1 = r.1.max(v);
    }
    (r.0 <= r.1).then_some(r)
}

pub(crate) fn legend_width(fig_legend: &[LegendEntry], title: &str) -> u32 {
    if fig_legend.is_empty() {
        return 0;
    }
    let chars = fig_legend
        .iter()
        .map(|e| e.text.chars().count())
        .chain(std::iter::once(title.chars().count()))
        .max()
        .unwrap_or(0) as u32;
    // (up to 560 px: a gear train's label is one per mesh, 70 characters for 4 planets)
    (chars * 7 + 44).clamp(120, 560)
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
        let lo = (0..col.len()).min_by_key(|&i| col[i].1).unwrap_or(0);
        let hi = (0..col.len()).max_by_key(|&i| col[i].1).unwrap_or(0);
        // a column spanning at most 2 pixels: one point (no staircase of stubs on a smooth
        // curve); else the extremes in the order they are reached (no zigzag)
        if col[hi].1 - col[lo].1 <= 2 {
            if cur.last() != Some(&first) {
                cur.push(first);
            }
            col.clear();
            return;
        }
        let (a, b) = if lo <= hi { (lo, hi) } else { (hi, lo) };
        for p in [first, col[a], col[b], last] {
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

pub(crate) type Err = String;

/// Font size of a title: 20, smaller for a long title so that it fits the width (not below 13).
/// `root` filled white with `title` on top: the area below the title.
/// The plotting area of `ctx` in pixels (drawn on without coordinates), the pixel of a data point
/// in it, and its width and height.
#[allow(clippy::type_complexity)]
pub(crate) fn pixel_area<'a, 'b, DB: DrawingBackend>(
    ctx: &'b ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
) -> (
    DrawingArea<DB, Shift>,
    impl Fn(f64, f64) -> (i32, i32) + Copy + use<'a, 'b, DB>,
    (i32, i32),
) {
    let plot = ctx.plotting_area();
    let (px, py) = plot.get_pixel_range();
    let size = (px.end - px.start, py.end - py.start);
    let map = move |x: f64, y: f64| {
        let (a, b) = ctx.backend_coord(&(x, y));
        (a - px.start, b - py.start)
    };
    (plot.strip_coord_spec(), map, size)
}

pub(crate) fn titled_area<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    title: &str,
) -> Result<DrawingArea<DB, Shift>, Err> {
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    root.fill(&WHITE).map_err(e)?;
    root.titled(title, ("sans-serif", title_size(title, &root)))
        .map_err(e)
}

fn title_size<DB: DrawingBackend>(title: &str, area: &DrawingArea<DB, Shift>) -> u32 {
    let (w, _) = area.dim_in_pixel();
    let chars = title.chars().count().max(1) as f64;
    // DejaVu Sans: about 0.55 em per character
    ((w as f64 - 20.0) / (0.56 * chars))
        .floor()
        .clamp(13.0, 20.0) as u32
}

pub(crate) fn draw_legend<DB: DrawingBackend>(
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
    let root = titled_area(root, &fig.title)?;
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
                axis_range(a, b)
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
        let yr = axis_range(yr.0, yr.1);
        let clip = ClipBox::around(xr, yr);
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
        let (xs, ys) = ((xr.1 - xr.0) / 10.0, (yr.1 - yr.0) / y_ticks as f64);
        let fmt = |v: &f64| axis_tick(*v, xs);
        let fmt_y = |v: &f64| axis_tick(*v, ys);
        let blank = |_: &f64| String::new();
        let mut mesh = ctx.configure_mesh();
        mesh.x_labels(10)
            .y_labels(y_ticks)
            .x_label_formatter(&fmt)
            .y_label_formatter(&fmt_y)
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
        let (pixel, map, (pw, ph)) = pixel_area(&ctx);
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
                    let runs = clip.polyline(&layer.points);
                    for run in runs.iter().flat_map(|r| reduced_polyline(r, map)) {
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
    let w = if fig.width > 0 { fig.width } else { 1100 };
    write_png_svg(stem, (w, figure_height(fig)), fig)
}

/// A figure drawn by the same code on any backend (PNG and SVG).
pub(crate) trait Draw {
    /// Draws the whole figure on `root`.
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), Err>;
}

impl Draw for Figure {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), Err> {
        draw_figure(root, self)
    }
}

/// Writes `fig` as `stem.png` and `stem.svg` of `size` pixels (each file atomically).
pub(crate) fn write_png_svg(
    stem: &Path,
    size: (u32, u32),
    fig: &impl Draw,
) -> Result<(), FigureError> {
    register_font();
    let png = stem.with_extension("png");
    let svg = stem.with_extension("svg");
    let err = |p: &Path, msg: String| FigureError {
        path: p.display().to_string(),
        msg,
    };
    geardyn_files::safe_write::draw_to(&png, |tmp| {
        fig.draw(BitMapBackend::new(tmp, size).into_drawing_area())
    })
    .map_err(|m| err(&png, m))?;
    geardyn_files::safe_write::draw_to(&svg, |tmp| {
        fig.draw(SVGBackend::new(tmp, size).into_drawing_area())
    })
    .map_err(|m| err(&svg, m))?;
    Ok(())
}

/// Points of one name, or none.
pub type PointsOf<'a> = &'a dyn Fn(&str) -> Option<Vec<(f64, f64)>>;

/// Keeps at most `max` points of a polyline, preserving each bucket's min and max in `y`
/// (so peaks of a long time history survive decimation).
pub fn decimate(points: &[(f64, f64)], max: usize) -> Vec<(f64, f64)> {
    if points.len() <= max || max < 4 {
        return points.to_vec();
    }
    let buckets = max / 2;
    let per = points.len().div_ceil(buckets);
    let mut out = Vec::with_capacity(max + 2);
    for chunk in points.chunks(per) {
        let (mut lo, mut hi) = (0, 0);
        for (i, p) in chunk.iter().enumerate() {
            if p.1 < chunk[lo].1 {
                lo = i;
            }
            if p.1 > chunk[hi].1 {
                hi = i;
            }
        }
        let (a, b) = if lo <= hi { (lo, hi) } else { (hi, lo) };
        out.push(chunk[a]);
        if b != a {
            out.push(chunk[b]);
        }
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
        assert_eq!(axis_tick(100030.0, 10.0), "100030");
        assert_eq!(axis_tick(3105.5, 0.5), "3105.5");
        assert_eq!(axis_tick(0.3, 0.1), "0.3");
        assert_eq!(axis_tick(1234.5678, 100.0), "1235");
    }

    #[test]
    fn decimation_keeps_extremes() {
        let pts: Vec<(f64, f64)> = (0..10_000)
            .map(|i| {
                (
                    i as f64,
                    if i == 4321 {
                        9.0
                    } else {
                        (i as f64 * 0.01).sin()
                    },
                )
            })
            .collect();
        let d = decimate(&pts, 500);
        assert!(d.len() <= 502);
        assert!(d.iter().any(|p| p.1 == 9.0));
        assert!(d.windows(2).all(|w| w[0].0 < w[1].0));
    }

    #[test]
    fn polylines_are_broken_at_non_finite_points_and_clipped() {
        let b = ClipBox::around((0.0, 1.0), (0.0, 1.0)); // [-1, 2] x [-1, 2]
        let nan = f64::NAN;
        let runs = b.polyline(&[(0.0, 0.0), (0.5, 0.5), (nan, 0.0), (1.0, 1.0), (1.5, 0.0)]);
        assert_eq!(
            runs,
            vec![vec![(0.0, 0.0), (0.5, 0.5)], vec![(1.0, 1.0), (1.5, 0.0)]]
        );
        // leaving and re-entering the box: cut at its border, inner points exact
        let runs = b.polyline(&[(0.0, 0.0), (0.0, 1e300), (1.0, 1.0), (1.0, 1.5)]);
        assert_eq!(runs.len(), 2);
        assert_eq!(runs[0], vec![(0.0, 0.0), (0.0, 2.0)]);
        assert_eq!(runs[1].last(), Some(&(1.0, 1.5)));
        assert!((runs[1][0].1 - 2.0).abs() < 1e-12);
        // entirely outside
        assert!(b.polyline(&[(5.0, 5.0), (6.0, 7.0)]).is_empty());
        // crossing the box from far away on both sides
        let runs = b.polyline(&[(-1e300, 0.5), (1e300, 0.5)]);
        assert_eq!(runs, vec![vec![(-1.0, 0.5), (2.0, 0.5)]]);
        // an overflowing difference is dropped, not drawn
        assert!(b.polyline(&[(-f64::MAX, 0.0), (f64::MAX, 0.0)]).is_empty());
    }

    #[test]
    fn constant_ranges_are_widened() {
        let (a, b) = padded(1.0, 1.0);
        assert!(a < 1.0 && b > 1.0 && b - a >= 0.2);
    }

    #[test]
    fn smooth_lines_are_reduced_without_stubs() {
        // 10 points per pixel column of a gentle slope: one point per column
        let pts: Vec<(f64, f64)> = (0..1000)
            .map(|i| (i as f64 / 10.0, i as f64 / 100.0))
            .collect();
        let runs = reduced_polyline(&pts, |x, y| (x.floor() as i32, (-y).round() as i32));
        assert_eq!(runs.len(), 1);
        assert_eq!(runs[0].len(), 100);
        assert!(runs[0].windows(2).all(|w| w[1].0 == w[0].0 + 1));
        // a jump inside a column keeps its extremes; a NaN breaks the line
        let pts = [
            (0.0, 0.0),
            (0.5, 50.0),
            (0.9, 0.0),
            (f64::NAN, 0.0),
            (2.0, 1.0),
            (3.0, 1.0),
        ];
        let runs = reduced_polyline(&pts, |x, y| (x.floor() as i32, y as i32));
        assert_eq!(
            runs,
            vec![vec![(0, 0), (0, 50), (0, 0)], vec![(2, 1), (3, 1)]]
        );
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
