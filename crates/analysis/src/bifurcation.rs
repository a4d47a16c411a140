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
pub use crate::ranges::{linspace, range_values, RangeError, MAX_RANGE_VALUES};
use crate::simulate::{Amplitudes, SimError, SimOptions, SimResult, Summary};
pub use crate::sweep_settings::{
    attractor_region, check_ics, InitialBox, ModeError, Section, SectionError, SweepMode, MAX_ICS,
};
use geardyn_model::MeshModel;
use geardyn_scenario::{ResolvedRecord, Scenario, ScenarioError};
use geardyn_solvers::HybridSystem;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;

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
    /// The ensemble escape test that decided it ([`Summary::escape`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub escape: Option<crate::escape::EscapeSummary>,
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
    /// A box of initial states that holds no state of the model (wholly behind its rigid back
    /// stop).
    #[error("{0}")]
    Box(String),
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

/// Deterministic initial state `ic` of value `index` (independent of scheduling); a random one
/// is drawn among the states `admissible` accepts ([`crate::sweep_settings::draw_state`]).
pub fn initial_state(
    mode: &SweepMode,
    y0: [f64; 2],
    index: usize,
    ic: usize,
    admissible: impl Fn(&[f64; 2]) -> bool,
) -> [f64; 2] {
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
            crate::sweep_settings::draw_state(&mut rng, x0_range, v0_range, admissible)
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
            escape: None,
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
                escape: s.escape,
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
    if let SweepMode::Multi {
        x0_range, v0_range, ..
    } = opts.mode
    {
        for (m, v) in models.iter().zip(&opts.values) {
            crate::sweep_settings::check_box(x0_range, v0_range, |y| {
                m.admissible(opts.sim.tau0, y)
            })
            .map_err(|e| SweepError::Box(format!("{} = {}: {e}", opts.param, v)))?;
        }
    }
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
        for i in jump_steps(&pts) {
            jumps.push(Jump {
                branch: if branch == 1 { "up" } else { "down" },
                from: pts[i].0,
                to: pts[i + 1].0,
                rms_before: pts[i].1,
                rms_after: pts[i + 1].1,
            });
        }
    }
    jumps
}

/// The jumps of one continuation branch `pts` — `(value, amplitude, period)` in the order the
/// sweep visited them — as the indices `i` of the steps `i -> i + 1` that jump: the amplitude
/// changes by more than five times the branch's median step change and by at least 10 % of its
/// range, and both sides are decided periodic motions (period > 0). Fewer than 3 points: none.
pub fn jump_steps(pts: &[(f64, f64, usize)]) -> Vec<usize> {
    if pts.len() < 3 {
        return Vec::new();
    }
    let steps: Vec<f64> = pts.windows(2).map(|w| (w[1].1 - w[0].1).abs()).collect();
    let range = pts.iter().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max)
        - pts.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
    let mut d = steps.clone();
    d.sort_by(|a, b| a.partial_cmp(b).unwrap_or(std::cmp::Ordering::Equal));
    let median = d[d.len() / 2];
    steps
        .iter()
        .enumerate()
        // a jump connects two decided periodic branches; chaotic windows fluctuate
        .filter(|&(i, &s)| s > 5.0 * median && s > 0.1 * range && pts[i].2 > 0 && pts[i + 1].2 > 0)
        .map(|(i, _)| i)
        .collect()
}

/// Runs per thread in a batch of the lanes path of [`crate::bifurcation::run_sweep`].
const BATCH_PER_THREAD: usize = 64;

/// Makes a task's result of its runs and hands it on (see `crate::bifurcation::run_sweep`).
pub(crate) type Finish<'a> = dyn Fn(Task, Vec<Run>) -> TaskResult + Sync + 'a;

/// A continuation sweep: the up branch (1) and the down branch (2) in parallel, each carrying
/// the final state from value to value (a task of `done` passes its state on).
pub(crate) fn continuation_branches(
    opts: &SweepOptions,
    models: &[MeshModel],
    done: &HashMap<Task, TaskResult>,
    finish: &Finish,
) -> Vec<TaskResult> {
    let n = opts.values.len();
    let chain = |branch: u8| -> Vec<TaskResult> {
        let order: Vec<usize> = if branch == 1 {
            (0..n).collect()
        } else {
            (0..n).rev().collect()
        };
        let mut y = opts.y0;
        let mut out = Vec::new();
        for i in order {
            let t = Task { index: i, branch };
            if let Some(r) = done.get(&t) {
                y = r.runs[0].final_state;
                continue;
            }
            let run = run_once(&models[i], y, 0, opts);
            y = run.final_state;
            out.push(finish(t, vec![run]));
        }
        out
    };
    let (up, down) = rayon::join(|| chain(1), || chain(2));
    up.into_iter().chain(down).collect()
}

/// The first runs of a batch: (value index, initial condition, initial state) of each run, and
/// its simulation.
type Simulated = (
    Vec<(usize, usize, [f64; 2])>,
    Vec<Result<SimResult, SimError>>,
);

/// The `k` runs of each task of a fixed or multi-initial sweep.
pub(crate) struct TaskRuns<'a> {
    pub(crate) opts: &'a SweepOptions,
    pub(crate) models: &'a [MeshModel],
    pub(crate) k: usize,
    pub(crate) finish: &'a Finish<'a>,
}

impl TaskRuns<'_> {
    /// Each run decided on its own thread.
    pub(crate) fn one_by_one(&self, todo: &[Task]) -> Vec<TaskResult> {
        let (opts, mode) = (self.opts, &self.opts.mode);
        todo.par_iter()
            .map(|&t| {
                let runs: Vec<Run> = (0..self.k)
                    .into_par_iter()
                    .map(|ic| {
                        let m = &self.models[t.index];
                        let y0 = initial_state(mode, opts.y0, t.index, ic, |y| {
                            m.admissible(opts.sim.tau0, y)
                        });
                        run_once(m, y0, ic, opts)
                    })
                    .collect();
                (self.finish)(t, runs)
            })
            .collect()
    }

    /// In batches of tasks (each batch's results are handed on, so an interruption loses at most
    /// the two batches in progress): the first runs of a batch (with fixed-step RK4 in lockstep
    /// lanes, else one by one in parallel), then the decisions of the batch together in rounds
    /// (TLEs in parallel; transient extensions, persistence checks and records again in the lanes
    /// where they are RK4 — a decision's follow always is, crate::pair_engine::follow_method — and
    /// the adaptive integrator's records in parallel: crate::lanes_decide::decide_lanes). The
    /// batches are pipelined: a batch is classified while the next one runs (rayon balances the
    /// two), so the threads are not left waiting on the few long classifications of a batch.
    pub(crate) fn in_batches(&self, todo: &[Task]) -> Vec<TaskResult> {
        let k = self.k;
        let batch = (BATCH_PER_THREAD * rayon::current_num_threads())
            .div_ceil(k)
            .max(1);
        let mut out = Vec::with_capacity(todo.len());
        let mut pending: Option<(&[Task], Simulated)> = None;
        let mut batches = todo.chunks(batch);
        loop {
            let next = batches.next();
            let (decided, simulated) = rayon::join(
                || pending.take().map(|(tasks, sim)| (tasks, self.decide(sim))),
                || next.map(|tasks| (tasks, self.simulate(tasks))),
            );
            if let Some((tasks, decided)) = decided {
                let mut decided = decided.into_iter();
                for &t in tasks {
                    let runs: Vec<Run> = decided.by_ref().take(k).collect();
                    out.push((self.finish)(t, runs));
                }
            }
            pending = simulated;
            if pending.is_none() {
                break;
            }
        }
        out
    }

    /// The first runs of the tasks of a batch.
    fn simulate(&self, tasks: &[Task]) -> Simulated {
        let (opts, mode) = (self.opts, &self.opts.mode);
        let items: Vec<(usize, usize, [f64; 2])> = tasks
            .iter()
            .flat_map(|t| {
                let m = &self.models[t.index];
                (0..self.k).map(move |ic| {
                    let y0 = initial_state(mode, opts.y0, t.index, ic, |y| {
                        m.admissible(opts.sim.tau0, y)
                    });
                    (t.index, ic, y0)
                })
            })
            .collect();
        let runs: Vec<(&MeshModel, [f64; 2])> = items
            .iter()
            .map(|&(i, _, y0)| (&self.models[i], y0))
            .collect();
        let firsts = if let Ok(lane) = crate::lanes::LaneSim::new(&opts.sim) {
            crate::lanes::simulate_lanes(&runs, &lane)
        } else {
            runs.par_iter()
                .map(|&(m, y0)| crate::simulate::simulate(m, y0, &opts.sim))
                .collect()
        };
        (items, firsts)
    }

    /// The decisions of a batch's runs: runs whose model the lanes cover are decided together
    /// (their integrations in the lanes), the others one by one.
    fn decide(&self, (items, lane_results): Simulated) -> Vec<Run> {
        let opts = self.opts;
        let runs: Vec<(&MeshModel, [f64; 2])> = items
            .iter()
            .map(|&(i, _, y0)| (&self.models[i], y0))
            .collect();
        let decided = crate::lanes_decide::decide_lane_runs(&runs, lane_results, &opts.sim);
        let with: Vec<(&MeshModel, &Decided)> =
            runs.iter().zip(&decided).map(|(r, d)| (r.0, d)).collect();
        let tles = record_tles(opts, &with);
        items
            .par_iter()
            .zip(decided.into_par_iter().zip(tles))
            .map(|(&(_, ic, y0), (d, tle))| run_of(y0, ic, opts, d, tle))
            .collect()
    }
}
