//! `geardyn stiffness`.

use crate::run_config::ConfigArgs;
use anyhow::{Context, Result};
use clap::Args;
use geardyn_io::output::{write_csv, write_text};
use geardyn_io::plot::{stacked_chart, Mark, Panel, Series, PALETTE};
use std::path::PathBuf;

/// Arguments of `geardyn stiffness`.
#[derive(Args, Debug)]
pub struct StiffnessArgs {
    #[command(flatten)]
    cfg: ConfigArgs,
    /// Output directory.
    #[arg(long, default_value = "out/stiffness")]
    out: PathBuf,
}

pub fn run(a: StiffnessArgs) -> Result<()> {
    let cfg = a.cfg.resolve()?;
    std::fs::create_dir_all(&a.out)
        .with_context(|| format!("cannot create {}", a.out.display()))?;
    write_text(&a.out.join("config.toml"), &cfg.to_toml())?;
    let t = std::time::Instant::now();
    let pair = cfg.pair_model()?;
    let build_time = t.elapsed().as_secs_f64();
    let model = cfg.build_model()?;
    let num = |v: f64| format!("{v}");
    if let Some(pm) = &pair {
        // physical table, every sample of every zone piece (zone borders appear twice: both sides)
        let d = |single: bool| {
            if single {
                cfg.effective_params().map(|p| p.d_single)
            } else {
                cfg.effective_params().map(|p| p.d_double)
            }
        };
        let (dd, ds) = (d(false)?, d(true)?);
        write_csv(
            &a.out.join("stiffness.csv"),
            &[
                "position_cycles",
                "k_pair1_N_per_m",
                "k_pair2_N_per_m",
                "k_mesh_N_per_m",
                "share1",
                "share2",
                "h_drive",
                "h_back",
                "half_backlash",
                "zone",
                "mu1",
                "mu2",
                "film1_um",
                "lambda1",
                "regime1",
            ],
            pm.rows.iter().map(|r| {
                vec![
                    num(r.position),
                    num(r.k_pair1),
                    num(r.k_pair2),
                    num(r.k_mesh),
                    num(r.share1),
                    num(r.share2),
                    num(r.h_drive),
                    num(r.h_back),
                    num(if r.single { ds } else { dd }),
                    (if r.single { "single" } else { "double" }).to_string(),
                    num(r.mu1),
                    num(r.mu2),
                    num(r.film1 * 1e6),
                    num(r.lambda1),
                    (match r.regime1 {
                        0 => "ehl",
                        1 => "mixed",
                        2 => "boundary",
                        _ => "constant_mu",
                    })
                    .to_string(),
                ]
            }),
        )?;
        let mut healthy_spec = pm.spec.clone();
        healthy_spec.breakage = None;
        let healthy = healthy_spec.build()?;
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
        let k1: Vec<(f64, f64)> = pm
            .rows
            .iter()
            .map(|r| (r.position, r.k_pair1 / 1e6))
            .collect();
        let k2: Vec<(f64, f64)> = pm
            .rows
            .iter()
            .filter(|r| r.k_pair2 > 0.0)
            .map(|r| (r.position, r.k_pair2 / 1e6))
            .collect();
        let l1: Vec<(f64, f64)> = pm.rows.iter().map(|r| (r.position, r.share1)).collect();
        let hd: Vec<(f64, f64)> = pm.rows.iter().map(|r| (r.position, r.h_drive)).collect();
        let hb: Vec<(f64, f64)> = pm.rows.iter().map(|r| (r.position, r.h_back)).collect();
        let mut stiff = vec![Series {
            label: "healthy",
            points: &hk,
            mark: Mark::Line,
            color: PALETTE[0],
        }];
        if pm.eps_b.is_some() {
            stiff.push(Series {
                label: "broken",
                points: &bk,
                mark: Mark::Line,
                color: PALETTE[1],
            });
        }
        // a broken pair: show the broken cycle and its neighbours in the detail figure
        stacked_chart(
            &a.out.join("stiffness"),
            "Mesh stiffness over the excitation period",
            "position (mesh cycles)",
            (0.0, cycles),
            &[Panel {
                y_label: "k_m (N/um)",
                series: stiff,
            }],
        )?;
        let (lo, hi) = match pm.spec.breakage {
            Some(b) if pm.cycles > 3 => {
                let nb = b.broken_cycle as f64;
                ((nb - 1.0).max(0.0), (nb + 2.0).min(cycles))
            }
            _ => (0.0, cycles.min(3.0)),
        };
        let win = |v: &[(f64, f64)]| -> Vec<(f64, f64)> {
            v.iter()
                .copied()
                .filter(|p| p.0 >= lo && p.0 <= hi)
                .collect()
        };
        let (hkw, bkw, k1w, k2w, l1w, hdw, hbw) = (
            win(&hk),
            win(&bk),
            win(&k1),
            win(&k2),
            win(&l1),
            win(&hd),
            win(&hb),
        );
        stacked_chart(
            &a.out.join("stiffness_detail"),
            "Pair stiffness, load share and friction factors",
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
                            points: &k1w,
                            mark: Mark::Dots(1),
                            color: PALETTE[2],
                        },
                        Series {
                            label: "leaving pair",
                            points: &k2w,
                            mark: Mark::Dots(1),
                            color: PALETTE[3],
                        },
                    ],
                },
                Panel {
                    y_label: "load share L1",
                    series: vec![Series {
                        label: "",
                        points: &l1w,
                        mark: Mark::Dots(1),
                        color: PALETTE[2],
                    }],
                },
                Panel {
                    y_label: "friction factor h",
                    series: vec![
                        Series {
                            label: "drive side",
                            points: &hdw,
                            mark: Mark::Dots(1),
                            color: PALETTE[0],
                        },
                        Series {
                            label: "back side",
                            points: &hbw,
                            mark: Mark::Dots(1),
                            color: PALETTE[1],
                        },
                    ],
                },
            ],
        )?;
        println!(
            "eps = {:.4}{}, k_av = {:.4e} N/m, omega_n = {:.4e} rad/s; tables for {} cycle(s) x {} samples built in {:.3} s -> {}",
            pm.geom.eps,
            pm.eps_b.map_or(String::new(), |e| format!(", eps_b = {e:.4}")),
            pm.k_av,
            pm.omega_n,
            pm.cycles,
            pm.spec.samples_per_cycle,
            build_time,
            a.out.display()
        );
    } else {
        // dimensionless model only: sample the model's own tables
        let n = 1024 * model.cycles_per_period() as usize;
        let c = model.cycles_per_period() as f64;
        let rows: Vec<[f64; 5]> = (0..n)
            .map(|i| {
                let u = c * i as f64 / n as f64;
                let (hd, hb) = model.friction_factors_at(u);
                [u, model.stiffness_at(u), hd, hb, model.backlash_at(u)]
            })
            .collect();
        write_csv(
            &a.out.join("stiffness.csv"),
            &[
                "position_cycles",
                "k_dimensionless",
                "h_drive",
                "h_back",
                "half_backlash",
            ],
            rows.iter()
                .map(|r| r.iter().map(|v| num(*v)).collect::<Vec<_>>()),
        )?;
        let k: Vec<(f64, f64)> = rows.iter().map(|r| (r[0], r[1])).collect();
        stacked_chart(
            &a.out.join("stiffness"),
            "Dimensionless mesh stiffness k/k_av",
            "position (mesh cycles)",
            (0.0, c),
            &[Panel {
                y_label: "k",
                series: vec![Series {
                    label: "",
                    points: &k,
                    mark: Mark::Line,
                    color: PALETTE[0],
                }],
            }],
        )?;
        println!(
            "dimensionless model (no [pair]): {} samples -> {}",
            n,
            a.out.display()
        );
    }
    Ok(())
}
