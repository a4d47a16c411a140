//! Two-parameter maps with their data: one metric on a colour bar, or the decided classes.

use crate::runner::Ctx;
use crate::Figure;
use anyhow::Result;
use geardyn_analysis::map2d::MapCell;
use geardyn_io::figure::RGBColor as PlotColor;
use geardyn_io::figure::{
    palette, write_raster, LegendEntry, RasterFigure, CHAOTIC, OTHER, QUASI, UNSETTLED,
};
use geardyn_io::output::write_csv;
use std::path::Path;

use crate::shared::*;

/// What a map figure draws: the `cells` over the grid `xs` × `ys`, the axes named `axes`, under
/// `title`.
#[derive(Clone, Copy)]
pub struct MapView<'a> {
    /// The cells, `x` fastest.
    pub cells: &'a [MapCell],
    /// The `x` values.
    pub xs: &'a [f64],
    /// The `y` values.
    pub ys: &'a [f64],
    /// The parameter names of `x` and `y`.
    pub axes: (&'a str, &'a str),
    /// The figure's title.
    pub title: &'a str,
}

/// A two-parameter map `dir/name.png|svg` of one metric (colour bar), with `name.csv`.
pub fn map_figure(
    ctx: &Ctx,
    dir: &Path,
    name: &str,
    map: &MapView,
    metric: &str,
    caption: &str,
) -> Result<Figure> {
    let cells = map.cells;
    let name = &safe(name);
    let vals: Vec<f64> = cells
        .iter()
        .map(|c| c.metric(metric).unwrap_or(f64::NAN))
        .collect();
    let lo = vals
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(f64::INFINITY, f64::min);
    let hi = vals
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(f64::NEG_INFINITY, f64::max);
    let colors: Vec<PlotColor> = vals
        .iter()
        .map(|v| {
            if v.is_finite() {
                geardyn_io::figure::colormap((v - lo) / (hi - lo).max(1e-12))
            } else {
                OTHER
            }
        })
        .collect();
    let raster = RasterFigure {
        colorbar: Some((lo, hi, metric.replace('_', " "))),
        ..map_raster(map, colors)
    };
    write_map(ctx, dir, name, &raster, cells, caption)
}

/// A map of the decided classes `dir/name.png|svg` (legend) with `name.csv`.
pub fn class_map_figure(ctx: &Ctx, dir: &Path, name: &str, map: &MapView) -> Result<Figure> {
    let (cells, title) = (map.cells, map.title);
    let name = &safe(name);
    let classes_ = [
        ("healthy periodic", palette(0)),
        ("periodic with back-side contact", palette(1)),
        ("chaotic", CHAOTIC),
        ("failed", PlotColor(190, 0, 50)),
        ("quasi-periodic", QUASI),
        ("unsettled", UNSETTLED),
    ];
    let mut count = [0usize; 6];
    let colors: Vec<PlotColor> = cells
        .iter()
        .map(|c| {
            let k = c.metric("class").unwrap_or(3.0) as usize;
            let k = k.min(5);
            count[k] += 1;
            classes_[k].1
        })
        .collect();
    let legend = classes_
        .iter()
        .zip(count)
        .filter(|(_, n)| *n > 0)
        .map(|((t, c), n)| {
            LegendEntry::dot(
                format!("{t} — {:.0} %", 100.0 * n as f64 / cells.len() as f64),
                *c,
            )
        })
        .collect();
    let raster = RasterFigure {
        legend,
        legend_title: "decided class".into(),
        ..map_raster(map, colors)
    };
    let caption = format!("{title}: the decided class of every cell (periodic by the period test, chaotic only with a significantly positive TLE).");
    write_map(ctx, dir, name, &raster, cells, &caption)
}

/// The raster of `map`: a colour per cell.
fn map_raster(map: &MapView, colors: Vec<PlotColor>) -> RasterFigure {
    RasterFigure {
        title: map.title.into(),
        x_label: map.axes.0.into(),
        y_label: map.axes.1.into(),
        x: cell_axis(map.xs),
        y: cell_axis(map.ys),
        colors,
        ..Default::default()
    }
}

/// Writes the map `raster` as `dir/name.png|svg` and its `cells` as `name.csv`: its figure, with
/// `caption`.
fn write_map(
    ctx: &Ctx,
    dir: &Path,
    name: &str,
    raster: &RasterFigure,
    cells: &[MapCell],
    caption: &str,
) -> Result<Figure> {
    let stem = dir.join(name);
    write_raster(&stem, raster)?;
    let csv = dir.join(format!("{name}.csv"));
    write_map_csv(&csv, (&raster.x_label, &raster.y_label), cells)?;
    Ok(ctx.fig(&stem, caption, &[csv]))
}

fn write_map_csv(path: &Path, axes: (&str, &str), cells: &[MapCell]) -> Result<()> {
    write_csv(
        path,
        &[
            axes.0,
            axes.1,
            "class",
            "motion",
            "healthy",
            "max_force",
            "min_force",
            "p_id",
            "impacts",
        ],
        cells.iter().map(|c| {
            vec![
                exact(c.x),
                exact(c.y),
                c.motion.word().into(),
                if c.motion.is_periodic() {
                    c.label.clone()
                } else {
                    c.motion.word().into()
                },
                c.healthy.to_string(),
                g(c.max_force),
                g(c.min_force),
                g(c.p_id),
                c.impacts.to_string(),
            ]
        }),
    )?;
    Ok(())
}

/// A raster axis over the grid values `v`: from half a step below the first to half a step
/// above the last, one cell per value (a step of 1 for a single value).
fn cell_axis(v: &[f64]) -> (f64, f64, usize) {
    let step = if v.len() > 1 {
        (v[v.len() - 1] - v[0]) / (v.len() - 1) as f64
    } else {
        1.0
    };
    (v[0] - step / 2.0, v[v.len() - 1] + step / 2.0, v.len())
}
