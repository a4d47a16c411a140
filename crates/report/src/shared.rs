//! Figures with their data, shared by the plans: sweep diagrams (one panel per section, points
//! coloured by attractor label, TLE / force / P_ID panels), basins, continuations, maps and
//! line plots. Every figure writes the CSV of what it draws next to it.

use crate::classes;
use crate::readings::f;
use crate::runner::{hdr, Ctx};
use crate::{Figure, Table};
use anyhow::Result;
use geardyn_analysis::attractor::IdentifyOptions;
use geardyn_analysis::basins::{Axis, BasinOptions, BasinResult};
use geardyn_analysis::bifurcation::{Section as Sec, TaskResult};
use geardyn_analysis::continuation::ContinuationResult;
use geardyn_analysis::simulate::{Method, SimOptions};
use geardyn_io::figure::RGBColor as PlotColor;
use geardyn_io::figure::{
    categorical, palette, write_figure, write_raster, Figure as Fig, Layer, LegendEntry, Panel,
    RasterFigure, Style, CHAOTIC, OTHER, QUASI, UNSETTLED,
};
use geardyn_io::output::write_csv;
use geardyn_model::MeshModel;
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::Path;

pub use crate::maps::{class_map_figure, map_figure};
pub use crate::orbit_figures::{attach_trajectory, branch_both_ways, orbit_figure};

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

/// What a sweep figure shows besides the sections.
#[derive(Clone, Debug, Default)]
pub struct SweepPanels {
    /// TLE panel (when computed).
    pub tle: bool,
    /// Maximum mesh force panel.
    pub max_force: bool,
    /// P_ID panel.
    pub p_id: bool,
    /// Impact-force record (largest impact force of every recorded excitation period).
    pub impact_force: bool,
}

/// How a label is described in legends: health and, for multi-cycle excitation, every period
/// in mesh cycles that runs of the label have (one label in revolutions can hold a 3 -> 6
/// mesh-cycle doubling).
fn legend_text(
    name: &str,
    healthy: bool,
    mesh_periods: &BTreeSet<usize>,
    periodic: bool,
) -> String {
    if !periodic {
        return name.to_string();
    }
    let mut s = name.to_string();
    if !mesh_periods.is_empty() {
        let list: Vec<String> = mesh_periods.iter().map(|m| m.to_string()).collect();
        let unit = if list == ["1"] {
            "mesh cycle"
        } else {
            "mesh cycles"
        };
        s.push_str(&format!(" ({} {unit})", list.join(", ")));
    }
    s.push_str(if healthy { ", healthy" } else { ", back side" });
    s
}

/// The sweep diagram `dir/name.png|svg` with `name_points.csv` and `name_runs.csv` (and
/// `name_impact_force.csv`).
#[allow(clippy::too_many_arguments)]
pub fn sweep_figure(
    ctx: &Ctx,
    dir: &Path,
    name: &str,
    param: &str,
    results: &[TaskResult],
    sections: &[Sec],
    panels: &SweepPanels,
    title: &str,
    caption: &str,
) -> Result<Figure> {
    let name = &safe(name);
    // groups by displayed name, over every run
    let mut groups: BTreeMap<String, BTreeMap<Sec, Vec<(f64, f64)>>> = BTreeMap::new();
    let mut counts: HashMap<String, usize> = HashMap::new();
    let mut info: HashMap<String, (bool, BTreeSet<usize>, bool)> = HashMap::new();
    type ByName = BTreeMap<String, Vec<(f64, f64)>>;
    let mut extra: BTreeMap<&str, ByName> = BTreeMap::new();
    let mut point_rows: Vec<Vec<String>> = Vec::new();
    let mut impact_rows: Vec<Vec<String>> = Vec::new();
    for r in results {
        for run in &r.runs {
            let nm = classes::name(run);
            *counts.entry(nm.clone()).or_default() += 1;
            let entry = info.entry(nm.clone()).or_insert((
                run.healthy,
                BTreeSet::new(),
                run.motion.is_periodic(),
            ));
            entry
                .1
                .extend(run.mesh_period.filter(|_| run.motion.is_periodic()));
            let g_ = groups.entry(nm.clone()).or_default();
            for &sec in sections {
                let mut pts: Vec<&(Sec, f64, f64)> =
                    run.points.iter().filter(|p| p.0 == sec).collect();
                if run.motion.is_periodic() {
                    // a periodic orbit repeats its points: keep each once
                    let mut seen = std::collections::HashSet::new();
                    pts.retain(|p| seen.insert((g(p.1), g(p.2))));
                }
                let cap = if r.runs.len() > 1 {
                    POINTS_PER_RUN_MULTI
                } else {
                    POINTS_PER_RUN
                };
                let keep = pts.len().min(cap);
                for &&(s, x, v) in pts.iter().skip(pts.len() - keep) {
                    let y = if s == Sec::Strobe { x } else { v };
                    g_.entry(sec).or_default().push((r.value, y));
                    point_rows.push(vec![
                        exact(r.value),
                        r.task.branch_name().into(),
                        run.ic.to_string(),
                        s.name().into(),
                        g(x),
                        g(v),
                        nm.clone(),
                    ]);
                }
            }
            let mut put = |k: &'static str, y: f64| {
                if y.is_finite() {
                    extra
                        .entry(k)
                        .or_default()
                        .entry(nm.clone())
                        .or_default()
                        .push((r.value, y));
                }
            };
            if let Some(t) = run.tle {
                put("tle", t);
            }
            put("max_force", run.max_force);
            put("p_id", run.p_id);
            if panels.impact_force {
                for (j, &fi) in run.impact_force_per_period.iter().enumerate() {
                    if fi > 0.0 {
                        extra
                            .entry("impact")
                            .or_default()
                            .entry(nm.clone())
                            .or_default()
                            .push((r.value, fi));
                    }
                    impact_rows.push(vec![
                        exact(r.value),
                        r.task.branch_name().into(),
                        run.ic.to_string(),
                        j.to_string(),
                        g(fi),
                    ]);
                }
            }
        }
    }
    // colour order: periodic labels by frequency, then the fixed classes
    let mut order: Vec<String> = counts.keys().cloned().collect();
    order.sort_by(|a, b| counts[b].cmp(&counts[a]).then(a.cmp(b)));
    let flat: BTreeMap<String, Vec<(f64, f64)>> =
        order.iter().map(|n| (n.clone(), vec![])).collect();
    let colored = categorical(flat, &order, &fixed_color);
    let color_of: HashMap<String, PlotColor> = {
        let mut m: HashMap<String, PlotColor> =
            colored.iter().map(|(n, c, _)| (n.clone(), *c)).collect();
        for n in &order {
            m.entry(n.clone()).or_insert(OTHER);
        }
        m
    };
    let legend: Vec<LegendEntry> = colored
        .iter()
        .map(|(n, c, _)| {
            let empty = (false, BTreeSet::new(), false);
            let (h, mp, per) = info.get(n).unwrap_or(&empty);
            LegendEntry::dot(legend_text(n, *h, mp, *per), *c)
        })
        .collect();
    let layers_of = |by_name: geardyn_io::figure::PointsOf, r: u32| -> Vec<Layer> {
        // draw the most frequent last so that it stays visible; sparse panels get larger dots
        let total: usize = order
            .iter()
            .filter_map(|n| by_name(n))
            .map(|p| p.len())
            .sum();
        let r = if total < 20_000 { r.max(2) } else { r };
        order
            .iter()
            .rev()
            .filter_map(|n| {
                by_name(n).map(|pts| Layer {
                    points: pts,
                    style: Style::Dots(r),
                    color: color_of[n],
                })
            })
            .collect()
    };
    let mut fig_panels: Vec<Panel> = Vec::new();
    for &sec in sections {
        fig_panels.push(Panel {
            y_label: section_axis(sec).into(),
            layers: layers_of(&|n| groups.get(n).and_then(|m| m.get(&sec)).cloned(), 1),
            ..Default::default()
        });
    }
    let mut extra_panel = |k: &str, label: &str, zero: bool| {
        if let Some(m) = extra.get(k) {
            fig_panels.push(Panel {
                y_label: label.into(),
                layers: layers_of(&|n| m.get(n).cloned(), 2),
                hlines: if zero { vec![0.0] } else { vec![] },
                weight: 0.7,
                ..Default::default()
            });
        }
    };
    if panels.impact_force {
        extra_panel("impact", "impact force per period", false);
    }
    if panels.max_force {
        extra_panel("max_force", "max mesh force", false);
    }
    if panels.p_id {
        extra_panel("p_id", "P_ID", false);
    }
    if panels.tle {
        extra_panel("tle", "TLE", true);
    }
    let lo = results
        .iter()
        .map(|r| r.value)
        .fold(f64::INFINITY, f64::min);
    let hi = results
        .iter()
        .map(|r| r.value)
        .fold(f64::NEG_INFINITY, f64::max);
    let pad = 0.015 * (hi - lo).abs().max(1e-9);
    let stem = dir.join(name);
    write_figure(
        &stem,
        &Fig {
            title: title.into(),
            x_label: param.into(),
            x_range: Some((lo - pad, hi + pad)),
            panels: fig_panels,
            legend,
            legend_title: "motion".into(),
            ..Default::default()
        },
    )?;
    let pts_csv = dir.join(format!("{name}_points.csv"));
    write_csv(
        &pts_csv,
        &[param, "branch", "ic", "section", "x", "v", "label"],
        point_rows,
    )?;
    let runs_csv = dir.join(format!("{name}_runs.csv"));
    geardyn_io::schema::runs_table(param, results).write_csv(&runs_csv, g)?;
    let mut data = vec![pts_csv, runs_csv];
    if panels.impact_force {
        let p = dir.join(format!("{name}_impact_force.csv"));
        write_csv(
            &p,
            &[param, "branch", "ic", "period", "impact_force"],
            impact_rows,
        )?;
        data.push(p);
    }
    Ok(ctx.fig(&stem, caption, &data))
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

/// Basins of `model` on an `n x n` grid of the box `x0 in x`, `x0' in v` (checkpointed as
/// `dir/name`); [`basin_render`] draws them.
#[allow(clippy::too_many_arguments)]
pub fn basin_grid(
    ctx: &Ctx,
    dir: &Path,
    name: &str,
    model: &MeshModel,
    n: usize,
    x: (f64, f64),
    v: (f64, f64),
    identify: IdentifyOptions,
) -> Result<BasinResult> {
    let opts = basin_options(n, x, v, identify);
    ctx.basins(dir, &safe(name), model, &opts)
}

/// Basins `dir/name.png|svg` with `name_cells.csv` and `name_attractors.csv` from basins `r`
/// computed by [`basin_grid`] with the same `name`, `n`, `x` and `v`. Returns the figure and a
/// table of the attractors.
#[allow(clippy::too_many_arguments)]
pub fn basin_render(
    ctx: &Ctx,
    dir: &Path,
    name: &str,
    n: usize,
    x: (f64, f64),
    v: (f64, f64),
    title: &str,
    r: &BasinResult,
) -> Result<(Figure, Table)> {
    let name = &safe(name);
    let cols = attractor_colors(r.attractors.len());
    let black = PlotColor(0, 0, 0);
    let colors: Vec<PlotColor> = r
        .cells
        .iter()
        .map(|&c| match c {
            -1 => black,
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
                    if a.descriptor.period > 0 {
                        a.descriptor.label.as_str()
                    } else {
                        a.descriptor.motion.word()
                    },
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
    if r.diverged > 0.0 {
        legend.push(LegendEntry::dot(
            format!("divergent — {:.1} %", 100.0 * r.diverged),
            black,
        ));
    }
    if r.failed > 0.0 {
        legend.push(LegendEntry::dot(
            format!("unresolved — {:.1} %", 100.0 * r.failed),
            OTHER,
        ));
    }
    let marks: Vec<(f64, f64)> = r
        .attractors
        .iter()
        .flat_map(|a| a.descriptor.points.iter().take(24).map(|p| (p[0], p[1])))
        .filter(|p| p.0 >= x.0 && p.0 <= x.1 && p.1 >= v.0 && p.1 <= v.1)
        .collect();
    let (dx, dv) = (
        (x.1 - x.0) / (n - 1).max(1) as f64,
        (v.1 - v.0) / (n - 1).max(1) as f64,
    );
    let stem = dir.join(name);
    write_raster(
        &stem,
        &RasterFigure {
            title: title.into(),
            x_label: "x0".into(),
            y_label: "x0'".into(),
            x: (x.0 - dx / 2.0, x.1 + dx / 2.0, n),
            y: (v.0 - dv / 2.0, v.1 + dv / 2.0, n),
            colors,
            legend,
            legend_title: "attractor (basin share)".into(),
            colorbar: None,
            marks,
        },
    )?;
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
        param,
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
/// `panel, series, x, y`).
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
) -> Result<Figure> {
    line_figure_y(
        ctx, dir, name, title, x_label, panels, hlines, caption, false,
    )
}

/// [`line_figure`] with one y range shared by all panels when `same_y` (panels to compare).
#[allow(clippy::too_many_arguments)]
pub fn line_figure_y(
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_legend_lists_every_mesh_period_of_a_label() {
        let m: BTreeSet<usize> = [6, 3].into_iter().collect();
        assert_eq!(
            legend_text("1-20-0", true, &m, true),
            "1-20-0 (3, 6 mesh cycles), healthy"
        );
        assert_eq!(
            legend_text("1-40-40", false, &BTreeSet::new(), true),
            "1-40-40, back side"
        );
        assert_eq!(legend_text("chaotic", false, &m, false), "chaotic");
        let one: BTreeSet<usize> = [1].into_iter().collect();
        assert_eq!(
            legend_text("1-0-0", true, &one, true),
            "1-0-0 (1 mesh cycle), healthy"
        );
    }
}
