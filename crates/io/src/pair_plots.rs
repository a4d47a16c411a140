//! Figures of a physical gear pair along the excitation period: mesh stiffness (healthy and
//! broken), pair stiffness, load sharing, friction factors, half backlash and lubrication.

use crate::plot::{stacked_chart, Mark, Panel, PlotError, Series, PALETTE};
use geardyn_physics::PairModel;
use std::path::{Path, PathBuf};

/// Writes the pair's figures into `dir`; returns `(stem, caption)` of each. `healthy` is the
/// same pair without breakage; `(dd, ds)` the dimensionless half backlash of the two zones.
pub fn pair_figures(
    dir: &Path,
    pm: &PairModel,
    healthy: &PairModel,
    dd: f64,
    ds: f64,
) -> Result<Vec<(PathBuf, String)>, PlotError> {
    let cycles = pm.cycles as f64;
    let hk: Vec<(f64, f64)> = (0..pm.cycles)
        .flat_map(|c| {
            healthy
                .rows
                .iter()
                .map(move |r| (c as f64 + r.position, r.k_mesh / 1e6))
        })
        .collect();
    let bk: Vec<(f64, f64)> = pm
        .rows
        .iter()
        .map(|r| (r.position, r.k_mesh / 1e6))
        .collect();
    let mut figs: Vec<(PathBuf, String)> = Vec::new();
    let stem = dir.join("mesh_stiffness");
    let mut series = vec![Series {
        label: "healthy",
        points: &hk,
        mark: Mark::Line,
        color: PALETTE[0],
    }];
    if pm.eps_b.is_some() {
        series.push(Series {
            label: "broken",
            points: &bk,
            mark: Mark::Line,
            color: PALETTE[1],
        });
    }
    stacked_chart(
        &stem,
        "Mesh stiffness over the excitation period",
        "position (mesh cycles)",
        (0.0, cycles),
        &[Panel {
            y_label: "k_m (N/um)",
            series,
        }],
    )?;
    figs.push((
        stem.clone(),
        "Mesh stiffness k_m over the excitation period (N/µm), healthy and broken pair."
            .to_string(),
    ));
    let nb = pm.spec.breakage.map_or(0, |b| b.broken_cycle) as f64;
    let (lo, hi) = if pm.cycles > 3 {
        ((nb - 1.0).max(0.0), (nb + 2.0).min(cycles))
    } else {
        (0.0, cycles.min(2.0))
    };
    let win = |v: Vec<(f64, f64)>| -> Vec<(f64, f64)> {
        v.into_iter().filter(|p| p.0 >= lo && p.0 <= hi).collect()
    };
    let k1 = win(pm
        .rows
        .iter()
        .map(|r| (r.position, r.k_pair1 / 1e6))
        .collect());
    let k2 = win(pm
        .rows
        .iter()
        .filter(|r| r.k_pair2 > 0.0)
        .map(|r| (r.position, r.k_pair2 / 1e6))
        .collect());
    let l1 = win(pm.rows.iter().map(|r| (r.position, r.share1)).collect());
    let l2 = win(pm
        .rows
        .iter()
        .filter(|r| r.k_pair2 > 0.0)
        .map(|r| (r.position, r.share2))
        .collect());
    let hd = win(pm.rows.iter().map(|r| (r.position, r.h_drive)).collect());
    let hb = win(pm.rows.iter().map(|r| (r.position, r.h_back)).collect());
    let dl = win(pm
        .rows
        .iter()
        .map(|r| (r.position, if r.single { ds } else { dd }))
        .collect());
    let (hkw, bkw) = (win(hk.clone()), win(bk.clone()));
    let lubricated = pm.rows.iter().any(|r| r.regime1 >= 0);
    let mu1 = win(pm.rows.iter().map(|r| (r.position, r.mu1)).collect());
    let mu2 = win(pm
        .rows
        .iter()
        .filter(|r| r.k_pair2 > 0.0)
        .map(|r| (r.position, r.mu2))
        .collect());
    let lam = win(pm.rows.iter().map(|r| (r.position, r.lambda1)).collect());
    let stem = dir.join("pairs_sharing_friction");
    stacked_chart(
        &stem,
        "Pair stiffness, load sharing, friction factors and half backlash",
        "position (mesh cycles)",
        (lo, hi),
        &[
            Panel {
                y_label: "stiffness (N/um)",
                series: vec![
                    Series {
                        label: "healthy mesh",
                        points: &hkw,
                        mark: Mark::Line,
                        color: PALETTE[0],
                    },
                    Series {
                        label: "mesh",
                        points: &bkw,
                        mark: Mark::Line,
                        color: PALETTE[1],
                    },
                    Series {
                        label: "entering pair",
                        points: &k1,
                        mark: Mark::Dots(1),
                        color: PALETTE[2],
                    },
                    Series {
                        label: "leaving pair",
                        points: &k2,
                        mark: Mark::Dots(1),
                        color: PALETTE[3],
                    },
                ],
            },
            Panel {
                y_label: "load share",
                series: vec![
                    Series {
                        label: "entering pair",
                        points: &l1,
                        mark: Mark::Dots(1),
                        color: PALETTE[2],
                    },
                    Series {
                        label: "leaving pair",
                        points: &l2,
                        mark: Mark::Dots(1),
                        color: PALETTE[3],
                    },
                ],
            },
            Panel {
                y_label: "friction factor h",
                series: vec![
                    Series {
                        label: "drive side",
                        points: &hd,
                        mark: Mark::Dots(1),
                        color: PALETTE[0],
                    },
                    Series {
                        label: "back side",
                        points: &hb,
                        mark: Mark::Dots(1),
                        color: PALETTE[1],
                    },
                ],
            },
            Panel {
                y_label: "half backlash D",
                series: vec![Series {
                    label: "",
                    points: &dl,
                    mark: Mark::Line,
                    color: PALETTE[6],
                }],
            },
        ],
    )?;
    if lubricated {
        let stem_l = dir.join("lubrication");
        stacked_chart(
            &stem_l,
            "Lubrication along the cycle: friction coefficients and film parameter",
            "position (mesh cycles)",
            (lo, hi),
            &[
                Panel {
                    y_label: "friction coefficient",
                    series: vec![
                        Series {
                            label: "entering pair",
                            points: &mu1,
                            mark: Mark::Dots(1),
                            color: PALETTE[2],
                        },
                        Series {
                            label: "leaving pair",
                            points: &mu2,
                            mark: Mark::Dots(1),
                            color: PALETTE[3],
                        },
                    ],
                },
                Panel {
                    y_label: "Lambda (entering pair)",
                    series: vec![Series {
                        label: "",
                        points: &lam,
                        mark: Mark::Dots(1),
                        color: PALETTE[0],
                    }],
                },
            ],
        )?;
    }
    figs.push((
        stem.clone(),
        "Around the broken cycle: stiffness of each pair and of the mesh, load shares, friction factors h (drive and back side) and the dimensionless half backlash.".to_string(),
    ));
    if lubricated {
        figs.push((
            dir.join("lubrication"),
            "Multi-state lubrication: friction coefficient of each pair (Xu–Kahraman EHL, mixed, boundary) and the film parameter Lambda = h_min/sigma (Dowson–Higginson film).".to_string(),
        ));
    }
    Ok(figs)
}
