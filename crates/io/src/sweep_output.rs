//! Tables and figures of parameter sweeps: bifurcation diagrams, frequency responses, basins and
//! continuations (figures through [`crate::figure`]: legends beside the data, scatter merged per
//! pixel, many distinct colours).

use crate::figure::{
    self, colormap, palette, write_figure, write_raster, Figure, FigureError, LabelColors, Layer,
    LegendEntry, Panel, RasterFigure, Style, CHAOTIC, LEGEND_MAX, OTHER, QUASI, UNSETTLED,
};
use crate::output::{write_csv, OutputError};
use crate::schema::full;
use geardyn_analysis::basins::BasinResult;
use geardyn_analysis::bifurcation::{Section, TaskResult};
use geardyn_analysis::orbit_branches::BifurcationKind;
use plotters::style::RGBColor;
use std::collections::BTreeMap;
use std::path::Path;

/// The name a run is drawn under: its label when periodic, else its decided class.
fn run_name(run: &geardyn_analysis::bifurcation::Run) -> String {
    if run.motion.is_periodic() {
        run.label.clone()
    } else {
        run.motion.word().to_string()
    }
}

/// The name an attractor is drawn under: its label when periodic, else its decided class
/// (without the crossing rates).
pub fn attractor_name(d: &geardyn_analysis::attractor::Descriptor) -> &str {
    if d.period > 0 {
        &d.label
    } else {
        d.motion.word()
    }
}

/// The operating point for a figure's title: what the model comes from (`source`, e.g.
/// `preset classic`), then omega, F and xi, those in `swept` (the figure's axes) left out:
/// `preset classic, omega = 1.2, F = 0.1, xi = 0.05`.
pub fn operating_point(source: &str, p: &geardyn_model::ModelParams, swept: &[&str]) -> String {
    let mut parts: Vec<String> = Vec::new();
    if !source.is_empty() {
        parts.push(source.to_string());
    }
    for (name, v) in [("omega", p.omega), ("F", p.load), ("xi", p.xi)] {
        if !swept.contains(&name) {
            parts.push(format!("{name} = {}", figure::tick(v)));
        }
    }
    parts.join(", ")
}

/// Points of a scatter layer that fall apart on a figure, per value of the parameter the layer
/// has points at: `y` told apart to 1/500 of the layer's `y` range (a periodic run records the
/// same stroboscopic points again every period).
fn distinct_per_value(points: &[(f64, f64)]) -> f64 {
    let (lo, hi) = points
        .iter()
        .map(|p| p.1)
        .filter(|y| y.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |r, y| {
            (r.0.min(y), r.1.max(y))
        });
    let q = ((hi - lo) / 500.0).max(1e-12 * lo.abs().max(hi.abs()).max(1.0));
    let mut keys: Vec<(u64, i64)> = points
        .iter()
        .filter(|p| p.0.is_finite() && p.1.is_finite())
        .map(|p| (p.0.to_bits(), ((p.1 - lo) / q).round() as i64))
        .collect();
    keys.sort_unstable();
    keys.dedup();
    let mut xs: Vec<u64> = keys.iter().map(|k| k.0).collect();
    xs.dedup();
    keys.len() as f64 / xs.len().max(1) as f64
}

/// Half-size in pixels of the dots of a scatter layer over a sweep of `values` values: a layer
/// of few distinct points per value (periodic branches) in dots the larger the fewer the values
/// (8 pixels for up to 30 values, 6 for up to 100); denser layers (chaotic bands) and long sweeps
/// in 4-pixel dots, never smaller (visible at 100 % zoom).
pub fn dot_radius(points: &[(f64, f64)], values: usize) -> u32 {
    let per_value = distinct_per_value(points);
    match (per_value <= 16.0, values) {
        (true, 0..=30) => 4,
        (true, 31..=100) => 3,
        _ => 2,
    }
}

/// A figure over the swept parameter `param` (the values of `results`, with a margin, on the x
/// axis): `panels` stacked, `legend` beside them under `legend_title`.
pub fn write_sweep_figure(
    stem: &Path,
    title: &str,
    param: &str,
    results: &[TaskResult],
    panels: Vec<Panel>,
    legend: Vec<LegendEntry>,
    legend_title: &str,
) -> Result<(), FigureError> {
    write_figure(
        stem,
        &Figure {
            title: title.into(),
            x_label: param.into(),
            x_range: Some(value_range(results)),
            panels,
            legend,
            legend_title: legend_title.into(),
            ..Default::default()
        },
    )
}

/// The x range of a sweep diagram: its values with a margin of 1.5 %.
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
/// unsettled) from `colors` (a label keeps its colour in every figure of a command), at most
/// [`LEGEND_MAX`] legend entries (the rarest labels as "N other labels"). Dots are sized by
/// the points per value ([`dot_radius`]). Scatter points are merged per pixel, so the SVG stays
/// small for any number of points.
pub fn plot_bifurcation(
    stem: &Path,
    param: &str,
    results: &[TaskResult],
    sections: &[Section],
    title: &str,
    colors: &mut LabelColors,
) -> Result<(), FigureError> {
    let sweep = results.iter().any(|r| r.task.branch > 0);
    let mut groups: BTreeMap<String, BTreeMap<Section, Vec<(f64, f64)>>> = BTreeMap::new();
    let mut counts: BTreeMap<String, usize> = BTreeMap::new();
    let mut tle: BTreeMap<String, Vec<(f64, f64)>> = BTreeMap::new();
    // runs per name that reached it after transient chaos (the legend counts them)
    let mut transients: BTreeMap<String, usize> = BTreeMap::new();
    for r in results {
        for run in &r.runs {
            let key = if sweep {
                format!("sweep {}", r.task.branch_name())
            } else {
                run_name(run)
            };
            *counts.entry(key.clone()).or_default() += 1;
            if matches!(
                run.motion,
                geardyn_analysis::classify::Motion::TransientChaos { .. }
            ) {
                *transients.entry(key.clone()).or_default() += 1;
            }
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
    let colored = figure::categorical_keyed(flat, &order, &figure::class_color, colors);
    let color_of = |n: &str| colored.iter().find(|c| c.0 == n).map_or(OTHER, |c| c.1);
    let values = {
        let mut v: Vec<f64> = results.iter().map(|r| r.value).collect();
        v.sort_by(f64::total_cmp);
        v.dedup();
        v.len()
    };
    // the labels grouped as "N other labels" are drawn as one layer under that name
    let grouped = |n: &str| !colored.iter().any(|c| c.0 == n);
    let layers = |get: figure::PointsOf| -> Vec<Layer> {
        let mut out: Vec<Layer> = Vec::new();
        let rest: Vec<(f64, f64)> = order
            .iter()
            .filter(|n| grouped(n))
            .filter_map(|n| get(n))
            .flatten()
            .collect();
        if !rest.is_empty() {
            out.push(Layer {
                style: Style::Dots(dot_radius(&rest, values)),
                points: rest,
                color: OTHER,
            });
        }
        // the most frequent motion first, the rarer ones drawn over it
        out.extend(order.iter().rev().filter(|n| !grouped(n)).filter_map(|n| {
            get(n).map(|points| Layer {
                style: Style::Dots(dot_radius(&points, values)),
                points,
                color: color_of(n),
            })
        }));
        out
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
        .map(|(n, c, _)| match transients.get(n) {
            Some(k) => LegendEntry::dot(format!("{n}, {k} after transient chaos"), *c),
            None => LegendEntry::dot(n.clone(), *c),
        })
        .collect();
    let legend_title = if sweep { "branch" } else { "motion" };
    write_sweep_figure(stem, title, param, results, panels, legend, legend_title)
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
        "class",
        "decided_by",
        "periods_integrated",
    ];
    let rows = results.iter().filter_map(|r| {
        let run = &r.runs[0];
        run.amplitudes.map(|a| {
            vec![
                full(r.value),
                r.task.branch_name().to_string(),
                run.label.clone(),
                full(a.mean_x),
                full(a.rms_x),
                full(a.p2p_x),
                full(a.mean_force),
                full(a.rms_force),
                full(a.p2p_force),
                full(run.max_force),
                full(run.p_id),
                run.motion.word().to_string(),
                run.decided_by.name().to_string(),
                run.periods_integrated.to_string(),
            ]
        })
    });
    write_csv(path, &header, rows)
}

/// Frequency-response figure: RMS of `x` and of `F_m` over the parameter, up and down sweeps
/// (legend beside the panels). Lines join periodic values only: a chaotic, quasi-periodic or
/// unsettled value is a dot in its class colour (black, dark grey, grey), and the line breaks
/// there.
pub fn plot_response(
    stem: &Path,
    param: &str,
    results: &[TaskResult],
    title: &str,
) -> Result<(), FigureError> {
    type Amp = geardyn_analysis::simulate::Amplitudes;
    // (value, amplitude, class name of a non-periodic run) of one branch, by value
    let branch = |b: u8, f: &dyn Fn(&Amp) -> f64| -> Vec<(f64, f64, Option<String>)> {
        let mut v: Vec<(f64, f64, Option<String>)> = results
            .iter()
            .filter(|r| r.task.branch == b)
            .filter_map(|r| {
                let run = &r.runs[0];
                let class = (!run.motion.is_periodic()).then(|| run_name(run));
                run.amplitudes.map(|a| (r.value, f(&a), class))
            })
            .collect();
        v.sort_by(|a, b| a.0.total_cmp(&b.0));
        v
    };
    let mut classes: Vec<String> = Vec::new();
    let mut layers_of = |f: &dyn Fn(&Amp) -> f64| -> Vec<Layer> {
        let mut periodic = Vec::new();
        let mut other: BTreeMap<String, Vec<(f64, f64)>> = BTreeMap::new();
        for (k, b) in [1u8, 2].into_iter().enumerate() {
            let pts = branch(b, f);
            let line: Vec<(f64, f64)> = pts
                .iter()
                .map(|p| (p.0, if p.2.is_none() { p.1 } else { f64::NAN }))
                .collect();
            periodic.push(Layer {
                points: line.clone(),
                style: Style::Line(2),
                color: palette(k),
            });
            periodic.push(Layer {
                points: line,
                style: Style::Dots(3),
                color: palette(k),
            });
            for (v, y, c) in pts {
                if let Some(c) = c {
                    other.entry(c).or_default().push((v, y));
                }
            }
        }
        for (c, pts) in other {
            if !classes.contains(&c) {
                classes.push(c.clone());
            }
            periodic.push(Layer {
                points: pts,
                style: Style::Dots(3),
                color: figure::class_color(&c).unwrap_or(OTHER),
            });
        }
        periodic
    };
    let x_layers = layers_of(&|a| a.rms_x);
    let f_layers = layers_of(&|a| a.rms_force);
    let mut legend = vec![
        LegendEntry::line("sweep up (periodic)", palette(0)),
        LegendEntry::line("sweep down (periodic)", palette(1)),
    ];
    classes.sort();
    legend.extend(classes.iter().map(|c| {
        LegendEntry::dot(
            format!("{c} (no line)"),
            figure::class_color(c).unwrap_or(OTHER),
        )
    }));
    let panels = vec![
        figure::Panel {
            y_label: "RMS of x (AC)".into(),
            layers: x_layers,
            ..Default::default()
        },
        figure::Panel {
            y_label: "RMS of F_m (AC)".into(),
            layers: f_layers,
            ..Default::default()
        },
    ];
    write_sweep_figure(
        stem,
        title,
        param,
        results,
        panels,
        legend,
        "branch / motion",
    )
}

/// Basin image: one distinct colour per attractor (id order), divergent cells black, unresolved
/// grey, crosses at the attractors' stroboscopic points; the legend (beside the image) names each
/// attractor with its label, health and basin share. At most [`LEGEND_MAX`] legend entries: the
/// attractors of the smallest basins beyond that are drawn as one group "N other attractors"
/// (light brown). Equal-colour runs are merged. `labels` name the axes (the pair: `x0`, `x0'`).
pub fn plot_basins(
    stem: &Path,
    title: &str,
    r: &BasinResult,
    labels: (&str, &str),
) -> Result<(), FigureError> {
    let black = CHAOTIC;
    let fixed = usize::from(r.diverged > 0.0)
        + usize::from(r.failed > 0.0)
        + usize::from(r.inadmissible > 0.0);
    let room = if r.attractors.len() + fixed <= LEGEND_MAX {
        r.attractors.len()
    } else {
        LEGEND_MAX.saturating_sub(fixed + 1)
    };
    // the attractors of the largest basins are named, in id order
    let mut by_share: Vec<usize> = (0..r.attractors.len()).collect();
    by_share.sort_by(|&a, &b| {
        r.attractors[b]
            .fraction
            .total_cmp(&r.attractors[a].fraction)
            .then(a.cmp(&b))
    });
    let mut named: Vec<usize> = by_share[..room].to_vec();
    named.sort_by_key(|&i| r.attractors[i].id);
    let color_of_id: BTreeMap<usize, RGBColor> = named
        .iter()
        .enumerate()
        .map(|(k, &i)| (r.attractors[i].id, palette(k)))
        .collect();
    let colors: Vec<RGBColor> = r
        .cells
        .iter()
        .map(|&c| match c {
            -1 => black,
            geardyn_analysis::basins::INADMISSIBLE => figure::INADMISSIBLE,
            i if i >= 0 => color_of_id.get(&(i as usize)).copied().unwrap_or(OTHER),
            _ => UNSETTLED,
        })
        .collect();
    let mut legend: Vec<LegendEntry> = named
        .iter()
        .map(|&i| {
            let at = &r.attractors[i];
            LegendEntry::dot(
                format!(
                    "#{} {}{}, {} ({:.1} %)",
                    at.id,
                    attractor_name(&at.descriptor),
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
                color_of_id[&at.id],
            )
        })
        .collect();
    if named.len() < r.attractors.len() {
        let rest: f64 = by_share[room..]
            .iter()
            .map(|&i| r.attractors[i].fraction)
            .sum();
        legend.push(LegendEntry::dot(
            format!(
                "{} other attractors ({:.1} %)",
                r.attractors.len() - named.len(),
                100.0 * rest
            ),
            OTHER,
        ));
    }
    legend.extend(lost_cells_legend(r, (black, UNSETTLED), |what, pct| {
        format!("{what} ({pct:.1} %)")
    }));
    let x = (r.x.min, r.x.max, r.x.n.max(1));
    let v = (r.v.min, r.v.max, r.v.n.max(1));
    write_basin_raster(stem, title, r, (x, v), labels, colors, legend)
}

/// The legend entries of the cells of `r` that reached no attractor, in `colors` (divergent,
/// unresolved), each with its share (`label(what, percent)`), and of the cells behind the rigid
/// back stop (their share of the grid; every other share is of the admissible cells); none for
/// a share of 0.
pub fn lost_cells_legend(
    r: &BasinResult,
    colors: (RGBColor, RGBColor),
    label: impl Fn(&str, f64) -> String,
) -> Vec<LegendEntry> {
    let mut entries: Vec<LegendEntry> = [
        ("divergent", r.diverged, colors.0),
        ("unresolved", r.failed, colors.1),
    ]
    .into_iter()
    .filter(|e| e.1 > 0.0)
    .map(|(what, share, color)| LegendEntry::dot(label(what, 100.0 * share), color))
    .collect();
    if r.inadmissible > 0.0 {
        // (its share is of the grid, every other of the cells in front of the stop)
        entries.push(LegendEntry::dot(
            format!(
                "behind the stop: {:.1} % of grid, not run",
                100.0 * r.inadmissible
            ),
            figure::INADMISSIBLE,
        ));
    }
    entries
}

/// Writes the basin image `stem` of `r` on the grid `x` × `v` (`(min, max, cells)` of each axis:
/// the cells tile `[min, max]`, their centres at `min + (i + 1/2)(max - min)/cells` as
/// [`geardyn_analysis::basins::Axis::value`] puts them): a colour per cell, `legend` beside the image, crosses at the
/// attractors' stroboscopic points (up to 24 each) inside the grid; `labels` name the axes.
pub fn write_basin_raster(
    stem: &Path,
    title: &str,
    r: &BasinResult,
    (x, v): ((f64, f64, usize), (f64, f64, usize)),
    labels: (&str, &str),
    colors: Vec<RGBColor>,
    legend: Vec<LegendEntry>,
) -> Result<(), FigureError> {
    let marks = r
        .attractors
        .iter()
        .flat_map(|a| a.descriptor.points.iter().take(24).map(|p| (p[0], p[1])))
        .filter(|p| p.0 >= x.0 && p.0 <= x.1 && p.1 >= v.0 && p.1 <= v.1)
        .collect();
    write_raster(
        stem,
        &RasterFigure {
            title: title.into(),
            x_label: labels.0.into(),
            y_label: labels.1.into(),
            x: (x.0, x.1, x.2),
            y: (v.0, v.1, v.2),
            colors,
            legend,
            legend_title: if r.inadmissible > 0.0 {
                "attractor (share in front of the stop)".into()
            } else {
                "attractor (basin share)".into()
            },
            colorbar: None,
            marks,
        },
    )
}

/// Continuation figure: basin shares (healthy, non-healthy) and a stroboscopic point of every
/// attractor over the parameter, coloured by label (non-periodic attractors in one grey group);
/// `point` names the coordinate of the points (the pair: `x`).
pub fn plot_continuation(
    stem: &Path,
    title: &str,
    (param, point): (&str, &str),
    values: &[f64],
    r: &geardyn_analysis::continuation::ContinuationResult,
    colors: &mut LabelColors,
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
    let colored = figure::categorical_keyed(
        tree,
        &order,
        &|n: &str| (n == "not periodic").then_some(UNSETTLED),
        colors,
    );
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
                    y_label: format!("{point} (a stroboscopic point)"),
                    layers: colored
                        .into_iter()
                        .map(|(_, c, points)| Layer {
                            style: Style::Dots(dot_radius(&points, values.len())),
                            points,
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

/// Figure of periodic-orbit branches (`geardyn orbits`, the report): stable stretches as lines,
/// unstable ones as dots, one colour per orbit period, the bifurcation points marked, over the
/// brute-force diagram `diagram` (`(value, x)` strobe points, grey). `title` states the preset and
/// the fixed parameters.
pub fn plot_orbits(
    stem: &Path,
    title: &str,
    param: &str,
    c: &geardyn_analysis::orbit_branches::Continuation,
    diagram: &[(f64, f64)],
) -> Result<(), FigureError> {
    use geardyn_analysis::orbit_branches::BranchPoint;
    let mut layers = Vec::new();
    let mut legend = Vec::new();
    if !diagram.is_empty() {
        let grey = RGBColor(120, 120, 120);
        layers.push(Layer {
            points: diagram.to_vec(),
            style: Style::Dots(1),
            color: grey,
        });
        legend.push(LegendEntry::dot("simulated (strobe)", grey));
    }
    // one colour per orbit period (the branches of one period share it)
    let mut periods: Vec<u32> = c.points.iter().map(|p| p.orbit.period).collect();
    periods.sort_unstable();
    periods.dedup();
    let branches = c.ends.len().max(1);
    for (k, &period) in periods.iter().enumerate() {
        let color = palette(k);
        let mut any_stable = false;
        let mut any_unstable = false;
        for b in 0..branches {
            let pts: Vec<&BranchPoint> = c
                .points
                .iter()
                .filter(|p| p.branch == b && p.orbit.period == period)
                .collect();
            if pts.is_empty() {
                continue;
            }
            // stable stretches as lines (a NaN breaks the line where the orbit is unstable),
            // unstable ones as dots
            let stable: Vec<(f64, f64)> = pts
                .iter()
                .map(|p| {
                    if p.orbit.stable {
                        (p.param, p.orbit.y[0])
                    } else {
                        (f64::NAN, f64::NAN)
                    }
                })
                .collect();
            let unstable: Vec<(f64, f64)> = pts
                .iter()
                .filter(|p| !p.orbit.stable)
                .map(|p| (p.param, p.orbit.y[0]))
                .collect();
            any_stable |= pts.iter().any(|p| p.orbit.stable);
            any_unstable |= !unstable.is_empty();
            layers.push(Layer {
                points: stable,
                style: Style::Line(2),
                color,
            });
            layers.push(Layer {
                points: unstable,
                style: Style::Dots(1),
                color,
            });
        }
        if any_stable {
            legend.push(LegendEntry::line(format!("period {period}, stable"), color));
        }
        if any_unstable {
            legend.push(LegendEntry::dot(
                format!("period {period}, unstable"),
                color,
            ));
        }
    }
    for kind in BifurcationKind::ALL {
        let color = match kind {
            BifurcationKind::PeriodDoubling => RGBColor(200, 0, 0),
            BifurcationKind::Fold => RGBColor(0, 0, 0),
            BifurcationKind::Torus => RGBColor(128, 0, 160),
            BifurcationKind::Grazing => RGBColor(0, 140, 60),
            BifurcationKind::CornerCollision => RGBColor(230, 120, 0),
            BifurcationKind::Pitchfork => RGBColor(0, 90, 200),
            BifurcationKind::BranchPoint => RGBColor(120, 90, 200),
            BifurcationKind::StabilityChange => RGBColor(0, 150, 160),
        };
        let pts: Vec<(f64, f64)> = c
            .bifurcations
            .iter()
            .filter(|b| b.kind == kind)
            .map(|b| (b.param, b.orbit.y[0]))
            .collect();
        if !pts.is_empty() {
            layers.push(Layer {
                points: pts,
                style: Style::Dots(4),
                color,
            });
            legend.push(LegendEntry::dot(kind.name(), color));
        }
    }
    let fig = Figure {
        title: title.to_string(),
        x_label: param.to_string(),
        panels: vec![Panel {
            y_label: "x at the strobe".into(),
            layers,
            weight: 1.6,
            ..Default::default()
        }],
        legend,
        ..Default::default()
    };
    write_figure(stem, &fig)
}

/// The range of the finite values (`(inf, -inf)` when none).
fn finite_range(vals: &[f64]) -> (f64, f64) {
    vals.iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        })
}

/// How a map's metric is coloured.
#[derive(Clone, Copy, Debug)]
pub struct MetricScale<'a> {
    /// The metric's name (the colour bar's).
    pub metric: &'a str,
    /// A range the colour scale always covers (a ratio whose ideal is 1, say: equal planets'
    /// load-sharing factors differ from 1 by rounding, which a scale of their own extremes would
    /// paint as contrast).
    pub cover: Option<(f64, f64)>,
    /// Legend entry of the cells without a value.
    pub missing: &'a str,
}

impl<'a> MetricScale<'a> {
    /// The scale of a metric over its own finite extremes, cells without a value being failed
    /// runs.
    pub fn of(metric: &'a str) -> Self {
        MetricScale {
            metric,
            cover: None,
            missing: "no value (failed run)",
        }
    }
}

/// Heatmap `stem` of a two-parameter map: `vals` row-major over `y` rows of the `x` values
/// (`(name, values)` of each axis, evenly spaced), on the colour map between the finite values'
/// extremes (widened to `scale.cover`; a colour bar named after the metric), cells without a
/// value grey. Returns the finite range of the values.
pub fn plot_metric_map(
    stem: &Path,
    title: &str,
    (xp, xv): (&str, &[f64]),
    (yp, yv): (&str, &[f64]),
    vals: &[f64],
    scale: MetricScale,
) -> Result<(f64, f64), FigureError> {
    let (v_lo, v_hi) = finite_range(vals);
    let (lo, hi) = match scale.cover {
        Some((a, b)) if v_lo <= v_hi => (v_lo.min(a), v_hi.max(b)),
        _ => (v_lo, v_hi),
    };
    let span = if hi > lo { hi - lo } else { 1.0 };
    let colors: Vec<_> = vals
        .iter()
        .map(|v| {
            if v.is_finite() {
                colormap((v - lo) / span)
            } else {
                UNSETTLED
            }
        })
        .collect();
    let cell = |v: &[f64]| {
        if v.len() > 1 {
            (v[1] - v[0]).abs()
        } else {
            1.0
        }
    };
    let (dx, dy) = (cell(xv), cell(yv));
    write_raster(
        stem,
        &RasterFigure {
            title: title.into(),
            x_label: xp.to_string(),
            y_label: yp.to_string(),
            x: (xv[0] - dx / 2.0, xv[xv.len() - 1] + dx / 2.0, xv.len()),
            y: (yv[0] - dy / 2.0, yv[yv.len() - 1] + dy / 2.0, yv.len()),
            colors,
            legend: if vals.iter().any(|v| !v.is_finite()) {
                vec![LegendEntry::dot(scale.missing, UNSETTLED)]
            } else {
                vec![]
            },
            legend_title: String::new(),
            colorbar: Some((
                if lo.is_finite() { lo } else { 0.0 },
                if hi.is_finite() { hi } else { 1.0 },
                scale.metric.to_string(),
            )),
            marks: vec![],
        },
    )?;
    Ok((v_lo, v_hi))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn periodic_branches_get_visible_dots() {
        // a period-1 run records its one stroboscopic point 100 times per value
        let periodic: Vec<(f64, f64)> = (0..40)
            .flat_map(|i| std::iter::repeat_n((i as f64, 0.01 * i as f64), 100))
            .collect();
        assert_eq!(dot_radius(&periodic, 40), 3);
        assert_eq!(dot_radius(&periodic, 12), 4);
        assert_eq!(dot_radius(&periodic, 400), 2);
        // a chaotic band: hundreds of distinct points per value
        let chaotic: Vec<(f64, f64)> = (0..4)
            .flat_map(|i| (0..300).map(move |k| (i as f64, k as f64)))
            .collect();
        assert_eq!(dot_radius(&chaotic, 40), 2);
        assert_eq!(dot_radius(&[], 40), 3);
    }

    #[test]
    fn titles_leave_the_swept_parameter_out() {
        let p = geardyn_model::presets::by_name("classic").unwrap();
        let t = operating_point("preset classic", &p, &["omega"]);
        assert!(t.starts_with("preset classic, F = "), "{t}");
        assert!(t.contains("xi = ") && !t.contains("omega"), "{t}");
    }
}
