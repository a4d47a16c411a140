//! Tables and figures of parameter sweeps: bifurcation diagrams, frequency responses, basins and
//! continuations (figures through [`crate::figure`]: legends beside the data, scatter merged per
//! pixel, many distinct colours).

use crate::figure::{
    self, palette, write_figure, write_raster, Figure, FigureError, Layer, LegendEntry,
    RasterFigure, Style, CHAOTIC, OTHER, QUASI, UNSETTLED,
};
use crate::output::{write_csv, OutputError};
use crate::plot::PlotColor;
use geardyn_analysis::basins::BasinResult;
use geardyn_analysis::bifurcation::{Section, TaskResult};
use std::collections::BTreeMap;
use std::path::Path;

fn num(v: f64) -> String {
    format!("{v}")
}

/// `bifurcation.csv`: the columns of [`crate::schema::points_table`], every digit.
pub fn write_bifurcation(
    path: &Path,
    param: &str,
    results: &[TaskResult],
) -> Result<(), OutputError> {
    crate::schema::points_table(param, results).write_csv(path, crate::schema::full)
}

/// `runs.csv`: one row per simulation, the columns of [`crate::schema::runs_table`], every digit.
pub fn write_runs(path: &Path, param: &str, results: &[TaskResult]) -> Result<(), OutputError> {
    crate::schema::runs_table(param, results).write_csv(path, crate::schema::full)
}

/// `impact_force.csv`: the columns of [`crate::schema::impact_force_table`], every digit.
pub fn write_impact_force(
    path: &Path,
    param: &str,
    results: &[TaskResult],
) -> Result<(), OutputError> {
    crate::schema::impact_force_table(param, results).write_csv(path, crate::schema::full)
}

/// The name a run is drawn under: its label when periodic, else its decided class.
fn run_name(run: &geardyn_analysis::bifurcation::Run) -> String {
    if run.motion.is_periodic() {
        run.label.clone()
    } else {
        run.motion.word().to_string()
    }
}

fn fixed_color(name: &str) -> Option<PlotColor> {
    match name {
        "chaotic" => Some(CHAOTIC),
        "quasi-periodic" => Some(QUASI),
        "unsettled" => Some(UNSETTLED),
        "failed" | "diverged" => Some(OTHER),
        _ => None,
    }
}

fn value_range(results: &[TaskResult]) -> (f64, f64) {
    let lo = results
        .iter()
        .map(|r| r.value)
        .fold(f64::INFINITY, f64::min);
    let hi = results
        .iter()
        .map(|r| r.value)
        .fold(f64::NEG_INFINITY, f64::max);
    let pad = 0.015 * (hi - lo).abs().max(1e-9);
    (lo - pad, hi + pad)
}

/// Bifurcation figure: one panel per section (x on the stroboscopic section, the velocity on
/// level and impact sections) against the parameter, the TLE below when computed; the legend
/// (its own column) names each motion. Continuation branches are coloured up/down; otherwise
/// points are coloured by the decided motion (label of periodic runs; chaotic, quasi-periodic,
/// unsettled), with up to [`figure::DISTINCT_COLORS`] distinct colours. Scatter points are
/// merged per pixel, so the SVG stays small for any number of points.
pub fn plot_bifurcation(
    stem: &Path,
    param: &str,
    results: &[TaskResult],
    sections: &[Section],
    title: &str,
) -> Result<(), FigureError> {
    let sweep = results.iter().any(|r| r.task.branch > 0);
    let mut groups: BTreeMap<String, BTreeMap<Section, Vec<(f64, f64)>>> = BTreeMap::new();
    let mut counts: BTreeMap<String, usize> = BTreeMap::new();
    let mut tle: BTreeMap<String, Vec<(f64, f64)>> = BTreeMap::new();
    for r in results {
        for run in &r.runs {
            let key = if sweep {
                format!("sweep {}", r.task.branch_name())
            } else {
                run_name(run)
            };
            *counts.entry(key.clone()).or_default() += 1;
            let g = groups.entry(key.clone()).or_default();
            for &(sec, x, v) in &run.points {
                let y = if sec == Section::Strobe { x } else { v };
                g.entry(sec).or_default().push((r.value, y));
            }
            if let Some(t) = run.tle {
                tle.entry(key).or_default().push((r.value, t));
            }
        }
    }
    let mut order: Vec<String> = counts.keys().cloned().collect();
    order.sort_by(|a, b| counts[b].cmp(&counts[a]).then(a.cmp(b)));
    let flat: BTreeMap<String, Vec<(f64, f64)>> =
        order.iter().map(|n| (n.clone(), vec![])).collect();
    let colored = figure::categorical(flat, &order, &fixed_color);
    let color_of = |n: &str| colored.iter().find(|c| c.0 == n).map_or(OTHER, |c| c.1);
    // dots as large as the columns of values leave room for: single pixels vanish (and their
    // colours cannot be told apart) on a sweep of a few values
    let radius = match results.len() {
        0..=40 => 3,
        41..=150 => 2,
        _ => 1,
    };
    let layers = |get: figure::PointsOf| -> Vec<Layer> {
        order
            .iter()
            .rev()
            .filter_map(|n| {
                get(n).map(|points| Layer {
                    points,
                    style: Style::Dots(radius),
                    color: color_of(n),
                })
            })
            .collect()
    };
    let mut panels: Vec<figure::Panel> = sections
        .iter()
        .map(|sec| figure::Panel {
            y_label: if *sec == Section::Strobe {
                "x (stroboscopic)".to_string()
            } else {
                format!("x' on {}", sec.name())
            },
            layers: layers(&|n| groups.get(n).and_then(|m| m.get(sec)).cloned()),
            ..Default::default()
        })
        .collect();
    if !tle.is_empty() {
        panels.push(figure::Panel {
            y_label: "TLE".into(),
            layers: layers(&|n| tle.get(n).cloned()),
            hlines: vec![0.0],
            weight: 0.7,
            ..Default::default()
        });
    }
    let legend = colored
        .iter()
        .map(|(n, c, _)| LegendEntry::dot(n.clone(), *c))
        .collect();
    write_figure(
        stem,
        &Figure {
            title: title.into(),
            x_label: param.into(),
            x_range: Some(value_range(results)),
            panels,
            legend,
            legend_title: if sweep { "branch" } else { "motion" }.into(),
            ..Default::default()
        },
    )
}

/// `response.csv`: amplitudes of both continuation branches.
pub fn write_response(path: &Path, param: &str, results: &[TaskResult]) -> Result<(), OutputError> {
    let header = [
        param,
        "branch",
        "label",
        "mean_x",
        "rms_x",
        "p2p_x",
        "mean_force",
        "rms_force",
        "p2p_force",
        "max_force",
        "p_id",
    ];
    let rows = results.iter().filter_map(|r| {
        let run = &r.runs[0];
        run.amplitudes.map(|a| {
            vec![
                num(r.value),
                r.task.branch_name().to_string(),
                run.label.clone(),
                num(a.mean_x),
                num(a.rms_x),
                num(a.p2p_x),
                num(a.mean_force),
                num(a.rms_force),
                num(a.p2p_force),
                num(run.max_force),
                num(run.p_id),
            ]
        })
    });
    write_csv(path, &header, rows)
}

/// Frequency-response figure: RMS of `x` and of `F_m`, up and down sweeps (legend beside the
/// panels).
pub fn plot_response(
    stem: &Path,
    param: &str,
    results: &[TaskResult],
    title: &str,
) -> Result<(), FigureError> {
    let branch =
        |b: u8, f: &dyn Fn(&geardyn_analysis::simulate::Amplitudes) -> f64| -> Vec<(f64, f64)> {
            let mut v: Vec<(f64, f64)> = results
                .iter()
                .filter(|r| r.task.branch == b)
                .filter_map(|r| r.runs[0].amplitudes.map(|a| (r.value, f(&a))))
                .collect();
            v.sort_by(|a, b| a.0.total_cmp(&b.0));
            v
        };
    let line = |points: Vec<(f64, f64)>, k: usize| Layer {
        points,
        style: Style::Line(2),
        color: palette(k),
    };
    let dots = |points: Vec<(f64, f64)>, k: usize| Layer {
        points,
        style: Style::Dots(2),
        color: palette(k),
    };
    let (ux, dx) = (branch(1, &|a| a.rms_x), branch(2, &|a| a.rms_x));
    let (uf, df) = (branch(1, &|a| a.rms_force), branch(2, &|a| a.rms_force));
    write_figure(
        stem,
        &Figure {
            title: title.into(),
            x_label: param.into(),
            x_range: Some(value_range(results)),
            panels: vec![
                figure::Panel {
                    y_label: "RMS of x (AC)".into(),
                    layers: vec![
                        line(ux.clone(), 0),
                        dots(ux, 0),
                        line(dx.clone(), 1),
                        dots(dx, 1),
                    ],
                    ..Default::default()
                },
                figure::Panel {
                    y_label: "RMS of F_m (AC)".into(),
                    layers: vec![line(uf, 0), line(df, 1)],
                    ..Default::default()
                },
            ],
            legend: vec![
                LegendEntry::line("sweep up", palette(0)),
                LegendEntry::line("sweep down", palette(1)),
            ],
            ..Default::default()
        },
    )
}

/// Basin image: one distinct colour per attractor (id order), divergent cells black, unresolved
/// grey, crosses at the attractors' stroboscopic points; the legend (beside the image) names each
/// attractor with its label, health and basin share. Equal-colour runs are merged.
pub fn plot_basins(stem: &Path, title: &str, r: &BasinResult) -> Result<(), FigureError> {
    let black = PlotColor(0, 0, 0);
    let colors: Vec<PlotColor> = r
        .cells
        .iter()
        .map(|&c| match c {
            -1 => black,
            i if i >= 0 => palette(i as usize),
            _ => OTHER,
        })
        .collect();
    let mut legend: Vec<LegendEntry> = r
        .attractors
        .iter()
        .map(|at| {
            LegendEntry::dot(
                format!(
                    "#{} {}{}, {} ({:.1} %)",
                    at.id,
                    if at.descriptor.period > 0 {
                        at.descriptor.label.clone()
                    } else {
                        // the decided class, without the crossing rates
                        at.descriptor.motion.word().to_string()
                    },
                    at.descriptor
                        .mesh_period
                        .map_or(String::new(), |m| format!(" [{m} mesh cycles]")),
                    if at.descriptor.healthy {
                        "healthy"
                    } else if at.descriptor.period > 0 {
                        "back-side contact"
                    } else {
                        "not periodic"
                    },
                    100.0 * at.fraction
                ),
                palette(at.id),
            )
        })
        .collect();
    if r.diverged > 0.0 {
        legend.push(LegendEntry::dot(
            format!("divergent ({:.1} %)", 100.0 * r.diverged),
            black,
        ));
    }
    if r.failed > 0.0 {
        legend.push(LegendEntry::dot(
            format!("unresolved ({:.1} %)", 100.0 * r.failed),
            OTHER,
        ));
    }
    let (nx, nv) = (r.x.n.max(1), r.v.n.max(1));
    let (dx, dv) = (
        (r.x.max - r.x.min) / (nx - 1).max(1) as f64,
        (r.v.max - r.v.min) / (nv - 1).max(1) as f64,
    );
    let marks = r
        .attractors
        .iter()
        .flat_map(|a| a.descriptor.points.iter().take(24).map(|p| (p[0], p[1])))
        .filter(|p| p.0 >= r.x.min && p.0 <= r.x.max && p.1 >= r.v.min && p.1 <= r.v.max)
        .collect();
    write_raster(
        stem,
        &RasterFigure {
            title: title.into(),
            x_label: "x0".into(),
            y_label: "x0'".into(),
            x: (r.x.min - dx / 2.0, r.x.max + dx / 2.0, nx),
            y: (r.v.min - dv / 2.0, r.v.max + dv / 2.0, nv),
            colors,
            legend,
            legend_title: "attractor (basin share)".into(),
            colorbar: None,
            marks,
        },
    )
}

/// Continuation figure: basin shares (healthy, non-healthy) and a stroboscopic point of every
/// attractor over the parameter, coloured by label (non-periodic attractors in one grey group).
pub fn plot_continuation(
    stem: &Path,
    title: &str,
    param: &str,
    values: &[f64],
    r: &geardyn_analysis::continuation::ContinuationResult,
) -> Result<(), FigureError> {
    let name = |p: &geardyn_analysis::continuation::BranchPoint| {
        if p.period > 0 {
            format!(
                "{}, {}",
                p.label,
                if p.healthy { "healthy" } else { "back side" }
            )
        } else {
            "not periodic".to_string()
        }
    };
    let mut order: Vec<String> = Vec::new();
    let mut tree: BTreeMap<String, Vec<(f64, f64)>> = BTreeMap::new();
    for p in &r.points {
        let n = name(p);
        if !order.contains(&n) {
            order.push(n.clone());
        }
        tree.entry(n).or_default().push((p.value, p.x));
    }
    let colored = figure::categorical(tree, &order, &|n: &str| {
        (n == "not periodic").then_some(UNSETTLED)
    });
    let share = |healthy: bool| -> Vec<(f64, f64)> {
        values
            .iter()
            .map(|&v| {
                (
                    v,
                    r.points
                        .iter()
                        .filter(|p| p.value == v && p.healthy == healthy)
                        .map(|p| p.fraction)
                        .sum(),
                )
            })
            .collect()
    };
    // the share lines in black and grey, apart from the attractor colours
    let mut legend = vec![
        LegendEntry::line("basin share, healthy", CHAOTIC),
        LegendEntry::line("basin share, non-healthy", QUASI),
    ];
    legend.extend(
        colored
            .iter()
            .map(|(n, c, _)| LegendEntry::dot(n.clone(), *c)),
    );
    let lo = values.first().copied().unwrap_or(0.0);
    let hi = values.last().copied().unwrap_or(1.0);
    write_figure(
        stem,
        &Figure {
            title: title.into(),
            x_label: param.into(),
            x_range: Some(figure::padded(lo, hi)),
            panels: vec![
                figure::Panel {
                    y_label: "basin share".into(),
                    layers: vec![
                        Layer {
                            points: share(true),
                            style: Style::Line(2),
                            color: CHAOTIC,
                        },
                        Layer {
                            points: share(false),
                            style: Style::Line(1),
                            color: QUASI,
                        },
                    ],
                    y_range: Some((-0.03, 1.03)),
                    weight: 0.8,
                    ..Default::default()
                },
                figure::Panel {
                    y_label: "x (a stroboscopic point)".into(),
                    layers: colored
                        .into_iter()
                        .map(|(_, c, points)| Layer {
                            points,
                            style: Style::Dots(2),
                            color: c,
                        })
                        .collect(),
                    ..Default::default()
                },
            ],
            legend,
            legend_title: "attractor".into(),
            ..Default::default()
        },
    )
}
