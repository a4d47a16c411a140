//! Figures with their data, shared by the plans: sweep diagrams (one panel per section, points
//! coloured by attractor label, TLE / force / P_ID panels), basins, continuations, maps and
//! line plots. Every figure writes the CSV of what it draws next to it.

use crate::readings::f;
use crate::runner::{hdr, Ctx};
use crate::{Figure, Table};
use anyhow::Result;
use geardyn_analysis::attractor::IdentifyOptions;
use geardyn_analysis::basins::{Axis, BasinOptions, BasinResult};
use geardyn_analysis::bifurcation::Section as Sec;
use geardyn_analysis::continuation::ContinuationResult;
use geardyn_analysis::simulate::{Method, SimOptions};
use geardyn_io::figure::RGBColor as PlotColor;
use geardyn_io::figure::{
    palette, write_figure, Figure as Fig, Layer, LegendEntry, Panel, Style, CHAOTIC, OTHER, QUASI,
    UNSETTLED,
};
use geardyn_io::output::write_csv;
use geardyn_io::sweep_output::{attractor_name, lost_cells_legend, write_basin_raster};
use geardyn_model::MeshModel;
use std::path::Path;

pub use crate::maps::{class_map_figure, map_figure, MapView};
pub use crate::orbit_figures::{attach_trajectory, branch_both_ways, orbit_figure};
pub use crate::sweep_figures::{sweep_figure, SweepPanels};

/// Most section points per run and section kept in figures and CSV files (one initial state
/// per value); the points of a periodic run are kept once each.
pub const POINTS_PER_RUN: usize = 150;
/// The same for each of several initial states per value.
pub const POINTS_PER_RUN_MULTI: usize = 40;

/// A parameter value or initial state for CSV files: the shortest form that reads back to the
/// same number (`1.4152542372881356`, not `1.41525`), so that a row can be rerun exactly; empty
/// for NaN.
pub fn exact(v: f64) -> String {
    if v.is_nan() {
        String::new()
    } else {
        format!("{v}")
    }
}

/// A measured number for CSV files: six significant digits.
pub fn g(v: f64) -> String {
    if !v.is_finite() {
        return if v.is_nan() {
            String::new()
        } else {
            format!("{v}")
        };
    }
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if !(1e-5..1e9).contains(&a) {
        return format!("{v:.5e}");
    }
    let d = (5 - a.log10().floor() as i32).clamp(0, 12) as usize;
    let s = format!("{v:.d$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// A file stem without dots (`basins_omega_1.801` → `basins_omega_1_801`): `with_extension`
/// would cut a stem at its last dot.
pub fn safe(name: &str) -> String {
    name.replace('.', "_")
}

/// Fixed colours of the non-periodic classes.
pub fn fixed_color(name: &str) -> Option<PlotColor> {
    match name {
        "chaotic" => Some(CHAOTIC),
        "quasi-periodic" => Some(QUASI),
        "unsettled" => Some(UNSETTLED),
        "failed" => Some(OTHER),
        _ => None,
    }
}

/// Y-axis name of a section panel.
pub fn section_axis(s: Sec) -> &'static str {
    match s {
        Sec::Strobe => "x (stroboscopic)",
        Sec::DsUp => "x' at x = D_s (up)",
        Sec::DsDown => "x' at x = -D_s (down)",
        Sec::DdUp => "x' at x = D_d (up)",
        Sec::DdDown => "x' at x = -D_d (down)",
        Sec::Impact => "x' before impact",
    }
}

/// Identification settings of basins and continuations: at most `transient` excitation periods
/// before recording `record`.
pub fn identify_options(transient: u64, record: u64) -> IdentifyOptions {
    IdentifyOptions {
        sim: SimOptions {
            method: Method::Dopri {
                rtol: 1e-7,
                atol: 1e-10,
            },
            transient_periods: transient,
            record_periods: record,
            ..Default::default()
        },
        ..Default::default()
    }
}

/// Attractor colours of a basin or continuation: by order, distinct.
fn attractor_colors(n: usize) -> Vec<PlotColor> {
    (0..n).map(palette).collect()
}

/// A box of initial states: `(x0 range, x0' range)`.
pub type StateBox = ((f64, f64), (f64, f64));

/// Basin shares of one model on further boxes of initial states (no figure): the seeds never give
/// their box, and attractor shares depend on it, so share claims are read against several boxes.
/// Returns `(box description, result)` per box, in the order given.
#[allow(clippy::too_many_arguments)]
pub fn basin_boxes(
    ctx: &Ctx,
    dir: &Path,
    name: &str,
    model: &MeshModel,
    n: usize,
    boxes: &[StateBox],
    identify: IdentifyOptions,
) -> Result<Vec<(String, BasinResult)>> {
    let mut out = Vec::new();
    for (i, &(x, v)) in boxes.iter().enumerate() {
        let opts = basin_options(n, x, v, identify);
        let r = ctx.basins(dir, &safe(&format!("{name}_box{i}")), model, &opts)?;
        out.push((box_text(x, v), r));
    }
    Ok(out)
}

/// An `n x n` grid on the box `x0 in x`, `x0' in v`.
fn basin_options(
    n: usize,
    x: (f64, f64),
    v: (f64, f64),
    identify: IdentifyOptions,
) -> BasinOptions {
    let axis = |(min, max): (f64, f64)| Axis { min, max, n };
    BasinOptions {
        x: axis(x),
        v: axis(v),
        identify,
        slice: Default::default(),
    }
}

/// `x0 ∈ [a, b], x0' ∈ [c, d]` for people.
pub fn box_text(x: (f64, f64), v: (f64, f64)) -> String {
    format!(
        "x0 ∈ [{}, {}], x0' ∈ [{}, {}]",
        f(x.0),
        f(x.1),
        f(v.0),
        f(v.1)
    )
}

/// The grid of a basin computation: `n x n` initial states on the box `x0 in x`, `x0' in v`,
/// checkpointed as `dir/name` ([`basin_grid`]) and drawn as `dir/name.png|svg` ([`basin_render`]).
#[derive(Clone, Copy)]
pub struct BasinGrid<'a> {
    /// Name of the checkpoint and of the figure and tables.
    pub name: &'a str,
    /// Initial states per axis.
    pub n: usize,
    /// `x0` range.
    pub x: (f64, f64),
    /// `x0'` range.
    pub v: (f64, f64),
}

/// Basins of `model` on the grid `g`; [`basin_render`] draws them.
pub fn basin_grid(
    ctx: &Ctx,
    dir: &Path,
    g: &BasinGrid,
    model: &MeshModel,
    identify: IdentifyOptions,
) -> Result<BasinResult> {
    let opts = basin_options(g.n, g.x, g.v, identify);
    ctx.basins(dir, &safe(g.name), model, &opts)
}

/// Basins `dir/name.png|svg` with `name_cells.csv` and `name_attractors.csv` from basins `r`
/// computed by [`basin_grid`] on the same grid `g`. Returns the figure and a table of the
/// attractors.
pub fn basin_render(
    ctx: &Ctx,
    dir: &Path,
    g: &BasinGrid,
    title: &str,
    r: &BasinResult,
) -> Result<(Figure, Table)> {
    let BasinGrid { name, n, x, v } = *g;
    let name = &safe(name);
    let cols = attractor_colors(r.attractors.len());
    let black = PlotColor(0, 0, 0);
    let colors: Vec<PlotColor> = r
        .cells
        .iter()
        .map(|&c| match c {
            -1 => black,
            geardyn_analysis::basins::INADMISSIBLE => geardyn_io::figure::INADMISSIBLE,
            i if i >= 0 => cols.get(i as usize).copied().unwrap_or(OTHER),
            _ => OTHER,
        })
        .collect();
    let mut legend: Vec<LegendEntry> = r
        .attractors
        .iter()
        .zip(&cols)
        .map(|(a, c)| {
            LegendEntry::dot(
                format!(
                    "#{} {} {} — {:.1} %",
                    a.id,
                    attractor_name(&a.descriptor),
                    if a.descriptor.healthy {
                        "healthy"
                    } else {
                        "back side"
                    },
                    100.0 * a.fraction
                ),
                *c,
            )
        })
        .collect();
    legend.extend(lost_cells_legend(r, (black, OTHER), |what, pct| {
        format!("{what} — {pct:.1} %")
    }));
    let stem = dir.join(name);
    let grid = ((x.0, x.1, n), (v.0, v.1, n));
    write_basin_raster(&stem, title, r, grid, ("x0", "x0'"), colors, legend)?;
    let cells_csv = dir.join(format!("{name}_cells.csv"));
    write_csv(
        &cells_csv,
        &["x0", "v0", "attractor"],
        r.cells.iter().enumerate().map(|(i, c)| {
            vec![
                exact(r.x.value(i % n)),
                exact(r.v.value(i / n)),
                c.to_string(),
            ]
        }),
    )?;
    let rows: Vec<Vec<String>> = r
        .attractors
        .iter()
        .map(|a| {
            vec![
                a.id.to_string(),
                a.descriptor.label.clone(),
                (if a.descriptor.healthy {
                    "healthy"
                } else {
                    "non-healthy"
                })
                .into(),
                format!("{:.1} %", 100.0 * a.fraction),
                f(a.descriptor.p_id),
                f(a.descriptor.max_force),
                a.descriptor
                    .points
                    .first()
                    .map_or(String::new(), |p| format!("({}, {})", f(p[0]), f(p[1]))),
            ]
        })
        .collect();
    let att_csv = dir.join(format!("{name}_attractors.csv"));
    let table = ctx.table(
        &att_csv,
        &format!("{title}: attractors"),
        &hdr(&[
            "id",
            "label",
            "health",
            "basin share",
            "P_ID",
            "max mesh force",
            "a stroboscopic point (x, x')",
        ]),
        rows,
    )?;
    let caption = format!(
        "{title}. Initial states x0 in [{}, {}], x0' in [{}, {}] ({n} x {n}) at phase 0; colours by attractor, \
         crosses at the attractors' stroboscopic points; {:.0} % of the cells lie on a basin boundary.",
        f(x.0),
        f(x.1),
        f(v.0),
        f(v.1),
        100.0 * r.boundary_fraction
    );
    Ok((ctx.fig(&stem, &caption, &[cells_csv, att_csv]), table))
}

/// Continuation figure `dir/name.png|svg` (basin shares, branch tree) with `name_branches.csv`,
/// and the interval table (`name_intervals.csv`).
pub fn continuation_figure(
    ctx: &Ctx,
    dir: &Path,
    name: &str,
    param: &str,
    c: &ContinuationResult,
    title: &str,
) -> Result<(Figure, Table)> {
    let name = &safe(name);
    let mut values: Vec<f64> = c.points.iter().map(|p| p.value).collect();
    values.sort_by(f64::total_cmp);
    values.dedup();
    let stem = dir.join(name);
    geardyn_io::sweep_output::plot_continuation(
        &stem,
        title,
        (param, "x"),
        &values,
        c,
        &mut geardyn_io::figure::LabelColors::default(),
    )?;
    let br_csv = dir.join(format!("{name}_branches.csv"));
    write_csv(
        &br_csv,
        &[
            param,
            "branch",
            "label",
            "period",
            "healthy",
            "basin_share",
            "max_force",
            "x",
            "v",
        ],
        c.points.iter().map(|p| {
            vec![
                exact(p.value),
                p.branch.to_string(),
                p.label.clone(),
                p.period.to_string(),
                p.healthy.to_string(),
                g(p.fraction),
                g(p.max_force),
                exact(p.x),
                exact(p.v),
            ]
        }),
    )?;
    let fmt = |l: &Vec<(usize, String, f64, f64)>| {
        l.iter()
            .map(|e| {
                if (e.2 - e.3).abs() < 0.005 {
                    format!("{} ({:.0} %)", e.1, 100.0 * e.2)
                } else {
                    format!("{} ({:.0}–{:.0} %)", e.1, 100.0 * e.2, 100.0 * e.3)
                }
            })
            .collect::<Vec<_>>()
            .join(", ")
    };
    let table = ctx.table(
        &dir.join(format!("{name}_intervals.csv")),
        &format!("Attractors over {param} (intervals of the continuation; basin shares of the sampled initial states)"),
        &[
            format!("{param} from"),
            format!("{param} to"),
            "healthy attractors".into(),
            "non-healthy attractors".into(),
        ],
        c.intervals
            .iter()
            .map(|iv| vec![f(iv.from), f(iv.to), fmt(&iv.healthy), fmt(&iv.non_healthy)])
            .collect(),
    )?;
    Ok((
        ctx.fig(
            &stem,
            &format!("{title}: basin shares of healthy and non-healthy attractors (top) and a stroboscopic point of every attractor found, coloured by label (bottom)."),
            &[br_csv],
        ),
        table,
    ))
}

/// One series of a line figure.
pub struct Line {
    /// Legend text.
    pub label: String,
    /// Points.
    pub points: Vec<(f64, f64)>,
    /// Dots instead of a line.
    pub dots: bool,
}

/// A figure of line series in stacked panels `(y label, series)`, with `name.csv` (long format:
/// `panel, series, x, y`); one y range shared by all panels when `same_y` (panels to compare).
#[allow(clippy::too_many_arguments)]
pub fn line_figure(
    ctx: &Ctx,
    dir: &Path,
    name: &str,
    title: &str,
    x_label: &str,
    panels: Vec<(String, Vec<Line>)>,
    hlines: &[f64],
    caption: &str,
    same_y: bool,
) -> Result<Figure> {
    let name = &safe(name);
    let shared_y = if same_y {
        let ys = panels
            .iter()
            .flat_map(|(_, ls)| ls.iter().flat_map(|l| l.points.iter().map(|p| p.1)))
            .filter(|v| v.is_finite());
        let (lo, hi) = ys.fold((f64::INFINITY, f64::NEG_INFINITY), |a, v| {
            (a.0.min(v), a.1.max(v))
        });
        (lo <= hi).then(|| geardyn_io::figure::padded(lo, hi))
    } else {
        None
    };
    let mut labels: Vec<String> = Vec::new();
    for (_, ls) in &panels {
        for l in ls {
            if !l.label.is_empty() && !labels.contains(&l.label) {
                labels.push(l.label.clone());
            }
        }
    }
    let col = |l: &str| {
        labels
            .iter()
            .position(|x| x == l)
            .map_or(PlotColor(60, 60, 60), palette)
    };
    let dotted = |l: &str| {
        panels
            .iter()
            .flat_map(|(_, ls)| ls.iter())
            .any(|x| x.label == l && x.dots)
    };
    let legend = labels
        .iter()
        .map(|l| {
            if dotted(l) {
                LegendEntry::dot(l.clone(), col(l))
            } else {
                LegendEntry::line(l.clone(), col(l))
            }
        })
        .collect();
    let mut rows: Vec<Vec<String>> = Vec::new();
    let fig_panels = panels
        .iter()
        .map(|(yl, ls)| {
            for l in ls {
                rows.extend(
                    l.points
                        .iter()
                        .map(|p| vec![yl.clone(), l.label.clone(), g(p.0), g(p.1)]),
                );
            }
            Panel {
                y_label: yl.clone(),
                layers: ls
                    .iter()
                    .map(|l| Layer {
                        points: l.points.clone(),
                        style: if l.dots {
                            Style::Dots(3)
                        } else {
                            Style::Line(2)
                        },
                        color: col(&l.label),
                    })
                    .collect(),
                hlines: hlines.to_vec(),
                y_range: shared_y,
                ..Default::default()
            }
        })
        .collect();
    let stem = dir.join(name);
    write_figure(
        &stem,
        &Fig {
            title: title.into(),
            x_label: x_label.into(),
            panels: fig_panels,
            legend,
            ..Default::default()
        },
    )?;
    let csv = dir.join(format!("{name}.csv"));
    write_csv(&csv, &["panel", "series", "x", "y"], rows)?;
    Ok(ctx.fig(&stem, caption, &[csv]))
}

/// A phase portrait `dir/name.png|svg` (trajectory, stroboscopic points, impacts) with
/// `name.csv` (`series, x, v`).
pub fn portrait_figure(
    ctx: &Ctx,
    dir: &Path,
    name: &str,
    title: &str,
    series: [(&str, Vec<[f64; 3]>); 3],
    caption: &str,
) -> Result<Figure> {
    let name = &safe(name);
    let mut rows = Vec::new();
    for (label, pts) in &series {
        rows.extend(
            pts.iter()
                .map(|p| vec![label.to_string(), g(p[0]), g(p[1]), g(p[2])]),
        );
    }
    let cols = [palette(0), palette(1), palette(2)];
    let xv = |pts: Vec<[f64; 3]>| -> Vec<(f64, f64)> { pts.iter().map(|p| (p[1], p[2])).collect() };
    let [(l0, p0), (l1, p1), (l2, p2)] = series;
    let (p0, p1, p2) = (xv(p0), xv(p1), xv(p2));
    let stem = dir.join(name);
    write_figure(
        &stem,
        &Fig {
            title: title.into(),
            x_label: "x".into(),
            panels: vec![Panel {
                y_label: "x'".into(),
                layers: vec![
                    Layer {
                        points: p0,
                        style: Style::Line(1),
                        color: cols[0],
                    },
                    Layer {
                        points: p1,
                        style: Style::Dots(3),
                        color: cols[1],
                    },
                    Layer {
                        points: p2,
                        style: Style::Dots(3),
                        color: cols[2],
                    },
                ],
                ..Default::default()
            }],
            legend: vec![
                LegendEntry::line(l0, cols[0]),
                LegendEntry::dot(l1, cols[1]),
                LegendEntry::dot(l2, cols[2]),
            ],
            width: 1000,
            panel_height: 520,
            ..Default::default()
        },
    )?;
    let csv = dir.join(format!("{name}.csv"));
    write_csv(&csv, &["series", "tau", "x", "v"], rows)?;
    Ok(ctx.fig(&stem, caption, &[csv]))
}
