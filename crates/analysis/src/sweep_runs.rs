//! The runs of a sweep's tasks ([`crate::bifurcation::run_sweep`]): the two continuation
//! branches, each carrying the state from value to value, and the runs of fixed and
//! multi-initial tasks, one by one or in pipelined batches (simulated in the lanes, then decided
//! together).

use crate::bifurcation::{
    initial_state, record_tles, run_of, run_once, Run, SweepOptions, Task, TaskResult,
};
use crate::lanes_decide::Decided;
use crate::simulate::{SimError, SimResult};
use geardyn_model::MeshModel;
use rayon::prelude::*;
use std::collections::HashMap;

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
                        let y0 = initial_state(mode, opts.y0, t.index, ic);
                        run_once(&self.models[t.index], y0, ic, opts)
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
                (0..self.k).map(move |ic| (t.index, ic, initial_state(mode, opts.y0, t.index, ic)))
            })
            .collect();
        let runs: Vec<(&MeshModel, [f64; 2])> = items
            .iter()
            .map(|&(i, _, y0)| (&self.models[i], y0))
            .collect();
        let firsts = if crate::lanes::lanes_apply(&opts.sim) {
            crate::lanes::simulate_lanes(&runs, &opts.sim)
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
