//! `geardyn stiffness`.

use crate::run_config::ConfigArgs;
use anyhow::Result;
use clap::Args;
use geardyn_io::output::{write_csv, write_text};
use geardyn_io::plot::{stacked_chart, Mark, Panel, Series, PALETTE};
use geardyn_io::run_record;
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
    let started = run_record::now_unix_s();
    let (cfg, scenario) = a.cfg.resolve()?;
    let _lock = run_record::prepare_folder(&a.out, "stiffness", None, false)?;
    write_text(&a.out.join("config.toml"), &cfg.to_toml())?;
    run_record::write_run_record(&a.out, "stiffness", &cfg, &scenario, started, 0.0)?;
    // time a fresh build of the pair's tables (the scenario already holds one)
    let t = std::time::Instant::now();
    let pair = match cfg.pair.as_ref() {
        Some(spec) => Some(spec.build()?),
        None => None,
    };
    let build_time = t.elapsed().as_secs_f64();
    let model = scenario.model();
    let num = |v: f64| format!("{v}");
    if let Some(pm) = &pair {
        // physical table, every sample of every zone piece (zone borders appear twice: both sides)
        let (dd, ds) = (scenario.params().d_double, scenario.params().d_single);
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
        geardyn_io::pair_plots::pair_figures(&a.out, pm, &healthy, dd, ds)?;
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
