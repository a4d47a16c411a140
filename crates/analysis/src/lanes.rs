//! Lockstep ensemble simulation of the gear model: many [`simulate`](crate::simulate::simulate)
//! runs (fixed-step RK4) advanced together in the lanes of
//! [`geardyn_solvers::ensemble`], with the same recorded quantities.
//!
//! Each run is a work item: `transient_periods` discarded, then `record_periods` recorded by the
//! scalar [`Recorder`](mod@crate::simulate) of [`simulate`](crate::simulate::simulate). Steps the
//! scalar integrator takes for a lane (events, breakpoints, impacts, sticking) go to that
//! recorder as they are; a lockstep step is recorded by a vectorised copy of the recorder's
//! per-step arithmetic (durations, Simpson integrals, ranges and force extrema with their
//! parabola refinement) on running totals kept per lane: the same samples and extrema as the
//! scalar recorder, the integrals to rounding (Simpson's rule written as one expression per
//! step). The parts that must agree to the bit are shared, not copied: the samples of a step
//! ([`geardyn_solvers::dense::hermite`]), the mesh force ([`MeshLanes::force`], the model's
//! kernel), the section-level counting rule and the parabola refinement. A lockstep step with anything rarer — a section level crossed, a
//! mesh-cycle strobe instant, a step longer than two trajectory samples — is handed to the scalar
//! recorder as the scalar integrator would report it.
//!
//! Runs are grouped by phase table ([`MeshLanes`]: models that differ only in `omega`, `F`, `xi`,
//! `c` share one), split into chunks of whole lane loads and the chunks run in parallel (rayon).
//! A run's result depends on nothing but the run, so the output is the same for any thread
//! count.

// lane loops over several arrays read clearer (and vectorise as intended) with an index
#![allow(clippy::needless_range_loop, clippy::manual_memcpy)]

use crate::attractor::{Capture, CellLabels, Descriptor, IdentifyOptions, Outcome};
use crate::classify::{Decide, Decision, Need};
use crate::driver::Observer;
use crate::lane_plan::{chunk_len, table_time};
pub use crate::lane_plan::{lanes_apply, lanes_cover_contact, LANES};
use crate::lanes_tle::tles_of;
use crate::record::{crosses_level, extreme_middle, parabola_peak, Recorder};
use crate::simulate::{summarize, Method, SimError, SimOptions, SimResult, Summary};
use geardyn_model::{MeshLaneBlock, MeshLanes, MeshMode, MeshModel};
use geardyn_solvers::dense::{hermite, nested_at};
use geardyn_solvers::ensemble::{
    run_lanes, run_lanes_on, At, Dispatch, End, LaneDriver, LaneStep, Next, Stage, Start,
};
use geardyn_solvers::{Step, Stop};
use rayon::prelude::*;

/// The recorder of a pair's run (the lanes step the single pair only).
pub(crate) type PairRecorder<'s> = Recorder<&'s MeshModel, 2>;

/// Running totals of the recorder of every lane, in lanes.
pub(crate) struct Acc<const L: usize> {
    dur: [[f64; L]; 3],
    int: [[f64; L]; 4],
    xmin: [f64; L],
    xmax: [f64; L],
    fmax: [f64; L],
    fmin: [f64; L],
    /// Section levels and whether each is counted; steps longer than this go to the recorder.
    lv: [[f64; L]; 4],
    cnt: [[bool; L]; 4],
    long: [f64; L],
}

impl<const L: usize> Acc<L> {
    pub(crate) fn new() -> Self {
        Acc {
            dur: [[0.0; L]; 3],
            int: [[0.0; L]; 4],
            xmin: [0.0; L],
            xmax: [0.0; L],
            fmax: [0.0; L],
            fmin: [0.0; L],
            lv: [[0.0; L]; 4],
            cnt: [[false; L]; 4],
            long: [0.0; L],
        }
    }

    /// Takes lane `l`'s totals and settings from its recorder.
    pub(crate) fn load(&mut self, l: usize, rec: &PairRecorder<'_>) {
        let r = &rec.res.meshes[0];
        for s in 0..3 {
            self.dur[s][l] = r.durations[s];
        }
        for s in 0..4 {
            self.int[s][l] = r.integrals[s];
            self.lv[s][l] = rec.levels[0].levels[s];
            self.cnt[s][l] = rec.levels[0].count[s];
        }
        self.xmin[l] = r.x_range.0;
        self.xmax[l] = r.x_range.1;
        self.fmax[l] = r.max_force;
        self.fmin[l] = r.min_force;
        self.long[l] = rec.sample_dt * 2.0;
    }

    /// Writes lane `l`'s totals back into its recorder.
    pub(crate) fn store(&self, l: usize, rec: &mut PairRecorder<'_>) {
        let r = &mut rec.res.meshes[0];
        for s in 0..3 {
            r.durations[s] = self.dur[s][l];
        }
        for s in 0..4 {
            r.integrals[s] = self.int[s][l];
        }
        r.x_range = (self.xmin[l], self.xmax[l]);
        r.max_force = self.fmax[l];
        r.min_force = self.fmin[l];
    }

    /// Records a lockstep step of the lanes in `rec` (as `Recorder::on_step` does for a step
    /// without event or mode change), except lanes with a rare case, which are returned.
    #[inline(always)]
    pub(crate) fn record(
        &mut self,
        batch: &MeshLanes,
        st: &LaneStep<'_, MeshLaneBlock<L>, 2, L>,
        rec: u32,
        mesh_on: bool,
    ) -> u32 {
        if rec == 0 {
            return 0;
        }
        if mesh_on && batch.near_cycle_end(st.j) {
            return rec;
        }
        let (t0, t1) = (st.t0, st.t1);
        let mut dt = [0.0; L];
        let mut xm = [0.0; L];
        let mut vm = [0.0; L];
        let mut x1 = [0.0; L];
        let mut v1 = [0.0; L];
        let mut rare = [false; L];
        for l in 0..L {
            dt[l] = t1[l] - t0[l];
            let h = dt[l];
            // the Hermite interpolant of the step (Step::hermite) at theta = 1/2 and 1
            let mut ym = [0.0; 2];
            let mut ye = [0.0; 2];
            for i in 0..2 {
                let [r0, r1, r2, r3] =
                    hermite(st.y0[i][l], st.y1[i][l], st.f0[i][l], st.f1[i][l], h);
                ym[i] = nested_at([r0, r1, r2, r3, 0.0], 0.5);
                ye[i] = r0 + r1;
            }
            xm[l] = ym[0];
            vm[l] = ym[1];
            x1[l] = ye[0];
            v1[l] = ye[1];
            let x0 = st.y0[0][l];
            let mut c = dt[l] > self.long[l];
            for s in 0..4 {
                c |= crosses_level(s % 2 == 0, x0, x1[l], self.lv[s][l]) & self.cnt[s][l];
            }
            rare[l] = c;
        }
        let mut rare_mask = 0u32;
        for l in 0..L {
            rare_mask |= (rare[l] as u32) << l;
        }
        let rare_mask = rare_mask & rec;
        let upd = rec & !rare_mask;
        if upd == 0 {
            return rare_mask;
        }
        let mut x0 = [0.0; L];
        let mut v0 = [0.0; L];
        for l in 0..L {
            x0[l] = st.y0[0][l];
            v0[l] = st.y0[1][l];
        }
        let mut f0 = [0.0; L];
        let mut fm = [0.0; L];
        let mut f1 = [0.0; L];
        // the recorder's sample times t0 + theta*dt
        let mut a0 = At {
            t: [0.0; L],
            grid: [0.0; L],
        };
        let mut am = a0;
        let mut a1 = a0;
        for l in 0..L {
            a0.t[l] = t0[l] + 0.0 * dt[l];
            am.t[l] = t0[l] + 0.5 * dt[l];
            a1.t[l] = t0[l] + 1.0 * dt[l];
            a0.grid[l] = st.grid[l];
            am.grid[l] = st.grid[l] + 0.5;
            a1.grid[l] = st.grid[l] + 1.0;
        }
        batch.force(st.j, Stage::Start, &a0, st.lanes, &x0, &v0, &mut f0);
        batch.force(st.j, Stage::Mid, &am, st.lanes, &xm, &vm, &mut fm);
        batch.force(st.j, Stage::End, &a1, st.lanes, &x1, &v1, &mut f1);
        let mut vertex = [0u64; L];
        for l in 0..L {
            let on = upd & (1 << l) != 0;
            let ln = st.lanes;
            let (sd, sb) = (ln.sd[l], ln.sb[l]);
            let contact = sd + sb > 0.0;
            let d = dt[l];
            // durations: drive, separated, back
            let dur = [
                self.dur[0][l] + sd * d,
                self.dur[1][l] + (1.0 - sd - sb) * d,
                self.dur[2][l] + sb * d,
            ];
            let xs = [x0[l], xm[l], x1[l]];
            let fs = [f0[l], fm[l], f1[l]];
            let (mut xmin, mut xmax) = (self.xmin[l], self.xmax[l]);
            let (mut fmax, mut fmin) = (self.fmax[l], self.fmin[l]);
            let mut int = [
                self.int[0][l],
                self.int[1][l],
                self.int[2][l],
                self.int[3][l],
            ];
            for k in 0..3 {
                // (samples of a finite step: no NaN, so the one-instruction min/max)
                xmin = if xs[k] < xmin { xs[k] } else { xmin };
                xmax = if xs[k] > xmax { xs[k] } else { xmax };
                fmax = if fs[k] > fmax { fs[k] } else { fmax };
                fmin = if fs[k] < fmin { fs[k] } else { fmin };
            }
            // Simpson's rule over the step
            let d6 = d * (1.0 / 6.0);
            int[0] += d6 * (xs[0] + 4.0 * xs[1] + xs[2]);
            int[1] += d6 * (xs[0] * xs[0] + 4.0 * (xs[1] * xs[1]) + xs[2] * xs[2]);
            int[2] += d6 * (fs[0] + 4.0 * fs[1] + fs[2]);
            int[3] += d6 * (fs[0] * fs[0] + 4.0 * (fs[1] * fs[1]) + fs[2] * fs[2]);
            // an extreme middle sample: the vertex of the parabola through the three samples
            // is taken below, lane by lane (rare; as a vector expression for every lane its two
            // divisions were about a fifth of a recorded step)
            let vx = extreme_middle(xs[0], xs[1], xs[2]);
            let vf = contact & extreme_middle(fs[0], fs[1], fs[2]);
            vertex[l] = ((vx as u64) << l) | ((vf as u64) << (32 + l));
            if on {
                for s in 0..3 {
                    self.dur[s][l] = dur[s];
                }
                for s in 0..4 {
                    self.int[s][l] = int[s];
                }
                self.xmin[l] = xmin;
                self.xmax[l] = xmax;
                self.fmax[l] = fmax;
                self.fmin[l] = fmin;
            }
        }
        let vertex = vertex.iter().fold(0, |m, b| m | b);
        let samples_x = [&x0, &xm, &x1];
        let samples_f = [&f0, &fm, &f1];
        widen(
            vertex as u32 & upd,
            samples_x,
            &mut self.xmin,
            &mut self.xmax,
        );
        widen(
            (vertex >> 32) as u32 & upd,
            samples_f,
            &mut self.fmin,
            &mut self.fmax,
        );
        rare_mask
    }
}

/// Widens `[lo, hi]` of the lanes in `mask` by the extreme value of the parabola through their
/// samples `(0, s[0])`, `(1/2, s[1])`, `(1, s[2])` ([`parabola_peak`], as the scalar recorder).
#[inline(always)]
fn widen<const L: usize>(mut mask: u32, s: [&[f64; L]; 3], lo: &mut [f64; L], hi: &mut [f64; L]) {
    while mask != 0 {
        let l = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        if let Some(p) = parabola_peak(s[0][l], s[1][l], s[2][l]) {
            lo[l] = lo[l].min(p);
            hi[l] = hi[l].max(p);
        }
    }
}

/// One simulation: transient, then record.
enum Phase {
    Transient(u64),
    Record(u64),
}

struct Job<'s> {
    out: usize,
    model: &'s MeshModel,
    phase: Phase,
    rec: Option<PairRecorder<'s>>,
    /// Periods to record.
    record: u64,
    /// The stroboscopic points only ([`SimOptions::strobe_only`]).
    strobe_only: bool,
}

/// Lane driver of many [`simulate`](crate::simulate::simulate) runs.
struct SimDriver<'s, 'q, const L: usize> {
    items: &'q [Item<'s>],
    next: usize,
    opts: &'q SimOptions,
    steps_per_cycle: u32,
    jobs: [Option<Job<'s>>; L],
    acc: Acc<L>,
    rec_mask: u32,
    mesh_on: bool,
    out: Vec<(usize, Result<SimResult, SimError>)>,
}

impl<'s, const L: usize> SimDriver<'s, '_, L> {
    fn start_record(&mut self, l: usize, t: f64) {
        let o = self.opts;
        let job = self.jobs[l].as_mut().expect("busy lane");
        let traj_from = job.record.saturating_sub(o.trajectory_periods);
        let rec = Recorder::new(job.model, false, o.samples_per_cycle, t, traj_from)
            .strobe_only(job.strobe_only);
        job.phase = Phase::Record(job.record);
        // (a record of the strobe alone takes no part in the lockstep recording)
        if !job.strobe_only {
            self.acc.load(l, &rec);
            self.rec_mask |= 1 << l;
        }
        job.rec = Some(rec);
    }
}

impl<'s, const L: usize> LaneDriver<'s, MeshLanes, 2, L> for SimDriver<'s, '_, L> {
    fn next_item(&mut self, l: usize) -> Option<Start<'s, MeshModel, 2>> {
        let &Item {
            out,
            model,
            y0,
            t0,
            memory,
            transient,
            record,
            strobe_only,
        } = self.items.get(self.next)?;
        self.next += 1;
        self.jobs[l] = Some(Job {
            out,
            model,
            phase: Phase::Transient(transient),
            rec: None,
            record,
            strobe_only,
        });
        if transient == 0 {
            self.start_record(l, t0);
        }
        Some(Start {
            sys: model,
            t0,
            y0,
            memory,
            h: model.mesh_cycle_time() / self.steps_per_cycle as f64,
            period: model.excitation_period(),
        })
    }

    #[inline(always)]
    fn on_lockstep(&mut self, batch: &MeshLanes, st: &LaneStep<'_, MeshLaneBlock<L>, 2, L>) -> u32 {
        self.acc
            .record(batch, st, st.mask & self.rec_mask, self.mesh_on)
    }

    fn on_step(
        &mut self,
        l: usize,
        _sys: &MeshModel,
        step: &Step<2>,
        before: &MeshMode,
        stop: Stop,
        after: &MeshMode,
        y_after: &[f64; 2],
    ) {
        if self.rec_mask & (1 << l) == 0 {
            return;
        }
        let Some(rec) = self.jobs[l].as_mut().and_then(|j| j.rec.as_mut()) else {
            return;
        };
        self.acc.store(l, rec);
        let own = rec.sys;
        rec.on_step(&own, step, before, stop, after, y_after);
        self.acc.load(l, rec);
    }

    fn on_strobe(&mut self, l: usize, t: f64, y: &[f64; 2]) -> Next {
        let job = self.jobs[l].as_mut().expect("busy lane");
        match &mut job.phase {
            Phase::Transient(left) => {
                *left -= 1;
                if *left > 0 {
                    return Next::Continue;
                }
            }
            Phase::Record(left) => {
                if let Some(rec) = job.rec.as_mut() {
                    Observer::<&MeshModel, 2>::on_strobe(rec, t, y);
                }
                *left -= 1;
                return if *left == 0 {
                    Next::Finish
                } else {
                    Next::Continue
                };
            }
        }
        // end of the transient: the record is a new run of periods from here
        self.start_record(l, t);
        if self.jobs[l].as_ref().is_some_and(|j| j.record == 0) {
            Next::Finish
        } else {
            Next::Segment
        }
    }

    fn on_end(&mut self, l: usize, end: End<2>) {
        let bit = 1u32 << l;
        let Some(mut job) = self.jobs[l].take() else {
            return;
        };
        let recording = self.rec_mask & bit != 0;
        self.rec_mask &= !bit;
        let r = match end {
            End::Failed(e) => Err(SimError::Solver(e)),
            End::Done {
                t,
                y,
                memory,
                stats,
            } => {
                let mut res = match job.rec.take() {
                    Some(mut rec) => {
                        if recording {
                            self.acc.store(l, &mut rec);
                        }
                        rec.finish()
                    }
                    None => SimResult::default(),
                };
                res.steps = stats.steps;
                res.rhs_evals = stats.rhs_evals;
                res.final_state = (t, y);
                res.final_memory = memory;
                Ok(res)
            }
        };
        self.out.push((job.out, r));
    }
}

/// A work item: a run of `simulate` from `(t0, y0)` with `transient` periods of transient (and
/// the options' record); `out` is its output index.
#[derive(Clone, Copy)]
struct Item<'s> {
    out: usize,
    model: &'s MeshModel,
    y0: [f64; 2],
    t0: f64,
    memory: f64,
    transient: u64,
    record: u64,
    /// Record the stroboscopic points only ([`SimOptions::strobe_only`]).
    strobe_only: bool,
}

/// Work items grouped by phase table.
type Groups<'s> = Vec<(MeshLanes, Vec<Item<'s>>)>;

/// Phase tables built at once by [`group`] (about 80 kB each at 512 steps per cycle).
const TABLE_BATCH: usize = 64;

/// Groups runs by phase table (models with equal tables share lanes); runs starting at a
/// stroboscopic instant of `tau0` use the tables of `tau0` ([`table_time`]). The tables of the
/// distinct (model, start) pairs are built in parallel (a sweep over omega has a model per value:
/// building them one by one was a fiftieth of a sweep's time), then compared in input order.
fn group<'s>(runs: &[Item<'s>], steps_per_cycle: u32, tau0: f64) -> Groups<'s> {
    let key = |it: &Item<'s>| {
        let tt = table_time(it.model, it.t0, tau0);
        (it.model as *const MeshModel, tt.to_bits(), tt)
    };
    // distinct (model, table time) pairs in order of first appearance
    let mut index: std::collections::HashMap<(usize, u64), usize> = Default::default();
    let mut builds: Vec<(f64, &'s MeshModel)> = Vec::new();
    let mut of_run = Vec::with_capacity(runs.len());
    for it in runs {
        let (p, bits, tt) = key(it);
        let k = *index.entry((p as usize, bits)).or_insert_with(|| {
            builds.push((tt, it.model));
            builds.len() - 1
        });
        of_run.push(k);
    }
    let mut groups: Groups<'s> = Vec::new();
    let mut group_of: Vec<usize> = Vec::with_capacity(builds.len());
    // in batches, so that a map's thousands of models (one table kept) never hold thousands of
    // tables at once
    for batch in builds.chunks(TABLE_BATCH) {
        let tables: Vec<MeshLanes> = batch
            .par_iter()
            .map(|&(tt, m)| MeshLanes::new(m, steps_per_cycle, tt))
            .collect();
        for t in tables {
            let g = match groups.iter().position(|(u, _)| *u == t) {
                Some(g) => g,
                None => {
                    groups.push((t, Vec::new()));
                    groups.len() - 1
                }
            };
            group_of.push(g);
        }
    }
    for (it, k) in runs.iter().zip(of_run) {
        groups[group_of[k]].1.push(*it);
    }
    groups
}

/// Simulates every `(model, y0)` as [`simulate`](crate::simulate::simulate) with `opts` would
/// (fixed-step RK4; see [`lanes_apply`]), in lockstep lanes; results in input order.
///
/// ```
/// use geardyn_analysis::lanes::simulate_lanes;
/// use geardyn_analysis::simulate::{simulate, Method, SimOptions};
/// let m = geardyn_model::MeshModel::new(&geardyn_model::presets::classic()).unwrap();
/// let opts = SimOptions {
///     method: Method::Rk4 { steps_per_cycle: 128 },
///     transient_periods: 50,
///     record_periods: 10,
///     ..Default::default()
/// };
/// let lanes = simulate_lanes(&[(&m, [0.0, 0.0]), (&m, [0.5, 0.1])], &opts);
/// let scalar = simulate(&m, [0.5, 0.1], &opts).unwrap();
/// let s = &lanes[1].as_ref().unwrap().strobe;
/// assert!((s[9][1] - scalar.strobe[9][1]).abs() < 1e-12);
/// ```
pub fn simulate_lanes(
    runs: &[(&MeshModel, [f64; 2])],
    opts: &SimOptions,
) -> Vec<Result<SimResult, SimError>> {
    simulate_lanes_on::<LANES>(runs, opts, Dispatch::Auto)
}

/// As [`simulate_lanes`], on the baseline (not AVX2) copy of the engine: the results are
/// identical (for tests).
#[doc(hidden)]
pub fn simulate_lanes_baseline(
    runs: &[(&MeshModel, [f64; 2])],
    opts: &SimOptions,
) -> Vec<Result<SimResult, SimError>> {
    simulate_lanes_on::<LANES>(runs, opts, Dispatch::Baseline)
}

/// As [`simulate_lanes`], on the copy of the engine `how` selects (when the CPU runs it): the
/// results are identical (for tests).
#[doc(hidden)]
pub fn simulate_lanes_dispatch(
    runs: &[(&MeshModel, [f64; 2])],
    opts: &SimOptions,
    how: Dispatch,
) -> Vec<Result<SimResult, SimError>> {
    simulate_lanes_on::<LANES>(runs, opts, how)
}

/// One run as [`simulate`](crate::simulate::simulate) with `opts` would (see [`lanes_apply`]), on
/// an engine of a single lane: no lockstep, but the lanes' phase-table arithmetic, faster than the
/// scalar integrator for a lone long run (C1, one thread: 36 ms against 57 ms for 2100 periods of
/// 512 steps). The result is that of the same run in [`simulate_lanes`].
pub fn simulate_lane(
    model: &MeshModel,
    y0: [f64; 2],
    opts: &SimOptions,
) -> Result<SimResult, SimError> {
    simulate_lane_grid(model, y0, opts, opts.tau0)
}

/// As [`simulate_lane`], on the phase tables of the runs of a sweep starting at `grid_tau0`
/// when `opts.tau0` is a stroboscopic instant of that sweep (a continuation, as the decisions of
/// [`decide_lanes`] run it): the result is that of the same run in [`decide_lanes`] (for tests).
#[doc(hidden)]
pub fn simulate_lane_grid(
    model: &MeshModel,
    y0: [f64; 2],
    opts: &SimOptions,
    grid_tau0: f64,
) -> Result<SimResult, SimError> {
    let item = Item {
        out: 0,
        model,
        y0,
        t0: opts.tau0,
        memory: opts.start_memory,
        transient: opts.transient_periods,
        record: opts.record_periods,
        strobe_only: opts.strobe_only,
    };
    simulate_items(&[item], opts, grid_tau0, Dispatch::Auto, usize::MAX)
        .pop()
        .expect("one run, one result")
}

fn simulate_lanes_on<const L: usize>(
    runs: &[(&MeshModel, [f64; 2])],
    opts: &SimOptions,
    how: Dispatch,
) -> Vec<Result<SimResult, SimError>> {
    let items: Vec<Item<'_>> = runs
        .iter()
        .enumerate()
        .map(|(out, &(model, y0))| Item {
            out,
            model,
            y0,
            t0: opts.tau0,
            memory: opts.start_memory,
            transient: opts.transient_periods,
            record: opts.record_periods,
            strobe_only: opts.strobe_only,
        })
        .collect();
    if L == 1 {
        simulate_items(&items, opts, opts.tau0, how, usize::MAX)
    } else {
        simulate_items(&items, opts, opts.tau0, how, 0)
    }
}

/// Runs every item (output index `out` in `0..items.len()`) with the record and method of
/// `opts`, in lanes of the tables of `tau0` ([`group`]); a group of fewer than `lone` runs runs on
/// one-lane engines (the same results: a run's result depends on nothing but the run).
fn simulate_items(
    items: &[Item<'_>],
    opts: &SimOptions,
    tau0: f64,
    how: Dispatch,
    lone: usize,
) -> Vec<Result<SimResult, SimError>> {
    let Method::Rk4 { steps_per_cycle } = opts.method else {
        panic!("simulate_lanes needs the RK4 method");
    };
    assert!(!opts.trajectory, "simulate_lanes keeps no trajectory");
    let n = steps_per_cycle.max(1);
    let groups = group(items, n, tau0);
    let mut work: Vec<(&MeshLanes, &[Item<'_>], bool)> = Vec::new();
    for (table, items) in &groups {
        if items.len() < lone {
            for c in items.chunks(1) {
                work.push((table, c, true));
            }
        } else {
            for c in items.chunks(chunk_len(items.len(), LANES)) {
                work.push((table, c, false));
            }
        }
    }
    let parts: Vec<Vec<(usize, Result<SimResult, SimError>)>> = work
        .par_iter()
        .map(|&(table, items, one)| {
            if one {
                sim_chunk::<1>(table, items, opts, n, how)
            } else {
                sim_chunk::<LANES>(table, items, opts, n, how)
            }
        })
        .collect();
    let mut out: Vec<Option<Result<SimResult, SimError>>> =
        (0..items.len()).map(|_| None).collect();
    for (i, r) in parts.into_iter().flatten() {
        out[i] = Some(r);
    }
    out.into_iter()
        .map(|r| r.expect("every run has a result"))
        .collect()
}

/// The runs of one chunk on an engine of `L` lanes.
fn sim_chunk<'s, const L: usize>(
    table: &MeshLanes,
    items: &[Item<'s>],
    opts: &SimOptions,
    n: u32,
    how: Dispatch,
) -> Vec<(usize, Result<SimResult, SimError>)> {
    let mut drv = SimDriver::<L> {
        items,
        next: 0,
        opts,
        steps_per_cycle: n,
        jobs: std::array::from_fn(|_| None),
        acc: Acc::new(),
        rec_mask: 0,
        mesh_on: items
            .first()
            .is_some_and(|it| it.model.cycles_per_period() > 1),
        out: Vec::with_capacity(items.len()),
    };
    run_lanes_on::<MeshLanes, _, 2, L>(how, table, &mut drv);
    drv.out
}

/// Where a cell's identification stands.
enum IdPhase<'s, 'q> {
    /// Transient periods done, and the early-capture observer (when capturing).
    Transient { done: u64, cap: Option<Capture<'q>> },
    /// Recording the description (`left` periods to go), from `t0`.
    Record {
        left: u64,
        t0: f64,
        rec: Box<PairRecorder<'s>>,
    },
    /// Decided (captured, diverged) at a strobe instant.
    Decided(Outcome),
}

/// Lane driver of many [`identify`](crate::attractor::identify) runs of one model.
struct IdDriver<'s, 'q, F, const L: usize> {
    on_done: &'q F,
    model: &'s MeshModel,
    items: &'q [(usize, [f64; 2])],
    next: usize,
    opts: &'q IdentifyOptions,
    known: &'q [Descriptor],
    cells: Option<&'q CellLabels>,
    steps_per_cycle: u32,
    jobs: [Option<(usize, IdPhase<'s, 'q>)>; L],
    acc: Acc<L>,
    rec_mask: u32,
    mesh_on: bool,
    out: Vec<(usize, Outcome)>,
}

impl<'s, 'q, F, const L: usize> LaneDriver<'s, MeshLanes, 2, L> for IdDriver<'s, 'q, F, L>
where
    F: Fn(usize, &Outcome) + Sync,
{
    fn next_item(&mut self, l: usize) -> Option<Start<'s, MeshModel, 2>> {
        let &(out, y0) = self.items.get(self.next)?;
        self.next += 1;
        let o = self.opts;
        let cap = (o.early_capture && !self.known.is_empty())
            .then(|| Capture::new(self.known, self.cells, o));
        self.jobs[l] = Some((out, IdPhase::Transient { done: 0, cap }));
        Some(Start {
            sys: self.model,
            t0: o.sim.tau0,
            y0,
            memory: o.sim.start_memory,
            h: self.model.mesh_cycle_time() / self.steps_per_cycle as f64,
            period: self.model.excitation_period(),
        })
    }

    #[inline(always)]
    fn on_lockstep(&mut self, batch: &MeshLanes, st: &LaneStep<'_, MeshLaneBlock<L>, 2, L>) -> u32 {
        self.acc
            .record(batch, st, st.mask & self.rec_mask, self.mesh_on)
    }

    fn on_step(
        &mut self,
        l: usize,
        _sys: &MeshModel,
        step: &Step<2>,
        before: &MeshMode,
        stop: Stop,
        after: &MeshMode,
        y_after: &[f64; 2],
    ) {
        if self.rec_mask & (1 << l) == 0 {
            return;
        }
        if let Some((_, IdPhase::Record { rec, .. })) = self.jobs[l].as_mut() {
            self.acc.store(l, rec);
            let own = rec.sys;
            rec.on_step(&own, step, before, stop, after, y_after);
            self.acc.load(l, rec);
        }
    }

    fn on_strobe(&mut self, l: usize, t: f64, y: &[f64; 2]) -> Next {
        let o = self.opts;
        let (_, phase) = self.jobs[l].as_mut().expect("busy lane");
        match phase {
            IdPhase::Transient { done, cap } => {
                *done += 1;
                // (identify: one run_periods call per period while capturing, else one for all)
                let next = if let Some(cap) = cap {
                    Observer::<MeshModel, 2>::on_strobe(cap, t, y);
                    if cap.diverged {
                        *phase = IdPhase::Decided(Outcome::Diverged);
                        return Next::Finish;
                    }
                    if let Some(id) = cap.captured {
                        *phase = IdPhase::Decided(Outcome::Captured { id, periods: *done });
                        return Next::Finish;
                    }
                    Next::Segment
                } else {
                    Next::Continue
                };
                if *done < o.sim.transient_periods {
                    return next;
                }
                if !(y[0].abs() < o.divergence && y[1].abs() < o.divergence) {
                    *phase = IdPhase::Decided(Outcome::Diverged);
                    return Next::Finish;
                }
                // Recordable::describe: a new integration of record_periods from (t, y)
                let traj_from = o
                    .sim
                    .record_periods
                    .saturating_sub(o.sim.trajectory_periods);
                let rec = Recorder::new(self.model, false, o.sim.samples_per_cycle, t, traj_from);
                self.acc.load(l, &rec);
                self.rec_mask |= 1 << l;
                *phase = IdPhase::Record {
                    left: o.sim.record_periods,
                    t0: t,
                    rec: Box::new(rec),
                };
                Next::Restart
            }
            IdPhase::Record { left, rec, .. } => {
                Observer::<&MeshModel, 2>::on_strobe(&mut **rec, t, y);
                *left -= 1;
                if *left == 0 {
                    Next::Finish
                } else {
                    Next::Continue
                }
            }
            IdPhase::Decided(_) => Next::Finish,
        }
    }

    fn on_end(&mut self, l: usize, end: End<2>) {
        let bit = 1u32 << l;
        let recording = self.rec_mask & bit != 0;
        self.rec_mask &= !bit;
        let Some((out, phase)) = self.jobs[l].take() else {
            return;
        };
        let outcome = match (end, phase) {
            (End::Failed(e), _) => Outcome::Failed(e.to_string()),
            (End::Done { .. }, IdPhase::Decided(o)) => o,
            (
                End::Done {
                    t,
                    y,
                    memory,
                    stats,
                },
                IdPhase::Record { t0, mut rec, .. },
            ) => {
                if recording {
                    self.acc.store(l, &mut rec);
                }
                let mut res = rec.finish();
                res.steps = stats.steps;
                res.rhs_evals = stats.rhs_evals;
                res.final_state = (t, y);
                res.final_memory = memory;
                let rec_opts = SimOptions {
                    transient_periods: 0,
                    tau0: t0,
                    ..self.opts.sim
                };
                let s = summarize(self.model, &res, &rec_opts);
                let pts: Vec<[f64; 2]> = res.strobe_states();
                let mut d =
                    Descriptor::new(s.period, s.label, s.healthy, &pts, s.max_force, s.p_id);
                d.motion = s.motion;
                d.mesh_period = s.mesh_period;
                Outcome::Recorded(d)
            }
            (End::Done { t, .. }, IdPhase::Transient { .. }) => {
                Outcome::Failed(format!("integration terminated at t = {t}"))
            }
        };
        (self.on_done)(out, &outcome);
        self.out.push((out, outcome));
    }
}

/// Whether [`identify_lanes`] can run these settings: fixed-step RK4 without a trajectory, and
/// a transient and a record of at least one period each.
pub fn identify_lanes_apply(opts: &IdentifyOptions) -> bool {
    lanes_apply(&opts.sim) && opts.sim.transient_periods > 0 && opts.sim.record_periods > 0
}

/// [`identify`](crate::attractor::identify) of `model` from every initial state of `y0s` (see
/// [`identify_lanes_apply`]), in lockstep lanes; outcomes in input order. `on_done(i, outcome)`
/// receives each outcome as soon as it is known (from any thread).
pub fn identify_lanes<F>(
    model: &MeshModel,
    y0s: &[[f64; 2]],
    known: &[Descriptor],
    opts: &IdentifyOptions,
    on_done: F,
) -> Vec<Outcome>
where
    F: Fn(usize, &Outcome) + Sync,
{
    identify_lanes_in_dyn(model, y0s, known, None, opts, &on_done)
}

/// As [`identify_lanes`], also captured by the labelled cells of a basin grid
/// ([`crate::attractor::identify_in`]: the same outcomes).
pub fn identify_lanes_in<F>(
    model: &MeshModel,
    y0s: &[[f64; 2]],
    known: &[Descriptor],
    cells: Option<&CellLabels>,
    opts: &IdentifyOptions,
    on_done: F,
) -> Vec<Outcome>
where
    F: Fn(usize, &Outcome) + Sync,
{
    identify_lanes_in_dyn(model, y0s, known, cells, opts, &on_done)
}

/// [`identify_lanes_in`], compiled once (not generic over the callback: the lanes engine it
/// drives is instantiated here only).
fn identify_lanes_in_dyn(
    model: &MeshModel,
    y0s: &[[f64; 2]],
    known: &[Descriptor],
    cells: Option<&CellLabels>,
    opts: &IdentifyOptions,
    on_done: &(dyn Fn(usize, &Outcome) + Sync),
) -> Vec<Outcome> {
    let Method::Rk4 { steps_per_cycle } = opts.sim.method else {
        panic!("identify_lanes needs the RK4 method");
    };
    let n = steps_per_cycle.max(1);
    let table = MeshLanes::new(model, n, opts.sim.tau0);
    let items: Vec<(usize, [f64; 2])> = y0s.iter().copied().enumerate().collect();
    let parts: Vec<Vec<(usize, Outcome)>> = items
        .par_chunks(chunk_len(items.len(), LANES))
        .map(|chunk| {
            let mut drv = IdDriver::<_, LANES> {
                on_done: &on_done,
                model,
                items: chunk,
                next: 0,
                opts,
                known,
                cells,
                steps_per_cycle: n,
                jobs: std::array::from_fn(|_| None),
                acc: Acc::new(),
                rec_mask: 0,
                mesh_on: model.cycles_per_period() > 1,
                out: Vec::with_capacity(chunk.len()),
            };
            run_lanes::<MeshLanes, _, 2, LANES>(&table, &mut drv);
            drv.out
        })
        .collect();
    let mut out: Vec<Option<Outcome>> = (0..y0s.len()).map(|_| None).collect();
    for (i, o) in parts.into_iter().flatten() {
        out[i] = Some(o);
    }
    out.into_iter()
        .map(|o| o.expect("every cell has an outcome"))
        .collect()
}

/// Runs per thread in a round of [`decide_lanes`] below which they run on one-lane engines (in
/// parallel) rather than sharing a 16-lane one: on one thread (C1, 512 steps per cycle) a
/// 16-lane engine with k busy lanes took as long as k one-lane engines at k = 4, 2x longer at
/// k = 2, half as long at k = 8.
const LONE_RUNS: usize = 4;

/// [`simulate_decided_from`](crate::classify::simulate_decided_from) of many runs of a lanes
/// sweep at once: each `(model, first)` is a run of [`simulate_lanes`] with `opts` and its
/// `summarize`; the decisions (`Decision`, the code of
/// [`simulate_decided_with`](crate::classify::simulate_decided_with)) go in rounds, each round
/// running the TLEs asked for (scalar, in parallel) and all the integrations asked for
/// (transient extensions, persistence checks, records again) together in the lanes. Those
/// integrations continue a run from a stroboscopic instant and share the phase tables of the
/// sweep ([`simulate_lane_grid`] with `opts.tau0` is the same run on one lane); results in input
/// order, each the decision [`simulate_decided_with`](crate::classify::simulate_decided_with)
/// reaches with [`simulate_lane_grid`].
pub fn decide_lanes(
    runs: Vec<(&MeshModel, (SimResult, Summary))>,
    opts: &SimOptions,
    how: Decide,
) -> Vec<Result<(SimResult, Summary, SimOptions), SimError>> {
    type Out = Result<(SimResult, Summary, SimOptions), SimError>;
    let mut ds: Vec<Option<Decision<'_>>> = runs
        .into_iter()
        .map(|(m, first)| Some(Decision::new(m, first, opts, how)))
        .collect();
    let models: Vec<&MeshModel> = ds.iter().flatten().map(|d| d.model()).collect();
    let lone = LONE_RUNS * rayon::current_num_threads().max(1);
    // the decisions finished on their own (see `decide_alone`), pushed once each
    let alone: std::sync::Mutex<Vec<(usize, Out)>> = std::sync::Mutex::new(Vec::new());
    rayon::scope(|scope| loop {
        // A decision whose next integration would run on a one-lane engine anyway (its rung
        // has fewer than `lone` runs) leaves the rounds and finishes on its own, beside them:
        // a round waits for its slowest integration, and a few long follows at low omega
        // (many steps per period) otherwise kept a core idle for most of a round.
        let mut rung: std::collections::HashMap<u32, usize> = Default::default();
        for d in ds.iter().flatten() {
            if let Need::Sim { opts: o, .. } = d.need() {
                if let (true, Method::Rk4 { steps_per_cycle }) = (lanes_apply(&o), o.method) {
                    *rung.entry(steps_per_cycle).or_default() += 1;
                }
            }
        }
        for (i, slot) in ds.iter_mut().enumerate() {
            let detach = slot.as_ref().is_some_and(|d| match d.need() {
                Need::Sim { opts: o, .. } => match o.method {
                    Method::Rk4 { steps_per_cycle } if lanes_apply(&o) => {
                        rung[&steps_per_cycle] < lone
                    }
                    _ => false,
                },
                _ => false,
            });
            if detach {
                let mut d = slot.take().expect("checked above");
                let alone = &alone;
                scope.spawn(move |_| {
                    decide_alone(&mut d, opts);
                    let r = d.finish();
                    alone.lock().expect("no panic holds it").push((i, r));
                });
            }
        }
        let mut tles: Vec<(usize, f64, [f64; 2], f64, u64)> = Vec::new();
        let mut sims: Vec<(Item<'_>, SimOptions)> = Vec::new();
        let mut sim_of: Vec<usize> = Vec::new();
        for (i, d) in ds.iter().enumerate() {
            let Some(d) = d else { continue };
            match d.need() {
                Need::Tle {
                    t,
                    y,
                    memory,
                    periods,
                } => tles.push((i, t, y, memory, periods)),
                Need::Sim { y0, opts: o } => {
                    sims.push((
                        Item {
                            out: sims.len(),
                            model: models[i],
                            y0,
                            t0: o.tau0,
                            memory: o.start_memory,
                            transient: o.transient_periods,
                            record: o.record_periods,
                            strobe_only: o.strobe_only,
                        },
                        o,
                    ));
                    sim_of.push(i);
                }
                Need::Done => {}
            }
        }
        if tles.is_empty() && sims.is_empty() {
            break;
        }
        let (tle_res, sim_res) = rayon::join(
            || {
                // one batch per window length (the last look at an undecided run is longer),
                // results back in the order asked
                let mut out: Vec<Option<(f64, f64)>> = vec![None; tles.len()];
                let mut lengths: Vec<u64> = tles.iter().map(|e| e.4).collect();
                lengths.sort_unstable();
                lengths.dedup();
                for len in lengths {
                    let (idx, runs): (Vec<usize>, Vec<crate::lanes_tle::TleStart<'_>>) = tles
                        .iter()
                        .enumerate()
                        .filter(|(_, e)| e.4 == len)
                        .map(|(k, &(i, t, y, m, _))| (k, (models[i], t, y, m)))
                        .unzip();
                    for (k, r) in idx.into_iter().zip(tles_of(&runs, opts, len)) {
                        out[k] = r;
                    }
                }
                out
            },
            || run_needs(&sims, opts.tau0),
        );
        for (&(i, ..), r) in tles.iter().zip(tle_res) {
            ds[i].as_mut().expect("in the rounds").tle(r);
        }
        for (&i, r) in sim_of.iter().zip(sim_res) {
            ds[i].as_mut().expect("in the rounds").simulated(r);
        }
    });
    let mut out: Vec<Option<Out>> = ds.into_iter().map(|d| d.map(|d| d.finish())).collect();
    for (i, r) in alone.into_inner().expect("no panic holds it") {
        out[i] = Some(r);
    }
    out.into_iter()
        .map(|r| r.expect("every run is decided"))
        .collect()
}

/// Takes decision `d` to its end alone: each integration it asks for is the one a round of
/// [`decide_lanes`] would run for it (a follow or record in fixed-step RK4 on the sweep's phase
/// tables, one lane; the adaptive integrator's records as they are; the exponents of
/// [`tles_of`]), each with the same result alone as among others, so the decision is the same.
fn decide_alone(d: &mut Decision<'_>, opts: &SimOptions) {
    loop {
        match d.need() {
            Need::Sim { y0, opts: o } => {
                let r = if lanes_apply(&o) {
                    simulate_lane_grid(d.model(), y0, &o, opts.tau0)
                } else {
                    crate::simulate::simulate(d.model(), y0, &o)
                };
                d.simulated(r);
            }
            Need::Tle {
                t,
                y,
                memory,
                periods,
            } => {
                let r = tles_of(&[(d.model(), t, y, memory)], opts, periods)
                    .pop()
                    .flatten();
                d.tle(r);
            }
            Need::Done => return,
        }
    }
}

/// The integrations a round of [`decide_lanes`] asks for (`sims[k]`: output `k` with its options),
/// results in that order: fixed-step RK4 ones together in the lanes (one batch per step size: the requested RK4, or a follow's,
/// [`crate::classify::follow_method`]), with the phase tables of the sweep's `tau0`; the others
/// (the adaptive integrator's records) one by one, in parallel.
fn run_needs(sims: &[(Item<'_>, SimOptions)], tau0: f64) -> Vec<Result<SimResult, SimError>> {
    let in_lanes = |(_, o): &(Item<'_>, SimOptions)| lanes_apply(o);
    let mut steps: Vec<u32> = sims
        .iter()
        .filter(|s| in_lanes(s))
        .filter_map(|(_, o)| match o.method {
            Method::Rk4 { steps_per_cycle } => Some(steps_per_cycle),
            Method::Dopri { .. } => None,
        })
        .collect();
    steps.sort_unstable();
    steps.dedup();
    let lone = LONE_RUNS * rayon::current_num_threads().max(1);
    let mut out: Vec<Option<Result<SimResult, SimError>>> = (0..sims.len()).map(|_| None).collect();
    let (batches, single) = rayon::join(
        || {
            // the rungs side by side: a rung of a few long follows would otherwise leave a core
            // idle until it ends
            steps
                .par_iter()
                .map(|&n| {
                    let mut items: Vec<(Item<'_>, SimOptions)> = sims
                        .iter()
                        .filter(|s| in_lanes(s) && s.1.method == Method::Rk4 { steps_per_cycle: n })
                        .copied()
                        .collect();
                    // longest first, so that the lanes of a chunk retire together (the results
                    // do not depend on the order)
                    items.sort_by_key(|(it, _)| std::cmp::Reverse(it.transient));
                    let o = items[0].1;
                    let batch: Vec<Item<'_>> = items
                        .iter()
                        .enumerate()
                        .map(|(k, (it, _))| Item { out: k, ..*it })
                        .collect();
                    let res = simulate_items(&batch, &o, tau0, Dispatch::Auto, lone);
                    items
                        .into_iter()
                        .map(|(it, _)| it.out)
                        .zip(res)
                        .collect::<Vec<_>>()
                })
                .collect::<Vec<_>>()
        },
        || {
            sims.par_iter()
                .filter(|s| !in_lanes(s))
                .map(|(it, o)| (it.out, crate::simulate::simulate(it.model, it.y0, o)))
                .collect::<Vec<_>>()
        },
    );
    for (k, r) in batches.into_iter().flatten().chain(single) {
        out[k] = Some(r);
    }
    out.into_iter()
        .map(|r| r.expect("every integration has a result"))
        .collect()
}

/// A decided run: the record, its summary and the settings of the record.
pub type Decided = Result<(SimResult, Summary, SimOptions), SimError>;

/// The decisions ([`simulate_decided`](crate::classify::simulate_decided)) of many runs whose
/// first runs `first` came from [`simulate_lanes`] or, with the adaptive integrator, from
/// [`simulate`](crate::simulate::simulate) (`runs[i]` gave `first[i]`): the runs whose
/// contact the lanes cover ([`lanes_cover_contact`]) are decided together ([`decide_lanes`]),
/// the others one by one from their lanes record, and a run the lanes could not finish is
/// decided by the scalar path from its start. Results in input order.
pub fn decide_lane_runs(
    runs: &[(&MeshModel, [f64; 2])],
    first: Vec<Result<SimResult, SimError>>,
    opts: &SimOptions,
) -> Vec<Decided> {
    let mut batched = Vec::new();
    let mut single = Vec::new();
    for (j, (&(m, y0), r)) in runs.iter().zip(first).enumerate() {
        match r {
            Ok(res) if lanes_cover_contact(m) => batched.push((j, m, res)),
            r => single.push((j, m, y0, r)),
        }
    }
    let (a, b) = rayon::join(
        || {
            let (idx, firsts): (Vec<usize>, Vec<_>) = batched
                .into_iter()
                .map(|(j, m, res)| {
                    let s = summarize(m, &res, opts);
                    (j, (m, (res, s)))
                })
                .unzip();
            idx.into_iter()
                .zip(decide_lanes(firsts, opts, Decide::default()))
                .collect::<Vec<_>>()
        },
        || {
            single
                .into_par_iter()
                .map(|(j, m, y0, r)| {
                    let d = match r {
                        Ok(res) => {
                            let s = summarize(m, &res, opts);
                            crate::classify::simulate_decided_from(
                                m,
                                (res, s),
                                opts,
                                Decide::default(),
                            )
                        }
                        Err(_) => crate::classify::simulate_decided(m, y0, opts, Decide::default()),
                    };
                    (j, d)
                })
                .collect::<Vec<_>>()
        },
    );
    let mut out: Vec<Option<Decided>> = (0..runs.len()).map(|_| None).collect();
    for (j, d) in a.into_iter().chain(b) {
        out[j] = Some(d);
    }
    out.into_iter()
        .map(|d| d.expect("every run is decided"))
        .collect()
}

/// [`simulate_decided`](crate::classify::simulate_decided) of every `(model, y0)` with
/// fixed-step RK4 ([`lanes_apply`]): the first runs in lockstep lanes, then
/// [`decide_lane_runs`]. Results in input order, the same for any thread count.
pub fn simulate_decided_lanes(runs: &[(&MeshModel, [f64; 2])], opts: &SimOptions) -> Vec<Decided> {
    decide_lane_runs(runs, simulate_lanes(runs, opts), opts)
}

#[cfg(test)]
mod tests {
    use super::chunk_len;

    /// A small batch splits into equal chunks, a multiple of the thread count (18 runs on two
    /// threads: 9 + 9, not 16 + 2, whose 16-lane chunk alone set the wall time); a large one
    /// into whole lane loads, eight chunks per thread or more.
    #[test]
    fn chunks_are_balanced_over_the_threads() {
        let on = |threads: usize, items: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| chunk_len(items, 16))
        };
        assert_eq!(on(2, 18), 9);
        assert_eq!(on(2, 29), 15);
        assert_eq!(on(2, 3), 2);
        assert_eq!(on(1, 18), 9);
        assert_eq!(on(1, 16), 16);
        assert_eq!(on(2, 200), 15);
        assert_eq!(on(2, 1000), 64);
        assert_eq!(on(4, 1), 1);
    }
}
