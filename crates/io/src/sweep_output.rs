//! Tables and figures of parameter sweeps: bifurcation diagrams and frequency responses.

use crate::output::{write_csv, OutputError};
use crate::plot::{attractor_color, raster_chart, Chart, Raster};
use crate::plot::{stacked_chart, Mark, Panel, PlotError, Series, PALETTE};
use geardyn_analysis::basins::BasinResult;
use geardyn_analysis::bifurcation::{Section, TaskResult};
use std::collections::BTreeMap;
use std::path::Path;

fn num(v: f64) -> String {
    format!("{v}")
}

/// `bifurcation.csv`: `param,branch,ic,section,x,v,label`, one row per section point.
pub fn write_bifurcation(
    path: &Path,
    param: &str,
    results: &[TaskResult],
) -> Result<(), OutputError> {
    let header = [param, "branch", "ic", "section", "x", "v", "label"];
    let rows = results.iter().flat_map(|r| {
        r.runs.iter().flat_map(move |run| {
            run.points.iter().map(move |&(sec, x, v)| {
                vec![
                    num(r.value),
                    r.task.branch_name().to_string(),
                    run.ic.to_string(),
                    sec.name().to_string(),
                    num(x),
                    num(v),
                    run.label.clone(),
                ]
            })
        })
    });
    write_csv(path, &header, rows)
}

/// `runs.csv`: one row per simulation with its label, P_ID, forces, amplitudes and TLE.
pub fn write_runs(path: &Path, param: &str, results: &[TaskResult]) -> Result<(), OutputError> {
    let header = [
        param,
        "branch",
        "ic",
        "x0",
        "v0",
        "label",
        "period",
        "healthy",
        "p_id",
        "max_force",
        "min_force",
        "impacts",
        "max_impact_force",
        "rms_x",
        "p2p_x",
        "rms_force",
        "p2p_force",
        "tle",
    ];
    let opt = |v: Option<f64>| v.map(num).unwrap_or_default();
    let rows = results.iter().flat_map(|r| {
        r.runs.iter().map(move |run| {
            let a = run.amplitudes;
            vec![
                num(r.value),
                r.task.branch_name().to_string(),
                run.ic.to_string(),
                num(run.y0[0]),
                num(run.y0[1]),
                run.label.clone(),
                run.period.to_string(),
                run.healthy.to_string(),
                num(run.p_id),
                num(run.max_force),
                num(run.min_force),
                run.impacts.to_string(),
                num(run
                    .impact_force_per_period
                    .iter()
                    .cloned()
                    .fold(0.0, f64::max)),
                opt(a.map(|a| a.rms_x)),
                opt(a.map(|a| a.p2p_x)),
                opt(a.map(|a| a.rms_force)),
                opt(a.map(|a| a.p2p_force)),
                opt(run.tle),
            ]
        })
    });
    write_csv(path, &header, rows)
}

/// Diagram points `(parameter, x)` of one colour group, per section.
type PointsBySection = BTreeMap<Section, Vec<(f64, f64)>>;

/// `impact_force.csv`: the impact-force record of seed A — the largest back-side impact force in
/// each recorded excitation period, per run (`param,branch,ic,period,impact_force`; 0 = no impact).
pub fn write_impact_force(
    path: &Path,
    param: &str,
    results: &[TaskResult],
) -> Result<(), OutputError> {
    let header = [param, "branch", "ic", "period", "impact_force"];
    let rows = results.iter().flat_map(|r| {
        r.runs.iter().flat_map(move |run| {
            run.impact_force_per_period
                .iter()
                .enumerate()
                .map(move |(j, f)| {
                    vec![
                        num(r.value),
                        r.task.branch_name().to_string(),
                        run.ic.to_string(),
                        j.to_string(),
                        num(*f),
                    ]
                })
        })
    });
    write_csv(path, &header, rows)
}

/// Label classes in order of first appearance (stable colours).
fn label_order(results: &[TaskResult]) -> Vec<String> {
    let mut seen = Vec::new();
    for r in results {
        for run in &r.runs {
            if !seen.contains(&run.label) {
                seen.push(run.label.clone());
            }
        }
    }
    seen
}

/// Bifurcation figure: one panel per section (x against the parameter), the TLE below when
/// computed. Continuation branches are coloured up/down; multi-initial points by attractor label
/// (the eight most frequent labels get a legend entry, the rest share grey).
pub fn plot_bifurcation(
    stem: &Path,
    param: &str,
    results: &[TaskResult],
    sections: &[Section],
    title: &str,
) -> Result<(), PlotError> {
    let multi = results.iter().any(|r| r.runs.len() > 1);
    let sweep = results.iter().any(|r| r.task.branch > 0);
    // group key -> points per section
    let mut groups: BTreeMap<(usize, String), PointsBySection> = BTreeMap::new();
    let labels = label_order(results);
    let mut counts: BTreeMap<String, usize> = BTreeMap::new();
    for r in results {
        for run in &r.runs {
            *counts.entry(run.label.clone()).or_default() += 1;
        }
    }
    let mut by_freq: Vec<&String> = labels.iter().collect();
    by_freq.sort_by_key(|l| std::cmp::Reverse(counts[*l]));
    let top: Vec<&String> = by_freq.into_iter().take(8).collect();
    for r in results {
        for run in &r.runs {
            let key = if multi {
                match top.iter().position(|l| **l == run.label) {
                    Some(i) => (i, run.label.clone()),
                    None => (99, "other".to_string()),
                }
            } else if sweep {
                (r.task.branch as usize, r.task.branch_name().to_string())
            } else {
                (0, String::new())
            };
            let g = groups.entry(key).or_default();
            for &(sec, x, v) in &run.points {
                // on a level section x is the level itself: the velocity is the information
                let y = if sec == Section::Strobe { x } else { v };
                g.entry(sec).or_default().push((r.value, y));
            }
        }
    }
    let tle: Vec<(f64, f64)> = results
        .iter()
        .flat_map(|r| {
            r.runs
                .iter()
                .filter_map(move |run| run.tle.map(|t| (r.value, t)))
        })
        .collect();
    let zero: Vec<(f64, f64)> = if tle.is_empty() {
        vec![]
    } else {
        let lo = results
            .iter()
            .map(|r| r.value)
            .fold(f64::INFINITY, f64::min);
        let hi = results
            .iter()
            .map(|r| r.value)
            .fold(f64::NEG_INFINITY, f64::max);
        vec![(lo, 0.0), (hi, 0.0)]
    };
    let y_labels: Vec<String> = sections
        .iter()
        .map(|s| {
            if *s == Section::Strobe {
                "x on strobe".to_string()
            } else {
                format!("x' on {}", s.name())
            }
        })
        .collect();
    let mut panels: Vec<Panel> = Vec::new();
    for (si, sec) in sections.iter().enumerate() {
        let mut series = Vec::new();
        for ((idx, name), secs) in &groups {
            if let Some(pts) = secs.get(sec) {
                let color = if *idx == 99 {
                    RGB_GREY
                } else {
                    PALETTE[*idx % PALETTE.len()]
                };
                series.push(Series {
                    label: if si == 0 { name.as_str() } else { "" },
                    points: pts,
                    mark: Mark::Dots(1),
                    color,
                });
            }
        }
        panels.push(Panel {
            y_label: &y_labels[si],
            series,
        });
    }
    if !tle.is_empty() {
        panels.push(Panel {
            y_label: "TLE",
            series: vec![
                Series {
                    label: "",
                    points: &zero,
                    mark: Mark::Line,
                    color: RGB_GREY,
                },
                Series {
                    label: "",
                    points: &tle,
                    mark: Mark::Dots(2),
                    color: PALETTE[6],
                },
            ],
        });
    }
    let lo = results
        .iter()
        .map(|r| r.value)
        .fold(f64::INFINITY, f64::min);
    let hi = results
        .iter()
        .map(|r| r.value)
        .fold(f64::NEG_INFINITY, f64::max);
    let pad = 0.02 * (hi - lo).abs().max(1e-9);
    stacked_chart(stem, title, param, (lo - pad, hi + pad), &panels)
}

const RGB_GREY: plotters::style::RGBColor = plotters::style::RGBColor(160, 160, 160);

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

/// Frequency-response figure: RMS of `x` and of `F_m`, up and down sweeps.
pub fn plot_response(
    stem: &Path,
    param: &str,
    results: &[TaskResult],
    title: &str,
) -> Result<(), PlotError> {
    let branch =
        |b: u8, f: &dyn Fn(&geardyn_analysis::simulate::Amplitudes) -> f64| -> Vec<(f64, f64)> {
            let mut v: Vec<(f64, f64)> = results
                .iter()
                .filter(|r| r.task.branch == b)
                .filter_map(|r| r.runs[0].amplitudes.map(|a| (r.value, f(&a))))
                .collect();
            v.sort_by(|a, b| a.0.partial_cmp(&b.0).unwrap_or(std::cmp::Ordering::Equal));
            v
        };
    let (ux, dx) = (branch(1, &|a| a.rms_x), branch(2, &|a| a.rms_x));
    let (uf, df) = (branch(1, &|a| a.rms_force), branch(2, &|a| a.rms_force));
    let lo = results
        .iter()
        .map(|r| r.value)
        .fold(f64::INFINITY, f64::min);
    let hi = results
        .iter()
        .map(|r| r.value)
        .fold(f64::NEG_INFINITY, f64::max);
    let panels = vec![
        Panel {
            y_label: "RMS of x (AC)",
            series: vec![
                Series {
                    label: "sweep up",
                    points: &ux,
                    mark: Mark::Line,
                    color: PALETTE[0],
                },
                Series {
                    label: "",
                    points: &ux,
                    mark: Mark::Dots(2),
                    color: PALETTE[0],
                },
                Series {
                    label: "sweep down",
                    points: &dx,
                    mark: Mark::Line,
                    color: PALETTE[1],
                },
                Series {
                    label: "",
                    points: &dx,
                    mark: Mark::Dots(2),
                    color: PALETTE[1],
                },
            ],
        },
        Panel {
            y_label: "RMS of F_m (AC)",
            series: vec![
                Series {
                    label: "",
                    points: &uf,
                    mark: Mark::Line,
                    color: PALETTE[0],
                },
                Series {
                    label: "",
                    points: &df,
                    mark: Mark::Line,
                    color: PALETTE[1],
                },
            ],
        },
    ];
    stacked_chart(stem, title, param, (lo, hi), &panels)
}

/// Basin image: healthy attractors in a blue–green family, unstable ones in a red–orange family
/// (each in id order), divergent cells black, unresolved grey; the legend names each attractor
/// with its label and basin fraction.
pub fn plot_basins(stem: &Path, title: &str, r: &BasinResult) -> Result<(), PlotError> {
    let (mut kh, mut ku) = (0, 0);
    let colors_by_id: Vec<_> = r
        .attractors
        .iter()
        .map(|at| {
            let k = if at.descriptor.healthy {
                &mut kh
            } else {
                &mut ku
            };
            *k += 1;
            attractor_color(at.descriptor.healthy, *k - 1)
        })
        .collect();
    let black = plotters::style::RGBColor(0, 0, 0);
    let grey = plotters::style::RGBColor(170, 170, 170);
    let colors: Vec<_> = r
        .cells
        .iter()
        .map(|&c| match c {
            -1 => black,
            -2 => grey,
            i => colors_by_id[i as usize],
        })
        .collect();
    let mut legend: Vec<(String, _)> = r
        .attractors
        .iter()
        .zip(&colors_by_id)
        .map(|(at, c)| {
            (
                format!(
                    "#{} {} {} ({:.1}%)",
                    at.id,
                    at.descriptor.label,
                    geardyn_analysis::simulate::health_text(
                        at.descriptor.healthy,
                        at.descriptor.period > 0
                    ),
                    100.0 * at.fraction
                ),
                *c,
            )
        })
        .collect();
    if r.diverged > 0.0 {
        legend.push((format!("divergent ({:.1}%)", 100.0 * r.diverged), black));
    }
    if r.failed > 0.0 {
        legend.push((format!("unresolved ({:.1}%)", 100.0 * r.failed), grey));
    }
    raster_chart(
        stem,
        &Chart {
            title,
            x_label: "x0",
            y_label: "x0'",
        },
        &Raster {
            x: (r.x.min, r.x.max, r.x.n),
            y: (r.v.min, r.v.max, r.v.n),
            colors: &colors,
        },
        &legend,
        None,
    )
}

/// Continuation figure: basin fractions (healthy, and healthy + unstable) and the branch tree
/// (first stroboscopic point of each attractor) over the parameter.
pub fn plot_continuation(
    stem: &Path,
    title: &str,
    param: &str,
    values: &[f64],
    r: &geardyn_analysis::continuation::ContinuationResult,
) -> Result<(), PlotError> {
    let lo = values.first().copied().unwrap_or(0.0);
    let hi = values.last().copied().unwrap_or(1.0);

    let frac = |healthy: bool| -> Vec<(f64, f64)> {
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
    let (fh, fu) = (frac(true), frac(false));
    let stacked: Vec<(f64, f64)> = fh.iter().zip(&fu).map(|(h, u)| (h.0, h.1 + u.1)).collect();
    let nb = r.points.iter().map(|p| p.branch + 1).max().unwrap_or(0);
    let branches: Vec<Vec<(f64, f64)>> = (0..nb)
        .map(|b| {
            r.points
                .iter()
                .filter(|p| p.branch == b)
                .map(|p| (p.value, p.x))
                .collect()
        })
        .collect();
    let names: Vec<String> = (0..nb)
        .map(|b| {
            let l = r
                .points
                .iter()
                .find(|p| p.branch == b)
                .map_or(String::new(), |p| p.label.clone());
            format!("branch {b} ({l})")
        })
        .collect();
    let mut tree = Vec::new();
    for (b, pts) in branches.iter().enumerate() {
        let c = PALETTE[b % PALETTE.len()];
        tree.push(Series {
            label: if b < 8 { names[b].as_str() } else { "" },
            points: pts,
            mark: Mark::Line,
            color: c,
        });
        tree.push(Series {
            label: "",
            points: pts,
            mark: Mark::Dots(3),
            color: c,
        });
    }
    stacked_chart(
        stem,
        title,
        param,
        (lo, hi),
        &[
            Panel {
                y_label: "basin fraction",
                series: vec![
                    Series {
                        label: "healthy + non-healthy",
                        points: &stacked,
                        mark: Mark::Line,
                        color: PALETTE[1],
                    },
                    Series {
                        label: "healthy",
                        points: &fh,
                        mark: Mark::Line,
                        color: PALETTE[0],
                    },
                ],
            },
            Panel {
                y_label: "x on strobe (tree)",
                series: tree,
            },
        ],
    )
}
