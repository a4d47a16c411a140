//! Shared machinery of the sweep commands: simulation and run arguments, initial states, ranges,
//! checkpointed parallel execution with a progress bar.

use crate::run_config::ConfigArgs;
use anyhow::{bail, Context, Result};
use clap::Args;
use geardyn_analysis::bifurcation::{range_values, SweepOptions, TaskResult, MAX_RANGE_VALUES};
use geardyn_exec::request::SweepSpec;
use geardyn_exec::{execute, Checkpointed, Progress, SweepJob};
use geardyn_io::config::{Face, SimOverrides};
use geardyn_io::Config;
use geardyn_scenario::Scenario;
use std::path::Path;

/// Integration settings on the command line (override the config's `[simulation]`). The values
/// are read as numbers and checked by the library ([`SimOverrides::apply`]), so a bad value gets
/// the message Python gives for the same keyword.
#[derive(Args, Debug, Clone)]
pub struct SimArgs {
    /// Recorded excitation periods per run (default: the config's simulation.record_periods).
    #[arg(long, allow_hyphen_values = true)]
    pub periods: Option<f64>,
    /// Transient excitation periods discarded per run (default: simulation.transient_periods).
    #[arg(long, allow_hyphen_values = true)]
    pub transient: Option<f64>,
    /// Integrator: dopri (adaptive, error-controlled, the default of every command) or rk4
    /// (fixed step, --steps-per-cycle per mesh cycle; sweeps, basins, maps and continuations
    /// advance it in 16 lockstep lanes: the classified C1 sweep of `geardyn bench
    /// --bifurcation` runs about twice as fast as with dopri).
    #[arg(long)]
    pub integrator: Option<String>,
    /// RK4 steps per mesh cycle (default: simulation.steps_per_cycle).
    #[arg(long, allow_hyphen_values = true)]
    pub steps_per_cycle: Option<f64>,
    #[command(flatten)]
    pub decision: DecisionArgs,
    /// Cap on the command's estimated work in right-hand-side evaluations (all runs, the
    /// decisions' worst case included); a command above it is refused [default: 1e12].
    #[arg(long, allow_hyphen_values = true)]
    pub max_work: Option<f64>,
}

/// The settings of a chaos verdict's decision (docs/analyses.md, rule 2): on every command that
/// classifies motions, the report included.
#[derive(Args, Debug, Clone)]
pub struct DecisionArgs {
    /// Decision horizon: excitation periods (from the start of a run) a motion with a positive
    /// Lyapunov exponent is followed before it is called chaotic [default: 10000].
    #[arg(long, allow_hyphen_values = true)]
    pub decision_periods: Option<f64>,
    /// Work budget of one run's decision in right-hand-side evaluations (4 per RK4 step, 6 per
    /// DP5 step); a run not periodic when it is spent is `unsettled` [default: 3000000000].
    #[arg(long, allow_hyphen_values = true)]
    pub decision_budget: Option<f64>,
    /// Resolution of a decision's follow (the long transients of a positive exponent's
    /// persistence checks, which record nothing): fixed-step RK4 steps per natural period, in
    /// the lockstep lanes, on models whose contact law the lanes step; 0 follows with the
    /// requested integrator (0 or 16 ... 1000000) [default: 64].
    #[arg(long, allow_hyphen_values = true)]
    pub follow_steps: Option<f64>,
    /// Copies of a chaotic state followed by the ensemble escape test, which tells a chaotic
    /// attractor (no copy leaves) from transient chaos (copies leak to a periodic orbit); 0 turns
    /// it off and follows the run itself to the decision horizon (0 or 2 ... 4096) [default: 16].
    #[arg(long, allow_hyphen_values = true)]
    pub escape_copies: Option<f64>,
    /// Span of the escape test in excitation periods; 0: the copies' spread, then two decision
    /// horizons of copy-periods (0 or 100 ... 1000000) [default: 0, i.e. 1250 periods and the
    /// spread for 16 copies at the default horizon].
    #[arg(long, allow_hyphen_values = true)]
    pub escape_periods: Option<f64>,
}

impl DecisionArgs {
    /// The overrides of these flags alone (the rest `None`).
    pub fn overrides(&self) -> SimOverrides {
        SimOverrides {
            decision_periods: self.decision_periods,
            decision_budget: self.decision_budget,
            follow_steps: self.follow_steps,
            escape_copies: self.escape_copies,
            escape_periods: self.escape_periods,
            ..Default::default()
        }
    }
}

/// The arguments of the commands that resume from a checkpoint in their output folder: the
/// configuration, the integration settings over it, and `--force`.
#[derive(Args, Debug, Clone)]
pub struct RunArgs {
    #[command(flatten)]
    pub cfg: ConfigArgs,
    #[command(flatten)]
    pub sim: SimArgs,
    #[command(flatten)]
    pub force: ForceArg,
}

impl RunArgs {
    /// The configuration, every override applied, and the scenario it resolves to.
    pub fn resolve(&self) -> Result<(Config, Scenario)> {
        self.sim.resolve(&self.cfg)
    }
}

/// The initial states of a multi-initial sweep or a continuation beside their count: the seed
/// and the boxes they are drawn from.
#[derive(Args, Debug, Clone)]
pub struct InitialStatesArgs {
    /// Seed of the initial states.
    #[arg(long, default_value_t = SweepSpec::default().seed)]
    pub seed: u64,
    /// x0 range of the initial states, MIN:MAX; default +-(D + 3 max(D, 1)), D the largest half
    /// backlash (a region that holds the coexisting attractors, not just the gap).
    #[arg(long, allow_hyphen_values = true)]
    pub x0_range: Option<String>,
    /// v0 range of the initial states, MIN:MAX; default +-3 max(D, 1).
    #[arg(long, allow_hyphen_values = true)]
    pub v0_range: Option<String>,
}

/// A `MIN:MAX` range, when given.
type OptionalRange = Option<(f64, f64)>;

impl InitialStatesArgs {
    /// The x0 and v0 ranges given (`None`: the default).
    pub fn ranges(&self) -> Result<(OptionalRange, OptionalRange)> {
        let pair = |s: &Option<String>, flag| s.as_deref().map(|s| parse_pair(s, flag)).transpose();
        Ok((
            pair(&self.x0_range, "--x0-range")?,
            pair(&self.v0_range, "--v0-range")?,
        ))
    }
}

/// `--force` of the commands that resume from a checkpoint in their output folder.
#[derive(Args, Debug, Clone)]
pub struct ForceArg {
    /// Discard a checkpoint in the output folder that was made with other settings, and start
    /// over (without it such a folder is refused).
    #[arg(long)]
    pub force: bool,
}

impl SimArgs {
    /// Applies the overrides to the config; `sets` are the command's `--set` assignments (a field
    /// given by both is refused: which one wins would be a silent choice). The list of fields
    /// is the library's ([`SimOverrides`]), shared with Python.
    pub fn apply(&self, cfg: &mut Config, sets: &[String]) -> Result<()> {
        let o = SimOverrides {
            periods: self.periods,
            transient: self.transient,
            integrator: self.integrator.clone(),
            steps_per_cycle: self.steps_per_cycle,
            max_work: self.max_work,
            ..self.decision.overrides()
        };
        Ok(o.apply(cfg, sets, Face::Cli)?)
    }

    /// The configuration of `cfg` with these overrides applied, and the scenario it resolves to.
    pub fn resolve(&self, cfg: &ConfigArgs) -> Result<(Config, Scenario)> {
        let mut c = cfg.config()?;
        self.apply(&mut c, &cfg.sets)?;
        let scenario = c.resolve()?;
        Ok((c, scenario))
    }
}

/// The values of `--range START:STOP:COUNT`, checked by the library ([`range_values`], as
/// Python's `range=`).
pub fn parse_range(s: &str) -> Result<Vec<f64>> {
    let r = parse_numbers(s, "--range", "START:STOP:COUNT, e.g. 0.5:2:200")?;
    Ok(range_values("range", r, MAX_RANGE_VALUES)?)
}

/// The three numbers of `START:STOP:COUNT` given to option `flag` (named in errors, with the
/// expected `form`); only their syntax is checked here, their range by the library.
pub fn parse_numbers(s: &str, flag: &str, form: &str) -> Result<(f64, f64, usize)> {
    let parts: Vec<&str> = s.split(':').collect();
    if parts.len() != 3 {
        bail!("bad {flag} '{s}': expected {form}");
    }
    let a: f64 = parts[0]
        .trim()
        .parse()
        .with_context(|| format!("bad {flag} '{s}': start '{}' is not a number", parts[0]))?;
    let b: f64 = parts[1]
        .trim()
        .parse()
        .with_context(|| format!("bad {flag} '{s}': stop '{}' is not a number", parts[1]))?;
    let n: usize = parts[2].trim().parse().with_context(|| {
        format!(
            "bad {flag} '{s}': count '{}' is not a positive integer",
            parts[2]
        )
    })?;
    Ok((a, b, n))
}

/// Parses `MIN:MAX`.
pub fn parse_pair(s: &str, what: &str) -> Result<(f64, f64)> {
    let (a, b) = s
        .split_once(':')
        .with_context(|| format!("bad {what} '{s}': expected MIN:MAX"))?;
    let a: f64 = a
        .trim()
        .parse()
        .with_context(|| format!("bad {what} '{s}'"))?;
    let b: f64 = b
        .trim()
        .parse()
        .with_context(|| format!("bad {what} '{s}'"))?;
    if !(a.is_finite() && b.is_finite() && a <= b) {
        bail!("bad {what} '{s}': finite MIN <= MAX");
    }
    Ok((a, b))
}

/// Runs a sweep, checked by the library ([`geardyn_exec::request::SweepSpec::options`]), with a
/// checkpoint in `out` and a progress bar on stderr.
pub fn run_checkpointed(
    cfg: &Config,
    scenario: &Scenario,
    opts: &SweepOptions,
    out: &Path,
    kind: &str,
    force: bool,
) -> Result<Vec<TaskResult>> {
    Ok(execute(
        &SweepJob::new(kind, scenario, opts),
        Some(&mut Checkpointed::folder(out, cfg, force)?),
        &progress(out),
    )?)
}

/// The progress bar of a command writing into `out`.
pub fn progress(out: &Path) -> Progress {
    Progress::new(None).announcing_resume(out)
}
