//! Bifurcation diagrams and frequency-response sweeps of the gear model over any parameter
//! (docs/model.md §5): fixed initial state, continuation (forward and backward), or multi-initial with
//! `K` seeded initial states per value, each run tagged with its attractor's label.
//!
//! Work is split into [`Task`]s (one parameter value on one branch). Fixed and multi-initial tasks
//! run in parallel (rayon); the two continuation chains run side by side, each sequentially. Every
//! result is keyed by its task, never by completion order, so the output is identical for any
//! thread count. Finished tasks are handed to a callback (the caller checkpoints them) and tasks
//! listed as done are skipped, which makes long sweeps resumable.

use crate::classify::{simulate_decided, Decide, Motion, TLE_PERIODS};
use crate::lanes_decide::Decided;
use crate::simulate::{Amplitudes, Level, SimError, SimOptions, SimResult, Summary};
use crate::sweep_runs::{continuation_branches, TaskRuns};
use geardyn_model::MeshModel;
use geardyn_scenario::{ResolvedRecord, Scenario, ScenarioError};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;

/// An unknown section name ([`Section::parse_list`]).
#[derive(Debug, thiserror::Error, PartialEq)]
#[error("unknown section '{0}': allowed {list}", list = Section::ALL.map(Section::name).join(", "))]
pub struct SectionError(pub String);

/// A Poincaré section of the bifurcation diagram.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Section {
    /// Stroboscopic: once per excitation period.
    Strobe,
    /// `x = D_s` upward.
    DsUp,
    /// `x = -D_s` downward.
    DsDown,
    /// `x = D_d` upward.
    DdUp,
    /// `x = -D_d` downward.
    DdDown,
    /// Back-side impacts (state before the impact).
    Impact,
}

impl Section {
    /// All sections.
    pub const ALL: [Section; 6] = [
        Section::Strobe,
        Section::DsUp,
        Section::DsDown,
        Section::DdUp,
        Section::DdDown,
        Section::Impact,
    ];
    /// Name used on the command line and in CSV.
    pub fn name(self) -> &'static str {
        match self {
            Section::Strobe => "strobe",
            Section::DsUp => "ds_up",
            Section::DsDown => "ds_down",
            Section::DdUp => "dd_up",
            Section::DdDown => "dd_down",
            Section::Impact => "impact",
        }
    }
    /// Parses a name.
    pub fn parse(s: &str) -> Option<Section> {
        Section::ALL.into_iter().find(|x| x.name() == s)
    }
    /// Parses a list of names (`--sections strobe,ds_up` split at the commas; Python's
    /// `sections`), each trimmed of spaces; an unknown name is refused with the allowed ones.
    ///
    /// ```
    /// use geardyn_analysis::bifurcation::Section;
    /// assert_eq!(Section::parse_list(["strobe", " impact"]).unwrap(), [Section::Strobe, Section::Impact]);
    /// assert!(Section::parse_list(["nope"]).unwrap_err().to_string().starts_with("unknown section 'nope'"));
    /// ```
    pub fn parse_list<'a>(
        names: impl IntoIterator<Item = &'a str>,
    ) -> Result<Vec<Section>, SectionError> {
        names
            .into_iter()
            .map(|t| Section::parse(t.trim()).ok_or_else(|| SectionError(t.to_string())))
            .collect()
    }
    fn of_level(l: Level) -> Section {
        match l {
            Level::DsUp => Section::DsUp,
            Level::DsDown => Section::DsDown,
            Level::DdUp => Section::DdUp,
            Level::DdDown => Section::DdDown,
        }
    }
}

/// How initial states are chosen.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "mode", rename_all = "snake_case")]
pub enum SweepMode {
    /// Every value from the same initial state.
    Fixed,
    /// Continuation: each value starts from the final state of the previous one, in both
    /// directions (branches `up` and `down`).
    Sweep,
    /// `ics` initial states per value, uniformly random in the box `x0_range x v0_range` from a
    /// generator seeded by `(seed, value index, ic index)`.
    Multi {
        /// Initial states per value.
        ics: usize,
        /// Seed.
        seed: u64,
        /// Range of `x0`.
        x0_range: (f64, f64),
        /// Range of `v0`.
        v0_range: (f64, f64),
    },
}

/// Largest number of initial states per value of a multi-initial sweep or a continuation.
pub const MAX_ICS: usize = 100_000;

/// A sweep mode or initial-state setting out of range ([`SweepMode::from_name`], [`check_ics`]).
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ModeError {
    /// An unknown mode name.
    #[error("bad mode '{0}': allowed fixed, sweep, multi")]
    Name(String),
    /// Initial states per value out of range.
    #[error("bad ics {0}: allowed 1 ..= {MAX_ICS} (initial states per value)")]
    Ics(usize),
    /// A box of initial states that is not a finite interval.
    #[error("bad {name} ({}, {}): finite MIN <= MAX", geardyn_model::error::num(.range.0), geardyn_model::error::num(.range.1))]
    Range {
        /// `x0_range` or `v0_range`.
        name: &'static str,
        /// The interval given.
        range: (f64, f64),
    },
}

/// Checks a number of initial states per value (`1 ..= MAX_ICS`).
pub fn check_ics(ics: usize) -> Result<usize, ModeError> {
    if (1..=MAX_ICS).contains(&ics) {
        Ok(ics)
    } else {
        Err(ModeError::Ics(ics))
    }
}

fn check_range(name: &'static str, r: (f64, f64)) -> Result<(f64, f64), ModeError> {
    if r.0.is_finite() && r.1.is_finite() && r.0 <= r.1 {
        Ok(r)
    } else {
        Err(ModeError::Range { name, range: r })
    }
}

/// The random initial states of every parameter value, checked and defaulted: those of a
/// multi-initial sweep ([`SweepMode::Multi`]) and of an attractor continuation
/// (`crate::continuation::ContinuationOptions`). Dimensionless: `x0` in backlash units `b_c`,
/// `v0` in `b_c omega_n`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InitialBox {
    /// Initial states per value, `1 ..= MAX_ICS`.
    pub ics: usize,
    /// Seed of the generator (with the value index and the state index).
    pub seed: u64,
    /// `x0` interval, finite, `MIN <= MAX`.
    pub x0_range: (f64, f64),
    /// `v0` interval, finite, `MIN <= MAX`.
    pub v0_range: (f64, f64),
}

impl InitialBox {
    /// The box of `ics` initial states per value ([`check_ics`]) drawn with `seed` from
    /// `x0_range` x `v0_range`, each by default that of the [`attractor_region`] of the largest
    /// half backlash `d_max` — the one place the CLI (`--ics`, `--x0-range`, `--v0-range`) and
    /// Python (`ics`, `x0_range`, `v0_range`) check and default them. The error names the field
    /// and its allowed range.
    ///
    /// ```
    /// use geardyn_analysis::bifurcation::{attractor_region, InitialBox};
    /// let b = InitialBox::new(8, 1, None, Some((-1.0, 1.0)), 0.5).unwrap();
    /// assert_eq!((b.x0_range, b.v0_range), (attractor_region(0.5).0, (-1.0, 1.0)));
    /// assert!(InitialBox::new(0, 1, None, None, 0.5).is_err());
    /// assert!(InitialBox::new(8, 1, Some((1.0, 0.0)), None, 0.5).is_err());
    /// ```
    pub fn new(
        ics: usize,
        seed: u64,
        x0_range: Option<(f64, f64)>,
        v0_range: Option<(f64, f64)>,
        d_max: f64,
    ) -> Result<Self, ModeError> {
        let region = attractor_region(d_max);
        Ok(InitialBox {
            ics: check_ics(ics)?,
            seed,
            x0_range: check_range("x0_range", x0_range.unwrap_or(region.0))?,
            v0_range: check_range("v0_range", v0_range.unwrap_or(region.1))?,
        })
    }
}

impl SweepMode {
    /// The mode named `name` (`fixed`, `sweep` or `multi`) — the one place the CLI and the Python
    /// module turn their options into a mode. For `multi`: the [`InitialBox`] of `ics`, `seed`,
    /// `x0_range`, `v0_range` and `d_max`. A range given is checked whatever the mode (a box
    /// that is no interval is a mistake even where it is not used).
    pub fn from_name(
        name: &str,
        ics: usize,
        seed: u64,
        x0_range: Option<(f64, f64)>,
        v0_range: Option<(f64, f64)>,
        d_max: f64,
    ) -> Result<Self, ModeError> {
        for (field, range) in [("x0_range", x0_range), ("v0_range", v0_range)] {
            if let Some(r) = range {
                check_range(field, r)?;
            }
        }
        match name {
            "fixed" => Ok(SweepMode::Fixed),
            "sweep" => Ok(SweepMode::Sweep),
            "multi" => {
                let b = InitialBox::new(ics, seed, x0_range, v0_range, d_max)?;
                Ok(SweepMode::Multi {
                    ics: b.ics,
                    seed: b.seed,
                    x0_range: b.x0_range,
                    v0_range: b.v0_range,
                })
            }
            other => Err(ModeError::Name(other.to_string())),
        }
    }
}

/// Settings of a sweep.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SweepOptions {
    /// Parameter name (any of [`geardyn_model::PARAMETER_NAMES`]).
    pub param: String,
    /// Parameter values, in order.
    pub values: Vec<f64>,
    /// Initial-state mode.
    pub mode: SweepMode,
    /// Simulation settings (method, transient and recorded periods).
    pub sim: SimOptions,
    /// Initial state for `Fixed` and the start of each continuation chain.
    pub y0: [f64; 2],
    /// Sections recorded.
    pub sections: Vec<Section>,
    /// Also compute the TLE (variational) from each run's final state over `sim.record_periods`.
    pub lyapunov: bool,
}

/// One unit of work: a value index on a branch.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct Task {
    /// Index into the values.
    pub index: usize,
    /// Branch: 0 fixed/multi, 1 forward (`up`), 2 backward (`down`).
    pub branch: u8,
}

impl Task {
    /// Branch name: `up` and `down` for the two continuation chains, `none` otherwise (fixed and
    /// multi-initial sweeps have no branches).
    pub fn branch_name(&self) -> &'static str {
        match self.branch {
            1 => "up",
            2 => "down",
            _ => "none",
        }
    }
}

/// One simulation within a task.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Run {
    /// Initial-state index (0 unless multi-initial).
    pub ic: usize,
    /// Initial state.
    pub y0: [f64; 2],
    /// Motion label: `n-p-q-r-s` when periodic, else the class word (`failed` when the
    /// integration failed: the reason is in [`Run::motion`]).
    pub label: String,
    /// Crossings per excitation period ([`Summary::rates`]); `None` in checkpoints written before
    /// it was recorded.
    #[serde(default)]
    pub rates: Option<[f64; 4]>,
    /// Period (0 = chaotic/quasi-periodic or failed).
    pub period: usize,
    /// Healthy attractor.
    pub healthy: bool,
    /// Dynamic instability proportion.
    pub p_id: f64,
    /// Maximum mesh force.
    pub max_force: f64,
    /// Minimum mesh force.
    pub min_force: f64,
    /// Back-side impacts in the record.
    pub impacts: u64,
    /// Largest impact force in each recorded excitation period.
    pub impact_force_per_period: Vec<f64>,
    /// Response amplitudes.
    pub amplitudes: Option<Amplitudes>,
    /// Section points `(section, x, v)`.
    pub points: Vec<(Section, f64, f64)>,
    /// TLE, if requested.
    pub tle: Option<f64>,
    /// Final state (continuation carries it on).
    pub final_state: [f64; 2],
    /// Decided class of the motion.
    #[serde(default)]
    pub motion: Motion,
    /// Period in mesh cycles of the mesh-cycle strobe (when an excitation period spans several).
    #[serde(default)]
    pub mesh_period: Option<usize>,
    /// Transient actually used (the requested one, extended while undecided).
    #[serde(default)]
    pub transient_used: u64,
    /// Excitation periods the run was followed in all ([`Summary::periods_integrated`]).
    #[serde(default)]
    pub periods_integrated: u64,
    /// The evidence of the verdict ([`Summary::decided_by`]).
    #[serde(default)]
    pub decided_by: crate::classify::DecidedBy,
}

impl Run {
    /// Whether the run touches the back side: an impact, back-side contact of a periodic orbit
    /// (not healthy), or a recorded crossing into back-side contact.
    pub fn touches_back_side(&self) -> bool {
        self.impacts > 0
            || (self.motion.is_periodic() && !self.healthy)
            || self
                .points
                .iter()
                .any(|p| matches!(p.0, Section::DsDown | Section::DdDown))
    }

    /// Why the run has no verdict (`failed` or `diverged`: the reason), else empty.
    pub fn reason(&self) -> String {
        match &self.motion {
            Motion::Failed { reason } => reason.clone(),
            m @ Motion::Diverged { .. } => m.describe(),
            _ => String::new(),
        }
    }
}

/// The result of one task.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TaskResult {
    /// The task.
    pub task: Task,
    /// Parameter value.
    pub value: f64,
    /// Runs (one, or `ics` for multi-initial).
    pub runs: Vec<Run>,
    /// The dimensionless parameters integrated at this value (a swept `pair.*` field changes
    /// what the pair computes).
    #[serde(default)]
    pub parameters: Option<ResolvedRecord>,
}

/// Sweep failure before any work starts.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SweepError {
    /// A parameter value makes an invalid model.
    #[error("{param} = {}: {reason}", geardyn_model::error::num(*.value))]
    Model {
        /// Parameter.
        param: String,
        /// Value.
        value: f64,
        /// Cause (not chained as an error source, so it is printed once).
        reason: ScenarioError,
    },
    /// No values.
    #[error("empty parameter range")]
    Empty,
    /// A subset of tasks asked of a sweep whose tasks depend on each other, or tasks not in it
    /// ([`run_sweep_tasks`]).
    #[error("{0}")]
    Tasks(String),
}

/// All tasks of a sweep, in output order.
pub fn tasks(opts: &SweepOptions) -> Vec<Task> {
    let n = opts.values.len();
    match opts.mode {
        SweepMode::Sweep => (0..n)
            .map(|index| Task { index, branch: 1 })
            .chain((0..n).map(|index| Task { index, branch: 2 }))
            .collect(),
        _ => (0..n).map(|index| Task { index, branch: 0 }).collect(),
    }
}

/// Default region `(x0_range, v0_range)` of the initial states that look for coexisting
/// attractors (multi-initial sweeps, attractor continuation, the report's coexistence studies):
/// `x0` in `+-(D + 3 l)`, `v0` in `+-3 l`, with `d_max` = `D` the largest half backlash of the
/// period ([`MeshModel::backlash_levels`]) and `l = max(D, 1)` (dimensionless: lengths in `b_c`,
/// velocities in `b_c omega_n`).
///
/// Why so wide: the attractors, not the backlash, set the scale. On the broken pair at
/// `omega` = 1.2, `F` = 0.07 an impacting `1-40-40` orbit coexists with the healthy `1-20-0`
/// one; it spans `x` in `[-1, 3.82]`, `x'` in `[-2.88, 2.43]` and its basin lies at `x0 > 1.7`:
/// 16 random starts found it 0 times in `+-1.5 x +-1` (the former default) and in
/// `+-2 x +-1.5`, 4 times in `+-3 x +-3`. The region holds that orbit whole.
pub fn attractor_region(d_max: f64) -> ((f64, f64), (f64, f64)) {
    let d = d_max;
    let l = 3.0 * d.max(1.0);
    ((-(d + l), d + l), (-l, l))
}

/// Deterministic initial state `ic` of value `index` (independent of scheduling).
pub fn initial_state(mode: &SweepMode, y0: [f64; 2], index: usize, ic: usize) -> [f64; 2] {
    match *mode {
        SweepMode::Multi {
            seed,
            x0_range,
            v0_range,
            ..
        } => {
            let mut rng = ChaCha8Rng::seed_from_u64(
                seed ^ ((index as u64) << 32) ^ (ic as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15),
            );
            [
                rng.gen_range(x0_range.0..=x0_range.1),
                rng.gen_range(v0_range.0..=v0_range.1),
            ]
        }
        _ => y0,
    }
}

/// The model at one swept value, through the scenario's builder (`pair.*` parameters rebuild the
/// pair's tables), with the parameters it integrates.
fn model_at(
    base: &Scenario,
    param: &str,
    value: f64,
) -> Result<(MeshModel, ResolvedRecord), SweepError> {
    base.with(param, value)
        .map(|s| (s.model().clone(), s.record()))
        .map_err(|reason| SweepError::Model {
            param: param.to_string(),
            value,
            reason,
        })
}

/// Simulates one run and extracts what a sweep records.
pub fn run_once(model: &MeshModel, y0: [f64; 2], ic: usize, opts: &SweepOptions) -> Run {
    let decided = simulate_decided(model, y0, &opts.sim, Decide::default());
    let tle = record_tles(opts, &[(model, &decided)]).pop().flatten();
    run_of(y0, ic, opts, decided, tle)
}

/// The exponents `--lyapunov` asks for ([`SweepOptions::lyapunov`]): over the recorded periods
/// (at least [`TLE_PERIODS`]: a shorter window reads a slowly converging orbit's exponent as
/// noise of either sign) from the end of each decided record, all together
/// ([`crate::lanes_tle::tle_many`]: in the lanes with fixed-step RK4); `None` for a failed run
/// or without `--lyapunov`.
pub(crate) fn record_tles(
    opts: &SweepOptions,
    runs: &[(&MeshModel, &Decided)],
) -> Vec<Option<f64>> {
    let mut out = vec![None; runs.len()];
    if !opts.lyapunov {
        return out;
    }
    let (idx, starts): (Vec<usize>, Vec<crate::lanes_tle::TleStart<'_>>) = runs
        .iter()
        .enumerate()
        .filter_map(|(i, (m, d))| {
            d.as_ref().ok().map(|(r, _, _)| {
                let (t, y) = r.final_state;
                (i, (*m, t, y, r.final_memory))
            })
        })
        .unzip();
    let periods = opts.sim.record_periods.max(TLE_PERIODS);
    let tles = crate::lanes_tle::tle_many(&starts, &opts.sim, periods);
    for (i, r) in idx.into_iter().zip(tles) {
        out[i] = r.map(|r| r.tle);
    }
    out
}

/// What a sweep records of a decided run.
pub(crate) fn run_of(
    y0: [f64; 2],
    ic: usize,
    opts: &SweepOptions,
    decided: Result<(SimResult, Summary, SimOptions), SimError>,
    tle: Option<f64>,
) -> Run {
    match decided {
        Err(e) => Run {
            motion: Motion::Failed {
                reason: e.to_string(),
            },
            transient_used: opts.sim.transient_periods,
            mesh_period: None,
            ic,
            y0,
            label: "failed".into(),
            rates: None,
            period: 0,
            healthy: false,
            // numbers of a failed run are meaningless; the label says so (0, not NaN, so that
            // checkpoints round-trip through JSON)
            p_id: 0.0,
            max_force: 0.0,
            min_force: 0.0,
            impacts: 0,
            impact_force_per_period: vec![],
            amplitudes: None,
            points: vec![],
            tle: None,
            final_state: y0,
            periods_integrated: 0,
            decided_by: crate::classify::DecidedBy::Error,
        },
        Ok((res, s, used)) => {
            let mut points = Vec::new();
            for sec in &opts.sections {
                match sec {
                    Section::Strobe => {
                        points.extend(res.strobe.iter().map(|p| (Section::Strobe, p.y[0], p.y[1])))
                    }
                    Section::Impact => points.extend(
                        res.mesh()
                            .events
                            .iter()
                            .filter(|e| e.kind == geardyn_model::EventKind::Impact)
                            .map(|e| (Section::Impact, e.x, e.v_before)),
                    ),
                    _ => points.extend(
                        res.mesh()
                            .crossings
                            .iter()
                            .filter(|c| Section::of_level(c.level) == *sec)
                            .map(|c| (*sec, c.x, c.v)),
                    ),
                }
            }
            let (_, y_end) = res.final_state;
            Run {
                ic,
                y0,
                label: s.label,
                rates: Some(s.rates),
                period: s.period,
                healthy: s.healthy,
                p_id: s.p_id,
                max_force: s.max_force,
                min_force: s.min_force,
                impacts: s.impacts,
                impact_force_per_period: res.mesh().impact_force_per_period.clone(),
                amplitudes: Some(res.amplitudes()),
                points,
                tle,
                final_state: y_end,
                motion: s.motion,
                mesh_period: s.mesh_period,
                transient_used: used.transient_periods,
                periods_integrated: s.periods_integrated,
                decided_by: s.decided_by,
            }
        }
    }
}

/// Runs the sweep. `done` holds results of a previous, interrupted run (they are not recomputed);
/// `on_done` receives each newly finished task (from any thread). Returns all results in
/// [`tasks`] order.
///
/// The start time of every run is `sim.tau0`: continuation carries the state, not the time, so
/// that each value sees the excitation at the same phase.
pub fn run_sweep<F>(
    base: &Scenario,
    opts: &SweepOptions,
    done: &HashMap<Task, TaskResult>,
    on_done: F,
) -> Result<Vec<TaskResult>, SweepError>
where
    F: Fn(&TaskResult) + Sync,
{
    sweep_tasks(base, opts, done, None, &on_done)
}

/// The tasks `only` of a fixed or multi-initial sweep (each of [`tasks`]), in [`tasks`] order:
/// the part of [`run_sweep`] a shard of a distributed plan computes. A task's runs depend on
/// nothing but the task (the lanes decide each run alone: `crate::lanes`), so any grouping of
/// the tasks gives the same results. A continuation (`SweepMode::Sweep`) carries the state from
/// value to value and is refused. Validates like [`run_sweep`].
pub fn run_sweep_tasks<F>(
    base: &Scenario,
    opts: &SweepOptions,
    only: &[Task],
    on_done: F,
) -> Result<Vec<TaskResult>, SweepError>
where
    F: Fn(&TaskResult) + Sync,
{
    if opts.mode == SweepMode::Sweep {
        return Err(SweepError::Tasks(
            "a continuation sweep (mode sweep) carries the state from value to value: its values cannot be computed apart".into(),
        ));
    }
    let all = tasks(opts);
    if let Some(t) = only.iter().find(|t| !all.contains(t)) {
        return Err(SweepError::Tasks(format!(
            "task {} (branch {}) is not one of the sweep's {} tasks",
            t.index,
            t.branch,
            all.len()
        )));
    }
    let only: std::collections::HashSet<Task> = only.iter().copied().collect();
    sweep_tasks(base, opts, &HashMap::new(), Some(&only), &on_done)
}

/// [`run_sweep`] of the tasks in `only` (all when `None`) not in `done`. Not generic over the
/// callback (the public functions are thin generic wrappers): the sweep, its lanes and decisions
/// are compiled once, here, not again in every crate and test that passes its own closure.
fn sweep_tasks(
    base: &Scenario,
    opts: &SweepOptions,
    done: &HashMap<Task, TaskResult>,
    only: Option<&std::collections::HashSet<Task>>,
    on_done: &(dyn Fn(&TaskResult) + Sync),
) -> Result<Vec<TaskResult>, SweepError> {
    if opts.values.is_empty() {
        return Err(SweepError::Empty);
    }
    // validate every value before spending any time
    let (models, records): (Vec<MeshModel>, Vec<ResolvedRecord>) = opts
        .values
        .iter()
        .map(|&v| model_at(base, &opts.param, v))
        .collect::<Result<Vec<_>, _>>()?
        .into_iter()
        .unzip();
    let all = tasks(opts);
    let finish = |t: Task, runs: Vec<Run>| {
        let r = TaskResult {
            task: t,
            value: opts.values[t.index],
            runs,
            parameters: Some(records[t.index].clone()),
        };
        // a run cut by a stop request (geardyn_solvers::cancel) is not finished work
        if !geardyn_solvers::cancel::requested() {
            on_done(&r);
        }
        r
    };
    let mut results: HashMap<Task, TaskResult> = done.clone();
    let fresh = match &opts.mode {
        SweepMode::Sweep => continuation_branches(opts, &models, done, &finish),
        mode => {
            let k = match mode {
                SweepMode::Multi { ics, .. } => (*ics).max(1),
                _ => 1,
            };
            let todo: Vec<Task> = all
                .iter()
                .copied()
                .filter(|t| !done.contains_key(t) && only.is_none_or(|o| o.contains(t)))
                .collect();
            // the batched path pays off where the lanes integrate something: fixed-step RK4, or a
            // decision's follow (crate::pair_engine::follow_method); an adaptive sweep of any other
            // model decides each run on its own thread (rounds would only add barriers)
            let batched = crate::lanes::lanes_apply(&opts.sim)
                || models
                    .iter()
                    .any(|m| crate::pair_engine::follow_method(m, &opts.sim).is_some());
            let runs = TaskRuns {
                opts,
                models: &models,
                k,
                finish: &finish,
            };
            if batched {
                runs.in_batches(&todo)
            } else {
                runs.one_by_one(&todo)
            }
        }
    };
    for r in fresh {
        results.insert(r.task, r);
    }
    Ok(all.into_iter().filter_map(|t| results.remove(&t)).collect())
}

/// A jump in a frequency-response branch: between `from` and `to` the RMS of `x` changes by more
/// than five times the branch's median step change and by at least 10% of its range, and both
/// sides are decided periodic motions (chaotic windows fluctuate from value to value without
/// "jumping").
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Jump {
    /// Branch (`up` or `down`).
    pub branch: &'static str,
    /// Parameter value before the jump.
    pub from: f64,
    /// Parameter value after the jump.
    pub to: f64,
    /// RMS of `x` before.
    pub rms_before: f64,
    /// RMS of `x` after.
    pub rms_after: f64,
}

/// Jumps of the continuation branches of a sweep (see [`Jump`]).
pub fn detect_jumps(results: &[TaskResult]) -> Vec<Jump> {
    let mut jumps = Vec::new();
    for branch in [1u8, 2u8] {
        let mut pts: Vec<(f64, f64, usize)> = results
            .iter()
            .filter(|r| r.task.branch == branch)
            .filter_map(|r| {
                r.runs[0]
                    .amplitudes
                    .map(|a| (r.value, a.rms_x, r.runs[0].period))
            })
            .collect();
        if branch == 2 {
            // in the order the backward sweep visited them
            pts.sort_by(|a, b| b.0.partial_cmp(&a.0).unwrap_or(std::cmp::Ordering::Equal));
        } else {
            pts.sort_by(|a, b| a.0.partial_cmp(&b.0).unwrap_or(std::cmp::Ordering::Equal));
        }
        if pts.len() < 3 {
            continue;
        }
        let mut d: Vec<f64> = pts.windows(2).map(|w| (w[1].1 - w[0].1).abs()).collect();
        let range = pts.iter().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max)
            - pts.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
        let steps = d.clone();
        d.sort_by(|a, b| a.partial_cmp(b).unwrap_or(std::cmp::Ordering::Equal));
        let median = d[d.len() / 2];
        for (i, &s) in steps.iter().enumerate() {
            // a jump connects two decided periodic branches; chaotic windows fluctuate
            let periodic = pts[i].2 > 0 && pts[i + 1].2 > 0;
            if s > 5.0 * median && s > 0.1 * range && periodic {
                jumps.push(Jump {
                    branch: if branch == 1 { "up" } else { "down" },
                    from: pts[i].0,
                    to: pts[i + 1].0,
                    rms_before: pts[i].1,
                    rms_after: pts[i + 1].1,
                });
            }
        }
    }
    jumps
}

/// Most values of a range (`--range`, `range=`, a map's axis).
pub const MAX_RANGE_VALUES: usize = 1_000_000;

/// A range `(START, STOP, COUNT)` that cannot make values.
#[derive(Debug, thiserror::Error)]
#[error("bad {name} ({}, {}, {count}): finite START and STOP (finite difference too) and 1 <= COUNT <= {max}", geardyn_model::error::num(*.start), geardyn_model::error::num(*.stop))]
pub struct RangeError {
    /// What the caller calls the range (`range`, `x`, `y`).
    pub name: String,
    /// Given start.
    pub start: f64,
    /// Given stop.
    pub stop: f64,
    /// Given count.
    pub count: usize,
    /// Most values allowed.
    pub max: usize,
}

/// The `count` values of the range `name` from `start` to `stop` ([`linspace`]), checked: finite
/// ends whose difference is finite too, `1 ..= max` values. The one check of a range for every
/// face (`--range 0.5:2:200`, `range=(0.5, 2, 200)`, a map's `--x omega:0.5:2:40`).
///
/// ```
/// use geardyn_analysis::bifurcation::range_values;
/// assert_eq!(range_values("range", (0.5, 1.0, 2), 10).unwrap(), vec![0.5, 1.0]);
/// let e = range_values("x", (0.5, f64::NAN, 9), 10).unwrap_err();
/// assert!(e.to_string().starts_with("bad x (0.5, NaN, 9)"));
/// ```
pub fn range_values(
    name: &str,
    (start, stop, count): (f64, f64, usize),
    max: usize,
) -> Result<Vec<f64>, RangeError> {
    if !(start.is_finite() && stop.is_finite() && (stop - start).is_finite())
        || count == 0
        || count > max
    {
        return Err(RangeError {
            name: name.to_string(),
            start,
            stop,
            count,
            max,
        });
    }
    Ok(linspace(start, stop, count))
}

/// Evenly spaced values `start..=stop` (`count` of them), each rounded to 12 significant digits.
///
/// The rounding keeps a grid a person typed as decimals decimal: `0.1 + 0.1 * 3` is
/// `0.30000000000000004` in binary, and that is what a record would print and what would run.
/// Rounded, the value that runs is the one written (`0.3`), at most `5e-13` relative from the
/// exact fraction of the interval.
///
/// ```
/// use geardyn_analysis::bifurcation::linspace;
/// assert_eq!(linspace(0.1, 0.5, 5), vec![0.1, 0.2, 0.3, 0.4, 0.5]);
/// assert_eq!(linspace(0.0, 1.0, 4)[1], 0.333333333333);
/// assert_eq!(linspace(-0.1, 0.2, 4), vec![-0.1, 0.0, 0.1, 0.2]);
/// ```
pub fn linspace(start: f64, stop: f64, count: usize) -> Vec<f64> {
    match count {
        0 => vec![],
        1 => vec![start],
        _ => (0..count)
            .map(|i| {
                let v = start + (stop - start) * i as f64 / (count - 1) as f64;
                // a value that is zero but for the rounding of the sum (a grid through zero): the
                // sum's rounding is relative to its terms, not to the range (0.5:1e300 keeps 0.5)
                let zero = i > 0 && v.abs() <= 1e-12 * (start.abs() + (v - start).abs());
                if zero {
                    0.0
                } else {
                    decimal12(v)
                }
            })
            .collect(),
    }
}

/// `v` rounded to 12 significant decimal digits (non-finite values unchanged).
fn decimal12(v: f64) -> f64 {
    if !v.is_finite() {
        return v;
    }
    format!("{v:.11e}").parse().unwrap_or(v)
}
