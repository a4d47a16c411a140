//! The resolved requests of the grid-shaped commands (`geardyn map2d`, `geardyn bifurcation`)
//! and the folder each writes from its results: one home shared by the single command and by
//! `geardyn merge` of a sharded plan ([`crate::shard`]), so that both write the same files with
//! the same bytes.
//!
//! A request is everything a command's results depend on, resolved: the configuration with every
//! override applied, the analysis options (axes or values, simulation and decision settings),
//! and what the titles name. It serialises to JSON exactly (every float round-trips), which is
//! how a plan carries it to the machines that compute its shards.

use geardyn_analysis::attractor::{check_phase, IdentifyError, IdentifyRequest, PhaseError};
use geardyn_analysis::bifurcation::InitialBox;
use geardyn_analysis::bifurcation::{
    ModeError, Section, SectionError, SweepMode, SweepOptions, TaskResult,
};
use geardyn_analysis::continuation::ContinuationOptions;
use geardyn_analysis::map2d::{MapCell, MapOptions};
use geardyn_io::figure::LabelColors;
use geardyn_io::output::OutputError;
use geardyn_io::ConfigError;
use geardyn_io::{npy, run_record, schema, sweep_output, Config};
use geardyn_scenario::{Scenario, ScenarioError};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Why a folder could not be written.
#[derive(Debug, thiserror::Error)]
pub enum FolderWriteError {
    /// A data file.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// A figure.
    #[error(transparent)]
    Figure(#[from] geardyn_io::figure::FigureError),
}

/// A two-parameter map (`geardyn map2d`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MapRequest {
    /// The configuration, every override applied.
    pub config: Config,
    /// What the model comes from, for titles (`preset classic`, `config my.toml`).
    pub source: String,
    /// Metric of the heatmap and of `map.npy` ([`geardyn_analysis::map2d::METRICS`]).
    pub metric: String,
    /// Axes and simulation settings.
    pub options: MapOptions,
}

/// A bifurcation diagram (`geardyn bifurcation`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BifurcationRequest {
    /// The configuration, every override applied.
    pub config: Config,
    /// What the model comes from, for titles.
    pub source: String,
    /// The mode's name as given (`fixed`, `sweep`, `multi`), for the title.
    pub mode: String,
    /// Values, mode, sections and simulation settings.
    pub options: SweepOptions,
}

/// A sweep request that cannot run: each message names the field (the CLI's flag, or the name
/// shared by the CLI and Python) and what is allowed.
#[derive(Debug, thiserror::Error)]
pub enum SweepRequestError {
    /// The simulation settings or the work cap of the configuration.
    #[error(transparent)]
    Config(#[from] ConfigError),
    /// The mode or its initial states (`mode`, `ics`, `x0_range`, `v0_range`).
    #[error(transparent)]
    Mode(#[from] ModeError),
    /// A section name.
    #[error(transparent)]
    Section(#[from] SectionError),
    /// The phase of the initial states.
    #[error(transparent)]
    Phase(#[from] PhaseError),
    /// The identification tolerances.
    #[error(transparent)]
    Identify(#[from] IdentifyError),
    /// The axes of a map.
    #[error(transparent)]
    Map(#[from] geardyn_analysis::map2d::MapError),
    /// A metric of a map not in [`geardyn_analysis::map2d::METRICS`].
    #[error("unknown metric '{0}': allowed {all}", all = geardyn_analysis::map2d::METRICS.join(", "))]
    Metric(String),
    /// The swept parameter refused at one end of the values.
    #[error("--param {param} = {value}")]
    Param {
        /// The parameter.
        param: String,
        /// The value, printed as [`geardyn_model::error::num`] prints it.
        value: String,
        /// Why the scenario refused it.
        #[source]
        source: ScenarioError,
    },
}

/// A one-parameter sweep as the faces state it (the flags of `geardyn bifurcation` and `geardyn
/// response`, the keyword arguments of `geardyn.bifurcation` and `geardyn.response`), before it
/// is checked: [`SweepSpec::options`] is the one place its mode, initial states, sections and
/// simulation settings are checked and defaulted, and [`check_sweep`] the one place the values
/// and the work are.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepSpec {
    /// Parameter swept (any of [`geardyn_model::PARAMETER_NAMES`]).
    pub param: String,
    /// Its values, in order (dimensionless, as the parameter).
    pub values: Vec<f64>,
    /// Mode name: `fixed`, `sweep` or `multi` ([`SweepMode::from_name`]).
    pub mode: String,
    /// Initial states per value (`multi` only), `1 ..= MAX_ICS`.
    pub ics: usize,
    /// Seed of the initial states (`multi` only).
    pub seed: u64,
    /// `x0` interval of the initial states (`multi` only); `None`: the attractor region.
    pub x0_range: Option<(f64, f64)>,
    /// `v0` interval of the initial states (`multi` only); `None`: the attractor region.
    pub v0_range: Option<(f64, f64)>,
    /// Section names ([`Section::parse_list`]).
    pub sections: Vec<String>,
    /// Also compute the top Lyapunov exponent per run.
    pub lyapunov: bool,
}

impl Default for SweepSpec {
    /// The defaults of `geardyn bifurcation` (`geardyn.bifurcation` has the same but for the
    /// values, which it asks for): 200 values of `omega` over `[0.5, 2]`, every value from the
    /// configuration's initial state, the stroboscopic section (8 initial states of seed 1 in
    /// the attractor region when the mode is changed to `multi`).
    fn default() -> Self {
        SweepSpec {
            param: "omega".into(),
            values: geardyn_analysis::bifurcation::linspace(0.5, 2.0, 200),
            mode: "fixed".into(),
            ics: 8,
            seed: 1,
            x0_range: None,
            v0_range: None,
            sections: vec!["strobe".into()],
            lyapunov: false,
        }
    }
}

impl SweepSpec {
    /// The sweep of `geardyn response` over `values` of `param`: continuation up and down, no
    /// sections, no exponent.
    pub fn response(param: String, values: Vec<f64>) -> SweepSpec {
        SweepSpec {
            param,
            values,
            mode: "sweep".into(),
            sections: vec![],
            ..SweepSpec::default()
        }
    }

    /// The checked options of the sweep on configuration `cfg` (its simulation settings and its
    /// initial state `[x0, v0]` for the fixed mode and the continuation chains) and its resolved
    /// `scenario` (the default region of the initial states is that of its largest half
    /// backlash); the values and the work are checked too ([`check_sweep`]). Checks in the
    /// order sections, mode, simulation settings, values, work.
    pub fn options(
        &self,
        cfg: &Config,
        scenario: &Scenario,
    ) -> Result<SweepOptions, SweepRequestError> {
        let sections = Section::parse_list(self.sections.iter().map(String::as_str))?;
        let mode = SweepMode::from_name(
            &self.mode,
            self.ics,
            self.seed,
            self.x0_range,
            self.v0_range,
            scenario.model().backlash_levels().1,
        )?;
        let opts = SweepOptions {
            param: self.param.clone(),
            values: self.values.clone(),
            mode,
            sim: cfg.sim_options()?,
            y0: [cfg.simulation.x0, cfg.simulation.v0],
            sections,
            lyapunov: self.lyapunov,
        };
        check_sweep(cfg, scenario, &opts)?;
        Ok(opts)
    }
}

/// An attractor continuation as the faces state it (`geardyn continuation`,
/// `geardyn.continuation`): several initial states per value, every attractor found followed
/// over the values. [`ContinuationRequest::options`] is the one place it is checked.
#[derive(Clone, Debug, PartialEq)]
pub struct ContinuationRequest {
    /// Parameter continued (any of [`geardyn_model::PARAMETER_NAMES`]).
    pub param: String,
    /// Its values, in order.
    pub values: Vec<f64>,
    /// Initial states per value, `1 ..= MAX_ICS`.
    pub ics: usize,
    /// Seed of the initial states.
    pub seed: u64,
    /// `x0` interval of the initial states; `None`: the attractor region.
    pub x0_range: Option<(f64, f64)>,
    /// `v0` interval of the initial states; `None`: the attractor region.
    pub v0_range: Option<(f64, f64)>,
    /// Phase of the initial states as a fraction of the excitation period, in `[0, 1)`.
    pub phase: f64,
    /// Identification tolerances.
    pub identify: IdentifyRequest,
}

impl ContinuationRequest {
    /// Initial states per value by default (the CLI's `--ics`, Python's `ics=`).
    pub const DEFAULT_ICS: usize = 32;

    /// The checked options on configuration `cfg` (its simulation settings) and its resolved
    /// `scenario` (the default region of the initial states is that of its largest half
    /// backlash). Checks the initial states, the phase, the identification, then the work.
    pub fn options(
        &self,
        cfg: &Config,
        scenario: &Scenario,
    ) -> Result<ContinuationOptions, SweepRequestError> {
        let b = InitialBox::new(
            self.ics,
            self.seed,
            self.x0_range,
            self.v0_range,
            scenario.model().backlash_levels().1,
        )?;
        let opts = ContinuationOptions {
            param: self.param.clone(),
            values: self.values.clone(),
            ics: b.ics,
            seed: b.seed,
            x0_range: b.x0_range,
            v0_range: b.v0_range,
            phase: check_phase(self.phase)?,
            identify: self.identify.options(cfg.sim_options()?)?,
        };
        cfg.check_work(
            scenario.model(),
            &opts.identify.sim,
            opts.values.len() * opts.ics,
            false,
        )?;
        Ok(opts)
    }
}

/// Checks a sweep before anything runs or is written: the swept parameter valid at both ends of
/// its values, the estimated work (every run's decision at its worst) below the configuration's
/// cap `max_work`.
pub fn check_sweep(
    cfg: &Config,
    scenario: &Scenario,
    opts: &SweepOptions,
) -> Result<(), SweepRequestError> {
    for v in [opts.values.first(), opts.values.last()]
        .into_iter()
        .flatten()
    {
        scenario
            .with(&opts.param, *v)
            .map_err(|source| SweepRequestError::Param {
                param: opts.param.clone(),
                value: geardyn_model::error::num(*v),
                source,
            })?;
    }
    let ics = match opts.mode {
        SweepMode::Multi { ics, .. } => ics.max(1),
        _ => 1,
    };
    cfg.check_work(scenario.model(), &opts.sim, opts.values.len() * ics, true)?;
    Ok(())
}

impl MapRequest {
    /// The metric of a map by default.
    pub const DEFAULT_METRIC: &'static str = "max_force";

    /// The request of a map of `metric` over the axes `x` and `y` (a parameter and its values
    /// each) on configuration `config` (every override applied) and its resolved `scenario`:
    /// checks the metric, the axes, then the work; `source` names the model in titles.
    pub fn new(
        config: Config,
        source: String,
        scenario: &Scenario,
        metric: String,
        x: (String, Vec<f64>),
        y: (String, Vec<f64>),
    ) -> Result<MapRequest, SweepRequestError> {
        if !geardyn_analysis::map2d::METRICS.contains(&metric.as_str()) {
            return Err(SweepRequestError::Metric(metric));
        }
        let options = MapOptions {
            x_param: x.0,
            x_values: x.1,
            y_param: y.0,
            y_values: y.1,
            sim: config.sim_options()?,
            y0: [config.simulation.x0, config.simulation.v0],
            lyapunov: metric == "tle",
        };
        options.check_axes()?;
        config.check_work(
            scenario.model(),
            &options.sim,
            options.x_values.len() * options.y_values.len(),
            true,
        )?;
        Ok(MapRequest {
            config,
            source,
            metric,
            options,
        })
    }
}

impl BifurcationRequest {
    /// The request of the sweep `spec` on configuration `config` (every override applied) and
    /// its resolved `scenario`, checked ([`SweepSpec::options`]); `source` names the model in
    /// titles.
    pub fn new(
        config: Config,
        source: String,
        scenario: &Scenario,
        spec: &SweepSpec,
    ) -> Result<BifurcationRequest, SweepRequestError> {
        let options = spec.options(&config, scenario)?;
        Ok(BifurcationRequest {
            config,
            source,
            mode: spec.mode.clone(),
            options,
        })
    }
}

/// The request of one grid-shaped command.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "command", rename_all = "snake_case")]
pub enum Request {
    /// `geardyn map2d`.
    Map2d(MapRequest),
    /// `geardyn bifurcation`.
    Bifurcation(BifurcationRequest),
}

impl Request {
    /// The command's name (`map2d`, `bifurcation`): the `kind` of its folder.
    pub fn command(&self) -> &'static str {
        match self {
            Request::Map2d(_) => "map2d",
            Request::Bifurcation(_) => "bifurcation",
        }
    }

    /// The configuration.
    pub fn config(&self) -> &Config {
        match self {
            Request::Map2d(r) => &r.config,
            Request::Bifurcation(r) => &r.config,
        }
    }
}

impl MapRequest {
    /// Writes the folder of `geardyn map2d` into `out`: `config.toml`, `run.json`, `map.csv`
    /// ([`schema::map_table`]), `map.npy` (the metric, `ny x nx`) and the heatmap `map.png`/`.svg`.
    /// Returns the finite range of the metric.
    pub fn write_folder(
        &self,
        out: &Path,
        scenario: &Scenario,
        cells: &[MapCell],
        started_unix_s: f64,
    ) -> Result<(f64, f64), FolderWriteError> {
        let o = &self.options;
        let (xp, yp) = (o.x_param.as_str(), o.y_param.as_str());
        let (xv, yv) = (&o.x_values, &o.y_values);
        run_record::write_config_and_record(
            out,
            "map2d",
            &self.config,
            scenario,
            &[run_record::Swept::of(xp, xv), run_record::Swept::of(yp, yv)],
            started_unix_s,
        )?;
        schema::map_table(xp, yp, cells).write_csv(&out.join("map.csv"), schema::full)?;
        let vals: Vec<f64> = cells
            .iter()
            .map(|c| c.metric(&self.metric).unwrap_or(f64::NAN))
            .collect();
        npy::write_f64(&out.join("map.npy"), &[yv.len(), xv.len()], &vals)?;
        let title = format!(
            "{} over ({}, {}): {}",
            self.metric,
            xp,
            yp,
            sweep_output::operating_point(&self.source, scenario.params(), &[xp, yp])
        );
        let (lo, hi) = sweep_output::plot_metric_map(
            &out.join("map"),
            &title,
            (xp, xv),
            (yp, yv),
            &vals,
            sweep_output::MetricScale::of(&self.metric),
        )?;
        Ok((lo, hi))
    }
}

impl BifurcationRequest {
    /// Writes the folder of `geardyn bifurcation` into `out`: `config.toml`, `run.json`,
    /// `bifurcation.csv`, `runs.csv`, `impact_force.csv` and the diagram `bifurcation.png`/`.svg`.
    pub fn write_folder(
        &self,
        out: &Path,
        scenario: &Scenario,
        results: &[TaskResult],
        started_unix_s: f64,
    ) -> Result<(), FolderWriteError> {
        let o = &self.options;
        let param = o.param.as_str();
        run_record::write_config_and_record(
            out,
            "bifurcation",
            &self.config,
            scenario,
            &[run_record::Swept::of(param, &o.values)],
            started_unix_s,
        )?;
        schema::points_table(param, results)
            .write_csv(&out.join("bifurcation.csv"), schema::full)?;
        schema::runs_table(param, results).write_csv(&out.join("runs.csv"), schema::full)?;
        schema::impact_force_table(param, results)
            .write_csv(&out.join("impact_force.csv"), schema::full)?;
        let title = format!(
            "Bifurcation diagram over {} ({} mode): {}",
            param,
            self.mode,
            sweep_output::operating_point(&self.source, scenario.params(), &[param])
        );
        sweep_output::plot_bifurcation(
            &out.join("bifurcation"),
            param,
            results,
            &o.sections,
            &title,
            &mut LabelColors::default(),
        )?;
        Ok(())
    }
}

/// The defaults every face shows for the options it does not require, by function (`simulate`,
/// `lyapunov`, `bifurcation`, `continuation`, `identify`, `orbits`, `signals`, `map2d`), taken
/// from the requests themselves: Python's keyword defaults are read from here, the CLI's flags
/// name the same constants.
pub fn face_defaults() -> serde_json::Value {
    use geardyn_analysis::attractor::IdentifyRequest;
    use geardyn_analysis::lyapunov_request::LyapunovRequest;
    use geardyn_analysis::orbits_request::OrbitsRequest;
    use geardyn_analysis::signals::SignalsRequest;
    let sweep = SweepSpec::default();
    let lyap = LyapunovRequest::default();
    let orbits = OrbitsRequest::default();
    let signals = SignalsRequest::default();
    let ident = IdentifyRequest::DEFAULT;
    serde_json::json!({
        "simulate": { "trajectory_periods": geardyn_io::simulate_folder::DEFAULT_TRAJECTORY_PERIODS },
        "lyapunov": { "method": lyap.method.name(), "max_periods": lyap.max_periods, "d0": lyap.d0 },
        "bifurcation": { "param": sweep.param, "mode": sweep.mode, "ics": sweep.ics, "seed": sweep.seed },
        "continuation": { "ics": ContinuationRequest::DEFAULT_ICS, "seed": sweep.seed },
        "identify": { "capture_tol": ident.capture_tol, "ident_rtol": ident.ident_rtol, "early_stop": ident.early_capture },
        "orbits": {
            "transient": orbits.transient, "ds": orbits.ds, "max_points": orbits.max_points,
            "switch_up_to": orbits.switch_up_to, "rtol": orbits.rtol,
        },
        "signals": {
            "revolutions": signals.revolutions, "transient": signals.transient,
            "samples_per_cycle": signals.samples_per_cycle,
            "segment_revolutions": signals.segment_revolutions, "sidebands": signals.sidebands,
            "shaft_orders": signals.shaft_orders, "residual": signals.residual.name(),
            "na4_reference": signals.na4_reference.name(),
        },
        "map2d": { "metric": MapRequest::DEFAULT_METRIC },
    })
}
