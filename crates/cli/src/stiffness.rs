//! `geardyn stiffness`.

use crate::run_config::ConfigArgs;
use anyhow::Result;
use clap::Args;
use geardyn_io::figure::{palette, write_figure, Figure, Layer, Panel, Style};
use geardyn_io::output::write_text;
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

pub fn run(a: StiffnessArgs, started: f64) -> Result<()> {
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
    if let Some(pm) = &pair {
        // physical table, every sample of every zone piece (zone borders appear twice: both sides)
        let (dd, ds) = (scenario.params().d_double, scenario.params().d_single);
        geardyn_io::schema::pair_stiffness_table(pm.rows.iter(), dd, ds)
            .write_csv(&a.out.join("stiffness.csv"), geardyn_io::schema::full)?;
        let mut healthy_spec = pm.spec.clone();
        healthy_spec.breakage = None;
        let healthy = healthy_spec.build()?;
        let context =
            geardyn_io::sweep_output::operating_point(&a.cfg.source(), scenario.params(), &[]);
        geardyn_io::pair_plots::pair_figures(&a.out, pm, &healthy, dd, ds, &context)?;
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
        let table = geardyn_io::schema::model_stiffness_table(model);
        table.write_csv(&a.out.join("stiffness.csv"), geardyn_io::schema::full)?;
        let n = table.rows();
        let c = model.cycles_per_period() as f64;
        let column = |name: &str| match table.column(name) {
            Some(geardyn_io::schema::Values::F64(v)) => v.clone(),
            _ => Vec::new(),
        };
        let k: Vec<(f64, f64)> = column("position_cycles")
            .into_iter()
            .zip(column("k_dimensionless"))
            .collect();
        write_figure(
            &a.out.join("stiffness"),
            &Figure {
                title: format!("Dimensionless mesh stiffness k/k_av: {}", a.cfg.source()),
                x_label: "position (mesh cycles)".into(),
                x_range: Some((0.0, c)),
                panels: vec![Panel {
                    y_label: "k/k_av".into(),
                    layers: vec![Layer {
                        points: k,
                        style: Style::Line(2),
                        color: palette(0),
                    }],
                    ..Default::default()
                }],
                panel_height: 400,
                ..Default::default()
            },
        )?;
        println!(
            "dimensionless model (no [pair]): {} samples -> {}",
            n,
            a.out.display()
        );
    }
    Ok(())
}
