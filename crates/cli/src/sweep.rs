//! Shared machinery of the sweep commands: simulation arguments, ranges, checkpointed parallel
//! execution with a progress bar.

use anyhow::{bail, Context, Result};
use clap::Args;
use geardyn_analysis::bifurcation::{SweepOptions, TaskResult};
use geardyn_io::config::{Face, SimOverrides};
use geardyn_io::executor::{execute, Progress, Store, SweepJob};
use geardyn_io::Config;
use geardyn_scenario::Scenario;
use std::path::Path;

/// Integration settings on the command line (override the config's `[simulation]`).
#[derive(Args, Debug, Clone)]
pub struct SimArgs {
    /// Recorded excitation periods per run.
    #[arg(long)]
    pub periods: Option<u64>,
    /// Transient excitation periods discarded per run.
    #[arg(long)]
    pub transient: Option<u64>,
    /// Integrator: dopri (adaptive, error-controlled, the default of every command) or rk4
    /// (fixed step, --steps-per-cycle per mesh cycle; sweeps, basins, maps and continuations
    /// advance it in 16 lockstep lanes: the classified C1 sweep of `geardyn bench
    /// --bifurcation` runs about twice as fast as with dopri).
    #[arg(long, value_parser = ["dopri", "rk4"])]
    pub integrator: Option<String>,
    /// RK4 steps per mesh cycle.
    #[arg(long)]
    pub steps_per_cycle: Option<u32>,
    /// Decision horizon: excitation periods (from the start of a run) a motion with a positive
    /// Lyapunov exponent is followed before it is called chaotic [default: 10000].
    #[arg(long)]
    pub decision_periods: Option<u64>,
    /// Work budget of one run's decision in right-hand-side evaluations (4 per RK4 step, 6 per
    /// DP5 step); a run not periodic when it is spent is `unsettled` [default: 1000000000].
    #[arg(long)]
    pub decision_budget: Option<u64>,
    /// Cap on the command's estimated work in right-hand-side evaluations (all runs, the
    /// decisions' worst case included); a command above it is refused [default: 1e12].
    #[arg(long)]
    pub max_work: Option<f64>,
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
            periods: self.periods.map(|p| p as f64),
            transient: self.transient.map(|t| t as f64),
            integrator: self.integrator.clone(),
            steps_per_cycle: self.steps_per_cycle.map(f64::from),
            decision_periods: self.decision_periods.map(|n| n as f64),
            decision_budget: self.decision_budget.map(|n| n as f64),
            max_work: self.max_work,
        };
        Ok(o.apply(cfg, sets, Face::Cli)?)
    }
}

/// Parses `START:STOP:COUNT` of `--range`.
pub fn parse_range(s: &str) -> Result<(f64, f64, usize)> {
    parse_range_of(s, "--range", "START:STOP:COUNT, e.g. 0.5:2:200", 1_000_000)
}

/// Parses `START:STOP:COUNT` given to option `flag` (named in errors, with the expected `form`),
/// at most `max_count` values; the spacing `(STOP - START) / COUNT` must be finite too.
pub fn parse_range_of(
    s: &str,
    flag: &str,
    form: &str,
    max_count: usize,
) -> Result<(f64, f64, usize)> {
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
    if !(a.is_finite() && b.is_finite() && (b - a).is_finite()) || n == 0 || n > max_count {
        bail!("bad {flag} '{s}': finite start and stop (finite difference too) and 1 <= count <= {max_count}");
    }
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

/// Runs a sweep, checked by the library ([`geardyn_io::request::SweepSpec::options`]), with a
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
        Some(Store::folder(out, cfg, force)?),
        &progress(out),
    )?)
}

/// The progress bar of a command writing into `out`.
pub fn progress(out: &Path) -> Progress {
    Progress::new(None).announcing_resume(out)
}
