//! PNG and SVG charts with no system fonts or libraries: `plotters` with its pure-Rust bitmap and
//! SVG backends and the DejaVu Sans font embedded in the binary (`assets/`, Bitstream Vera
//! licence).

use plotters::coord::Shift;
use plotters::prelude::*;
pub use plotters::style::RGBColor as PlotColor;
use std::path::Path;
use std::sync::Once;

static FONT: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");
static REGISTER: Once = Once::new();

/// Registers the embedded font under the family name `sans-serif` (idempotent).
pub fn register_font() {
    REGISTER.call_once(|| {
        // the embedded file is a valid TTF; a failure here is a build defect
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

/// Plot failure.
#[derive(Debug, thiserror::Error)]
#[error("cannot draw {path}: {msg}")]
pub struct PlotError {
    path: String,
    msg: String,
}

/// How a series is drawn.
#[derive(Clone, Copy, Debug)]
pub enum Mark {
    /// Polyline.
    Line,
    /// Filled dots of the given radius in pixels.
    Dots(u32),
}

/// One data series.
pub struct Series<'a> {
    /// Legend label (empty: no legend entry).
    pub label: &'a str,
    /// Points `(x, y)`.
    pub points: &'a [(f64, f64)],
    /// Drawing style.
    pub mark: Mark,
    /// Colour.
    pub color: RGBColor,
}

/// Colour-blind-safe palette (Okabe–Ito).
pub const PALETTE: [RGBColor; 7] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(0, 0, 0),
];

/// Axes and titles of a chart.
pub struct Chart<'a> {
    /// Title.
    pub title: &'a str,
    /// X-axis label.
    pub x_label: &'a str,
    /// Y-axis label.
    pub y_label: &'a str,
}

/// Largest magnitude of an axis end: wider data are drawn clipped. Keeps every axis width (and
/// the tick spacing derived from it) finite: an axis from -1e308 to 1e308 is infinitely wide in
/// `f64`, and the tick search never ends on it.
pub const AXIS_LIMIT: f64 = 1e300;

/// Most labelled ticks per axis.
pub const MAX_TICKS: usize = 10;

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

/// Axis ranges covering the finite points of the series (non-finite ones are skipped), padded by
/// 4 % and bounded by [`AXIS_LIMIT`].
fn bounds(series: &[Series]) -> ((f64, f64), (f64, f64)) {
    let mut xr = (f64::INFINITY, f64::NEG_INFINITY);
    let mut yr = (f64::INFINITY, f64::NEG_INFINITY);
    for s in series {
        for &(x, y) in s.points {
            if x.is_finite() && y.is_finite() {
                xr = (xr.0.min(x), xr.1.max(x));
                yr = (yr.0.min(y), yr.1.max(y));
            }
        }
    }
    let pad = |r: (f64, f64)| {
        if !r.0.is_finite() {
            return (0.0, 1.0);
        }
        let (lo, hi) = (
            r.0.clamp(-AXIS_LIMIT, AXIS_LIMIT),
            r.1.clamp(-AXIS_LIMIT, AXIS_LIMIT),
        );
        let w = (hi - lo).max(1e-12 * lo.abs().max(1.0));
        (lo - 0.04 * w, hi + 0.04 * w)
    };
    (pad(xr), pad(yr))
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

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    chart: &Chart,
    series: &[Series],
) -> Result<(), String> {
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let ((x0, x1), (y0, y1)) = bounds(series);
    let clip = ClipBox::around((x0, x1), (y0, y1));
    let mut ctx = ChartBuilder::on(&root)
        .caption(chart.title, ("sans-serif", 22))
        .margin(12)
        .x_label_area_size(44)
        .y_label_area_size(64)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(|e| e.to_string())?;
    ctx.configure_mesh()
        .x_labels(MAX_TICKS)
        .y_labels(MAX_TICKS)
        .x_desc(chart.x_label)
        .y_desc(chart.y_label)
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 16))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(|e| e.to_string())?;
    draw_series_list(&mut ctx, series, 14, clip)?;
    root.present().map_err(|e| e.to_string())
}

type XyChart<'a, DB> = ChartContext<
    'a,
    DB,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

/// Draws the series (lines or dots; non-finite points skipped, everything clipped to `clip`) and,
/// if any is labelled, the legend.
fn draw_series_list<'a, DB: DrawingBackend + 'a>(
    ctx: &mut XyChart<'a, DB>,
    series: &[Series],
    legend_font: u32,
    clip: ClipBox,
) -> Result<(), String> {
    let mut any_label = false;
    for s in series {
        let color = s.color;
        match s.mark {
            Mark::Line => {
                for run in clip.polyline(s.points) {
                    ctx.draw_series(LineSeries::new(run, color.stroke_width(1)))
                        .map_err(|e| e.to_string())?;
                }
            }
            Mark::Dots(r) => {
                ctx.draw_series(
                    s.points
                        .iter()
                        .filter(|&&p| clip.contains(p))
                        .map(|&p| Circle::new(p, r, color.filled())),
                )
                .map_err(|e| e.to_string())?;
            }
        }
        if !s.label.is_empty() {
            any_label = true;
            ctx.draw_series(std::iter::empty::<Circle<(f64, f64), u32>>())
                .map_err(|e| e.to_string())?
                .label(s.label)
                .legend(move |(x, y)| {
                    Rectangle::new([(x, y - 4), (x + 14, y + 4)], color.filled())
                });
        }
    }
    if any_label {
        ctx.configure_series_labels()
            .label_font(("sans-serif", legend_font))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(|e| e.to_string())?;
    }
    Ok(())
}

/// Writes `stem.png` (1000x600) and `stem.svg`.
pub fn xy_chart(stem: &Path, chart: &Chart, series: &[Series]) -> Result<(), PlotError> {
    register_font();
    let png = stem.with_extension("png");
    let svg = stem.with_extension("svg");
    let err = |p: &Path, msg: String| PlotError {
        path: p.display().to_string(),
        msg,
    };
    crate::safe_write::draw_to(&png, |tmp| {
        draw(
            BitMapBackend::new(tmp, (1000, 600)).into_drawing_area(),
            chart,
            series,
        )
    })
    .map_err(|m| err(&png, m))?;
    crate::safe_write::draw_to(&svg, |tmp| {
        draw(
            SVGBackend::new(tmp, (1000, 600)).into_drawing_area(),
            chart,
            series,
        )
    })
    .map_err(|m| err(&svg, m))?;
    Ok(())
}

/// One panel of a stacked figure.
pub struct Panel<'a> {
    /// Y-axis label.
    pub y_label: &'a str,
    /// Series.
    pub series: Vec<Series<'a>>,
}

fn draw_panels<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    title: &str,
    x_label: &str,
    x_range: (f64, f64),
    panels: &[Panel],
) -> Result<(), String> {
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let root = root
        .titled(title, ("sans-serif", 22))
        .map_err(|e| e.to_string())?;
    let areas = root.split_evenly((panels.len().max(1), 1));
    let x_range = axis_range(x_range.0, x_range.1);
    for (k, (area, panel)) in areas.into_iter().zip(panels).enumerate() {
        let (_, (y0, y1)) = bounds(&panel.series);
        let clip = ClipBox::around(x_range, (y0, y1));
        let last = k + 1 == panels.len();
        let mut ctx = ChartBuilder::on(&area)
            .margin(8)
            .x_label_area_size(if last { 40 } else { 18 })
            .y_label_area_size(64)
            .build_cartesian_2d(x_range.0..x_range.1, y0..y1)
            .map_err(|e| e.to_string())?;
        let mut mesh = ctx.configure_mesh();
        mesh.x_labels(MAX_TICKS)
            .y_labels(MAX_TICKS)
            .y_desc(panel.y_label)
            .label_style(("sans-serif", 13))
            .axis_desc_style(("sans-serif", 15))
            .light_line_style(RGBColor(240, 240, 240));
        if last {
            mesh.x_desc(x_label);
        }
        mesh.draw().map_err(|e| e.to_string())?;
        draw_series_list(&mut ctx, &panel.series, 12, clip)?;
    }
    root.present().map_err(|e| e.to_string())
}

/// Writes a figure of stacked panels sharing the x axis as `stem.png` and `stem.svg`.
pub fn stacked_chart(
    stem: &Path,
    title: &str,
    x_label: &str,
    x_range: (f64, f64),
    panels: &[Panel],
) -> Result<(), PlotError> {
    register_font();
    let png = stem.with_extension("png");
    let svg = stem.with_extension("svg");
    let h = (260 * panels.len().max(1) + 60) as u32;
    let err = |p: &Path, msg: String| PlotError {
        path: p.display().to_string(),
        msg,
    };
    crate::safe_write::draw_to(&png, |tmp| {
        draw_panels(
            BitMapBackend::new(tmp, (1100, h)).into_drawing_area(),
            title,
            x_label,
            x_range,
            panels,
        )
    })
    .map_err(|m| err(&png, m))?;
    crate::safe_write::draw_to(&svg, |tmp| {
        draw_panels(
            SVGBackend::new(tmp, (1100, h)).into_drawing_area(),
            title,
            x_label,
            x_range,
            panels,
        )
    })
    .map_err(|m| err(&svg, m))?;
    Ok(())
}

/// A regular grid of coloured cells (`colors[iy * nx + ix]`).
pub struct Raster<'a> {
    /// x range and cell count.
    pub x: (f64, f64, usize),
    /// y range and cell count.
    pub y: (f64, f64, usize),
    /// Cell colours, row-major with y rows.
    pub colors: &'a [RGBColor],
}

fn draw_raster<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    chart: &Chart,
    r: &Raster,
    legend: &[(String, RGBColor)],
    colorbar: Option<(f64, f64)>,
) -> Result<(), String> {
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let (w, _) = root.dim_in_pixel();
    let (main, side) =
        root.split_horizontally(w.saturating_sub(if colorbar.is_some() { 120 } else { 0 }));
    let (xr, yr) = (axis_range(r.x.0, r.x.1), axis_range(r.y.0, r.y.1));
    let mut ctx = ChartBuilder::on(&main)
        .caption(chart.title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(44)
        .y_label_area_size(64)
        .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)
        .map_err(|e| e.to_string())?;
    ctx.configure_mesh()
        .x_labels(MAX_TICKS)
        .y_labels(MAX_TICKS)
        .disable_mesh()
        .x_desc(chart.x_label)
        .y_desc(chart.y_label)
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 16))
        .draw()
        .map_err(|e| e.to_string())?;
    let (dx, dy) = ((xr.1 - xr.0) / r.x.2 as f64, (yr.1 - yr.0) / r.y.2 as f64);
    // (no more cells than colours: a short colour slice is drawn partly, not a panic)
    let cells = r.x.2.saturating_mul(r.y.2).min(r.colors.len());
    ctx.draw_series((0..cells).map(|c| {
        let (ix, iy) = (c % r.x.2, c / r.x.2);
        let x0 = xr.0 + ix as f64 * dx;
        let y0 = yr.0 + iy as f64 * dy;
        Rectangle::new([(x0, y0), (x0 + dx, y0 + dy)], r.colors[c].filled())
    }))
    .map_err(|e| e.to_string())?;
    for (name, color) in legend {
        let c = *color;
        ctx.draw_series(std::iter::empty::<Circle<(f64, f64), u32>>())
            .map_err(|e| e.to_string())?
            .label(name.as_str())
            .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 14, y + 5)], c.filled()));
    }
    if !legend.is_empty() {
        ctx.configure_series_labels()
            .label_font(("sans-serif", 13))
            .background_style(WHITE.mix(0.9))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(|e| e.to_string())?;
    }
    if let Some((lo, hi)) = colorbar {
        let (lo, hi) = axis_range(lo, hi);
        let mut cb = ChartBuilder::on(&side)
            .margin_top(40)
            .margin_bottom(56)
            .margin_right(8)
            .y_label_area_size(64)
            .build_cartesian_2d(0.0..1.0, lo..hi)
            .map_err(|e| e.to_string())?;
        cb.configure_mesh()
            .y_labels(MAX_TICKS)
            .disable_x_axis()
            .disable_mesh()
            .label_style(("sans-serif", 12))
            .draw()
            .map_err(|e| e.to_string())?;
        let n = 100;
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
        .map_err(|e| e.to_string())?;
    }
    root.present().map_err(|e| e.to_string())
}

/// Writes a raster image (basins, maps) as `stem.png` and `stem.svg`, with a legend of named
/// colours or a colour bar `(min, max)` of [`colormap`].
pub fn raster_chart(
    stem: &Path,
    chart: &Chart,
    r: &Raster,
    legend: &[(String, RGBColor)],
    colorbar: Option<(f64, f64)>,
) -> Result<(), PlotError> {
    register_font();
    let png = stem.with_extension("png");
    let svg = stem.with_extension("svg");
    let err = |p: &Path, msg: String| PlotError {
        path: p.display().to_string(),
        msg,
    };
    crate::safe_write::draw_to(&png, |tmp| {
        draw_raster(
            BitMapBackend::new(tmp, (1000, 820)).into_drawing_area(),
            chart,
            r,
            legend,
            colorbar,
        )
    })
    .map_err(|m| err(&png, m))?;
    crate::safe_write::draw_to(&svg, |tmp| {
        draw_raster(
            SVGBackend::new(tmp, (1000, 820)).into_drawing_area(),
            chart,
            r,
            legend,
            colorbar,
        )
    })
    .map_err(|m| err(&svg, m))?;
    Ok(())
}

/// A perceptually ordered colour map (viridis, five stops, linear in between) for `t` in `[0, 1]`.
pub fn colormap(t: f64) -> RGBColor {
    const STOPS: [(f64, f64, f64); 5] = [
        (68.0, 1.0, 84.0),
        (59.0, 82.0, 139.0),
        (33.0, 145.0, 140.0),
        (94.0, 201.0, 98.0),
        (253.0, 231.0, 37.0),
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let x = t * 4.0;
    let i = (x as usize).min(3);
    let f = x - i as f64;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    let l = |p: f64, q: f64| (p + (q - p) * f).round() as u8;
    RGBColor(l(a.0, b.0), l(a.1, b.1), l(a.2, b.2))
}

/// Colours of attractors: healthy ones in a blue–green family, unstable ones in a red–orange
/// family, each in order of its id within the family.
pub fn attractor_color(healthy: bool, k: usize) -> RGBColor {
    const HEALTHY: [RGBColor; 6] = [
        RGBColor(0, 114, 178),
        RGBColor(0, 158, 115),
        RGBColor(86, 180, 233),
        RGBColor(0, 80, 120),
        RGBColor(120, 200, 170),
        RGBColor(40, 60, 200),
    ];
    const UNSTABLE: [RGBColor; 6] = [
        RGBColor(213, 94, 0),
        RGBColor(230, 159, 0),
        RGBColor(204, 121, 167),
        RGBColor(160, 30, 30),
        RGBColor(240, 200, 80),
        RGBColor(150, 60, 120),
    ];
    if healthy {
        HEALTHY[k % HEALTHY.len()]
    } else {
        UNSTABLE[k % UNSTABLE.len()]
    }
}

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
    fn writes_png_and_svg() {
        let dir = std::env::temp_dir().join(format!("geardyn-plot-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let pts = [(0.0, 0.0), (1.0, 1.0), (2.0, 0.5)];
        let chart = Chart {
            title: "t",
            x_label: "x",
            y_label: "y",
        };
        xy_chart(
            &dir.join("c"),
            &chart,
            &[Series {
                label: "a",
                points: &pts,
                mark: Mark::Line,
                color: PALETTE[0],
            }],
        )
        .unwrap();
        let png = std::fs::read(dir.join("c.png")).unwrap();
        assert_eq!(&png[1..4], b"PNG");
        let svg = std::fs::read_to_string(dir.join("c.svg")).unwrap();
        assert!(svg.contains("<svg"));
        std::fs::remove_dir_all(dir).ok();
    }
}
