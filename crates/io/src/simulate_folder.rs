//! The folder of one simulation (`geardyn simulate`, Python `simulate(out=...)`): the resolved
//! configuration, trajectory, stroboscopic points, events, section crossings, `summary.json`,
//! the time-history, mesh-force and phase-portrait figures, and `run.json`. One home for what the
//! folder holds and for the fields `summary.json` adds to the [`Summary`].

use crate::figure::{
    decimate, palette, tick, write_figure, Figure, FigureError, Layer, LegendEntry, Panel, Style,
    CHAOTIC,
};
use crate::output::{self, OutputError};
use crate::{run_record, Config};
use geardyn_analysis::classify::{simulate_decided, Decide};
use geardyn_analysis::simulate::{SimOptions, SimResult, Summary};
use geardyn_scenario::Scenario;
use std::path::Path;

/// A finished simulation, as the folder records it.
pub struct Finished<'a> {
    /// What the model comes from, for the figures' titles (`preset classic`, `config <file>`).
    pub source: &'a str,
    /// The configuration, overrides applied.
    pub cfg: &'a Config,
    /// What was integrated.
    pub scenario: &'a Scenario,
    /// The record.
    pub res: &'a SimResult,
    /// Its decided summary.
    pub summary: &'a Summary,
    /// The settings of the record (transient as extended by the decision, method used).
    pub used: &'a SimOptions,
    /// The settings asked for.
    pub requested: &'a SimOptions,
    /// Wall time of the integration, seconds.
    pub elapsed_s: f64,
}

/// Failure to write the folder.
#[derive(Debug, thiserror::Error)]
pub enum FolderWriteError {
    /// A data file.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// A figure.
    #[error(transparent)]
    Figure(#[from] FigureError),
}

/// The fields `summary.json` holds beside the [`Summary`]: the parameters integrated, contact
/// durations, the excitation period, the transient and record used and asked for, the methods,
/// the work and the wall time.
pub fn summary_extra(f: &Finished<'_>) -> serde_json::Value {
    let (res, used, opts) = (f.res, f.used, f.requested);
    serde_json::json!({
        "parameters": f.scenario.record(),
        "contact_durations": { "drive": res.mesh().durations[0], "separated": res.mesh().durations[1], "back": res.mesh().durations[2] },
        "excitation_period": f.scenario.model().excitation_period(),
        "transient_periods": used.transient_periods,
        "transient_requested": opts.transient_periods,
        "record_periods": used.record_periods,
        "record_requested": opts.record_periods,
        "method": used.method,
        "method_requested": opts.method,
        "steps": res.steps,
        "rhs_evals": res.rhs_evals,
        "wall_time_s": f.elapsed_s,
    })
}

/// Writes the folder `out` (prepared and locked by the caller:
/// [`run_record::prepare_folder`]); `started_unix_s` is when the run began.
pub fn write(out: &Path, f: &Finished<'_>, started_unix_s: f64) -> Result<(), FolderWriteError> {
    let res = f.res;
    output::write_text(&out.join("config.toml"), &f.cfg.to_toml())?;
    output::write_trajectory(&out.join("trajectory.csv"), res)?;
    output::write_strobe(&out.join("strobe.csv"), res)?;
    output::write_events(&out.join("events.csv"), res)?;
    output::write_sections(&out.join("sections.csv"), res)?;
    output::write_summary(&out.join("summary.json"), f.summary, summary_extra(f))?;
    let title_tail = crate::sweep_output::operating_point(f.source, f.scenario.params(), &[]);
    plots(out, f.scenario.model(), res, &title_tail)?;
    run_record::write_run_record(
        out,
        "simulate",
        f.cfg,
        f.scenario,
        started_unix_s,
        run_record::now_unix_s() - started_unix_s,
    )?;
    Ok(())
}

/// The time history, mesh force and phase portrait; `op` (the operating point) ends each title.
fn plots(
    out: &Path,
    model: &geardyn_model::MeshModel,
    res: &SimResult,
    op: &str,
) -> Result<(), FigureError> {
    let ts = model.excitation_period();
    // the time history and mesh force show the last few excitation periods
    let shown = if model.cycles_per_period() > 1 {
        1.0
    } else {
        5.0
    };
    let t_end = res.final_state.0;
    let window: Vec<_> = res
        .mesh()
        .trajectory
        .iter()
        .filter(|p| p.tau >= t_end - shown * ts)
        .collect();
    let xs: Vec<(f64, f64)> = window.iter().map(|p| (p.tau, p.x)).collect();
    let fs: Vec<(f64, f64)> = window.iter().map(|p| (p.tau, p.mesh_force)).collect();
    let (dd, ds) = model.backlash_levels();
    let (t0, t1) = (xs.first().map_or(0.0, |p| p.0), t_end);
    let level = |v: f64, color| Layer {
        points: vec![(t0, v), (t1, v)],
        style: Style::Line(1),
        color,
    };
    let gold = palette(4);
    let mut layers = vec![level(ds, CHAOTIC), level(-ds, CHAOTIC)];
    let mut legend = vec![
        LegendEntry::line("x", palette(0)),
        LegendEntry::line(format!("±D_s = {}", tick(ds)), CHAOTIC),
    ];
    if dd != ds {
        layers.push(level(dd, gold));
        layers.push(level(-dd, gold));
        legend.push(LegendEntry::line(format!("±D_d = {}", tick(dd)), gold));
    }
    layers.push(Layer {
        points: decimate(&xs, 20_000),
        style: Style::Line(1),
        color: palette(0),
    });
    let x_range = Some((t0, t1));
    let periods = if shown > 1.0 {
        "last 5 excitation periods"
    } else {
        "last excitation period"
    };
    // one panel over the window shown, under the title `what`
    let over_time = |name: &str, what: &str, panel: Panel, legend: Vec<LegendEntry>| {
        write_figure(
            &out.join(name),
            &Figure {
                title: format!("{what} ({periods}): {op}"),
                x_label: "τ (dimensionless time)".into(),
                x_range,
                panels: vec![panel],
                legend,
                panel_height: 460,
                ..Default::default()
            },
        )
    };
    let x_panel = Panel {
        y_label: "x (units of b_c)".into(),
        layers,
        ..Default::default()
    };
    over_time("time_history", "Time history", x_panel, legend)?;
    let force_panel = Panel {
        y_label: "F_m (units of k_av b_c)".into(),
        layers: vec![Layer {
            points: decimate(&fs, 20_000),
            style: Style::Line(1),
            color: palette(1),
        }],
        hlines: vec![0.0],
        ..Default::default()
    };
    over_time("mesh_force", "Dynamic mesh force", force_panel, vec![])?;
    let stride = (res.mesh().trajectory.len() / 40_000).max(1);
    let phase: Vec<(f64, f64)> = res
        .mesh()
        .trajectory
        .iter()
        .step_by(stride)
        .map(|p| (p.x, p.v))
        .collect();
    let strobe: Vec<(f64, f64)> = res.strobe.iter().map(|p| (p.y[0], p.y[1])).collect();
    write_figure(
        &out.join("phase_portrait"),
        &Figure {
            title: format!("Phase portrait and stroboscopic Poincaré section: {op}"),
            x_label: "x (units of b_c)".into(),
            panels: vec![Panel {
                y_label: "x'".into(),
                layers: vec![
                    Layer {
                        points: phase,
                        style: Style::Line(1),
                        color: palette(5),
                    },
                    Layer {
                        points: strobe,
                        style: Style::Dots(4),
                        color: palette(1),
                    },
                ],
                ..Default::default()
            }],
            legend: vec![
                LegendEntry::line("trajectory", palette(5)),
                LegendEntry::dot("Poincaré points", palette(1)),
            ],
            width: 1000,
            panel_height: 640,
            ..Default::default()
        },
    )?;
    Ok(())
}

/// Excitation periods a simulation keeps in its trajectory by default (the last ones).
pub const DEFAULT_TRAJECTORY_PERIODS: u64 = 10;

/// Most excitation periods a simulation keeps in its trajectory.
pub const MAX_TRAJECTORY_PERIODS: u64 = 1_000_000;

/// Why a simulation did not run or its folder was not written.
#[derive(Debug, thiserror::Error)]
pub enum SimulateError {
    /// The configuration does not resolve to a model.
    #[error("configuration rejected")]
    Rejected(#[source] crate::ConfigError),
    /// The simulation settings or the work cap.
    #[error(transparent)]
    Config(#[from] crate::ConfigError),
    /// `trajectory_periods` out of `1 ..= MAX_TRAJECTORY_PERIODS`.
    #[error("trajectory_periods = {0}: allowed 1 ..= {MAX_TRAJECTORY_PERIODS}")]
    TrajectoryPeriods(u64),
    /// The output folder refused.
    #[error(transparent)]
    Folder(#[from] run_record::FolderError),
    /// The integration failed.
    #[error("integration failed")]
    Integration(#[source] geardyn_analysis::simulate::SimError),
    /// The folder's files could not be written.
    #[error(transparent)]
    Write(#[from] FolderWriteError),
}

/// A simulation that ran: everything [`Finished`] refers to, owned.
pub struct Simulated {
    /// What the model comes from.
    pub source: String,
    /// The configuration, overrides applied.
    pub cfg: Config,
    /// What was integrated.
    pub scenario: Scenario,
    /// The record.
    pub res: SimResult,
    /// Its decided summary.
    pub summary: Summary,
    /// The settings of the record.
    pub used: SimOptions,
    /// The settings asked for.
    pub requested: SimOptions,
    /// Wall time of the integration, seconds.
    pub elapsed_s: f64,
}

impl Simulated {
    /// The run as the folder's writer sees it.
    pub fn finished(&self) -> Finished<'_> {
        Finished {
            source: &self.source,
            cfg: &self.cfg,
            scenario: &self.scenario,
            res: &self.res,
            summary: &self.summary,
            used: &self.used,
            requested: &self.requested,
            elapsed_s: self.elapsed_s,
        }
    }
}

/// One simulation, the way `geardyn simulate` and Python's `simulate` run it: the configuration
/// `cfg` (overrides applied) resolved and checked, its work checked, the folder `out` (when
/// given) claimed and locked before the run, the run decided ([`simulate_decided`]), the last
/// `trajectory_periods` excitation periods of the trajectory kept (`None`: all), the folder
/// written.
pub fn simulate(
    cfg: Config,
    source: String,
    trajectory_periods: Option<u64>,
    out: Option<&Path>,
) -> Result<Simulated, SimulateError> {
    let started = run_record::now_unix_s();
    let scenario = cfg.resolve().map_err(SimulateError::Rejected)?;
    let model = scenario.model();
    let mut opts = cfg.sim_options()?;
    opts.trajectory = true;
    opts.trajectory_periods = match trajectory_periods {
        Some(n) if !(1..=MAX_TRAJECTORY_PERIODS).contains(&n) => {
            return Err(SimulateError::TrajectoryPeriods(n))
        }
        Some(n) => n,
        None => u64::MAX,
    };
    cfg.check_work(model, &opts, 1, true)?;
    // a folder another run holds, or one with foreign files, is refused at once
    let _lock = out
        .map(|dir| run_record::prepare_folder(dir, "simulate", None, false))
        .transpose()?;
    let y0 = [cfg.simulation.x0, cfg.simulation.v0];
    let t = std::time::Instant::now();
    let (res, summary, used) = simulate_decided(model, y0, &opts, Decide::default())
        .map_err(SimulateError::Integration)?;
    let run = Simulated {
        elapsed_s: t.elapsed().as_secs_f64(),
        source,
        cfg,
        scenario,
        res,
        summary,
        used,
        requested: opts,
    };
    if let Some(dir) = out {
        write(dir, &run.finished(), started)?;
    }
    Ok(run)
}
