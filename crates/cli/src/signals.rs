//! `geardyn signals`: vibration signals of the broken pair and its healthy twin at the same
//! operating point (dynamic transmission error, mesh force, acceleration), their spectra in
//! orders of the pinion revolution and the gear condition indicators (docs/analyses.md, "Fault
//! signatures").

use crate::run_config::ConfigArgs;
use anyhow::{Context, Result};
use clap::Args;
use geardyn_analysis::indicators::ResidualKind;
use geardyn_analysis::signals::{Na4Reference, SignalsRequest, SIGNAL_NAMES};
use geardyn_analysis::stage_signals::StageSignalsRequest;
use geardyn_exec::{execute, SignalsJob};
use geardyn_io::output::{write_json, write_text};
use geardyn_io::run_record;
use geardyn_io::schema::{
    full, indicators_table, lines_table, signals_table, spectrum_table, tsa_table,
};
use std::path::PathBuf;

/// Arguments of `geardyn signals`.
#[derive(Args, Debug)]
pub struct SignalsArgs {
    #[command(flatten)]
    cfg: ConfigArgs,
    /// Pinion revolutions recorded (a planetary stage: records of whole carrier revolutions and
    /// motion periods; default 1).
    #[arg(long, default_value_t = SignalsRequest::default().revolutions)]
    revolutions: u64,
    /// Pinion revolutions discarded first (a planetary stage: its motion is decided first, from
    /// rest; this many more carrier revolutions are then discarded, default 5).
    #[arg(long, default_value_t = SignalsRequest::default().transient)]
    transient: u64,
    /// Samples per mesh cycle (z1 times that per revolution; a planetary stage: a multiple of
    /// its planets, default the least from 16 up).
    #[arg(long, default_value_t = SignalsRequest::default().samples_per_cycle)]
    samples_per_cycle: u32,
    /// Revolutions per Welch segment of the spectra (order resolution 1 / this).
    #[arg(long, default_value_t = SignalsRequest::default().segment_revolutions)]
    segment_revolutions: u64,
    /// Shaft sidebands of every mesh harmonic removed from the difference signal.
    #[arg(long, default_value_t = SignalsRequest::default().sidebands)]
    sidebands: usize,
    /// Shaft orders 1..=N removed from the difference signal (and from the residual with
    /// --residual mesh_and_shaft).
    #[arg(long, default_value_t = SignalsRequest::default().shaft_orders)]
    shaft_orders: usize,
    /// Residual signal: the TSA without the mesh harmonics (mesh) or also without the shaft
    /// orders (mesh_and_shaft).
    #[arg(long, default_value = SignalsRequest::default().residual.name())]
    residual: String,
    /// NA4/NB4 denominator: the record's own variance (own) or the variance averaged over the
    /// run healthy twin -> broken pair (run).
    #[arg(long, default_value = SignalsRequest::default().na4_reference.name())]
    na4_reference: String,
    /// Output directory.
    #[arg(long, default_value = "out/signals")]
    out: PathBuf,
}

pub fn run(mut a: SignalsArgs, started: f64) -> Result<()> {
    if let Some(t) = crate::train::from_args(&a.cfg)? {
        // (a train: --transient counts carrier revolutions, --revolutions records of whole
        // carrier revolutions; the pair's defaults, left as they are, give the stage's own)
        let (pair, stage) = (SignalsRequest::default(), StageSignalsRequest::default());
        let pair_only = [
            (
                "--segment-revolutions",
                a.segment_revolutions != pair.segment_revolutions,
            ),
            ("--sidebands", a.sidebands != pair.sidebands),
            ("--shaft-orders", a.shaft_orders != pair.shaft_orders),
            ("--residual", a.residual != pair.residual.name()),
            (
                "--na4-reference",
                a.na4_reference != pair.na4_reference.name(),
            ),
        ];
        if let Some((flag, _)) = pair_only.iter().find(|(_, set)| *set) {
            anyhow::bail!("{flag} applies to a pair's signals (its indicators and healthy twin); a planetary stage's signals take --revolutions, --transient and --samples-per-cycle");
        }
        if a.revolutions == 0 {
            anyhow::bail!("--revolutions 0: at least 1 record");
        }
        let own = |v: u64, p: u64, s: u64| if v == p { s } else { v };
        let req = StageSignalsRequest {
            transient_revolutions: own(a.transient, pair.transient, stage.transient_revolutions),
            records: own(a.revolutions, pair.revolutions, stage.records),
            samples_per_cycle: own(
                a.samples_per_cycle.into(),
                pair.samples_per_cycle.into(),
                stage.samples_per_cycle.into(),
            ) as u32,
            ..stage
        };
        return crate::train_signals::signals(&t, &req, &a.out);
    }
    // the default pair is the broken one (a command about a chipped tooth)
    if a.cfg.preset.is_none() && a.cfg.config.is_none() {
        a.cfg.preset = Some("breakage".into());
    }
    let (cfg, scenario) = a.cfg.resolve()?;
    let sim = cfg.sim_options()?;
    let req = SignalsRequest {
        revolutions: a.revolutions,
        transient: a.transient,
        samples_per_cycle: a.samples_per_cycle,
        segment_revolutions: a.segment_revolutions,
        sidebands: a.sidebands,
        shaft_orders: a.shaft_orders,
        residual: ResidualKind::from_name(&a.residual)?,
        na4_reference: Na4Reference::from_name(&a.na4_reference)?,
        y0: [cfg.simulation.x0, cfg.simulation.v0],
        tau0: cfg.simulation.tau0,
        method: sim.method,
    };
    // every setting is checked before the folder is touched
    req.check(&scenario)?;
    let lock = run_record::prepare_folder(&a.out, "signals", None, false)?;
    let t = std::time::Instant::now();
    let job = SignalsJob {
        scenario: &scenario,
        request: &req,
    };
    let r = execute(&job, None, &()).context("signals failed")?;
    let out = &a.out;
    signals_table(&r).write_csv(&out.join("signals.csv"), full)?;
    spectrum_table(&r).write_csv(&out.join("spectrum.csv"), full)?;
    indicators_table(&r).write_csv(&out.join("indicators.csv"), full)?;
    tsa_table(&r).write_csv(&out.join("tsa.csv"), full)?;
    lines_table(&r).write_csv(&out.join("lines.csv"), full)?;
    write_json(
        &out.join("signals.json"),
        &serde_json::json!({ "request": &req, "result": &r }),
    )?;
    write_text(&out.join("config.toml"), &cfg.to_toml())?;
    let context = format!(
        "{} ({})",
        a.cfg.source(),
        geardyn_io::describe::operating_point(&scenario)
    );
    geardyn_io::signal_plots::signal_figures(out, &r, &context, 4)?;
    run_record::write_run_record(
        out,
        "signals",
        &cfg,
        &scenario,
        started,
        run_record::now_unix_s() - started,
    )?;
    drop(lock);
    for n in &r.notes {
        println!("note: {n}");
    }
    for p in &r.pairs {
        let m = &p.motion;
        println!(
            "{} pair: {} ({}), {} impacts per revolution, P_ID {:.4}",
            p.pair, m.label, m.class, m.impacts_per_rev, m.p_id
        );
    }
    if let [h, b] = r.pairs.as_slice() {
        for (k, name) in SIGNAL_NAMES.iter().enumerate() {
            let ratios: Vec<String> = ["rms", "kurtosis", "fm4", "na4", "er"]
                .iter()
                .map(|i| {
                    let (vb, vh) = (
                        b.indicators[k].get(i).unwrap_or(f64::NAN),
                        h.indicators[k].get(i).unwrap_or(f64::NAN),
                    );
                    format!("{i} {:.3}", vb / vh)
                })
                .collect();
            println!("  broken/healthy {name}: {}", ratios.join(", "));
        }
    }
    println!("{:.2} s -> {}", t.elapsed().as_secs_f64(), out.display());
    Ok(())
}
