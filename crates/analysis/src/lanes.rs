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

use crate::driver::Observer;
use crate::lane_plan::{chunk_len, table_time};
pub use crate::lane_plan::{lanes_apply, lanes_cover_contact, LaneSim, NotInLanes, LANES};
use crate::record::{crosses_level, extreme_middle, parabola_peak, Recorder};
use crate::simulate::{SimError, SimOptions, SimResult};
use geardyn_model::{MeshLaneBlock, MeshLanes, MeshMode, MeshModel};
use geardyn_solvers::dense::{hermite, nested_at};
use geardyn_solvers::ensemble::{
    run_lanes_on, At, Dispatch, End, LaneDriver, LaneStep, Next, Stage, Start,
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
        let [a0, am, a1] = sample_times(t0, &dt, st.grid);
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

/// The recorder's sample times `t0 + theta*dt` and grid positions at theta = 0, 1/2 and 1 of
/// each lane's step.
#[inline(always)]
fn sample_times<const L: usize>(t0: &[f64; L], dt: &[f64; L], grid: &[f64; L]) -> [At<L>; 3] {
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
        a0.grid[l] = grid[l];
        am.grid[l] = grid[l] + 0.5;
        a1.grid[l] = grid[l] + 1.0;
    }
    [a0, am, a1]
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

/// The recording hooks of a mesh lane driver, written once: `LaneDriver::on_lockstep` and
/// `LaneDriver::on_step` of a driver with the fields `acc` (the lanes' running totals, an
/// [`Acc`]), `rec_mask` (the lanes that record) and `mesh_on` (mesh-cycle strobe instants
/// matter). A lockstep step is recorded by `acc`, except its rare lanes; a scalar step of a
/// recording lane `l` goes to the lane's recorder `$rec` (an `Option<&mut PairRecorder>`, `None`
/// when the lane has none now) between a store and a load of its totals. `$s` names `self`.
macro_rules! recording_hooks {
    ($s:ident, $l:ident => $rec:expr) => {
        #[inline(always)]
        fn on_lockstep(&mut $s, batch: &MeshLanes, st: &LaneStep<'_, MeshLaneBlock<L>, 2, L>) -> u32 {
            $s.acc.record(batch, st, st.mask & $s.rec_mask, $s.mesh_on)
        }

        fn on_step(
            &mut $s,
            $l: usize,
            _sys: &MeshModel,
            step: &Step<2>,
            before: &MeshMode,
            stop: Stop,
            after: &MeshMode,
            y_after: &[f64; 2],
        ) {
            if $s.rec_mask & (1 << $l) == 0 {
                return;
            }
            if let Some(rec) = $rec {
                $s.acc.store($l, rec);
                let own = rec.sys;
                rec.on_step(&own, step, before, stop, after, y_after);
                $s.acc.load($l, rec);
            }
        }
    };
}
pub(crate) use recording_hooks;

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

    recording_hooks!(self, l => self.jobs[l].as_mut().and_then(|j| j.rec.as_mut()));

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
pub(crate) struct Item<'s> {
    pub(crate) out: usize,
    pub(crate) model: &'s MeshModel,
    pub(crate) y0: [f64; 2],
    pub(crate) t0: f64,
    pub(crate) memory: f64,
    pub(crate) transient: u64,
    pub(crate) record: u64,
    /// Record the stroboscopic points only ([`SimOptions::strobe_only`]).
    pub(crate) strobe_only: bool,
}

impl<'s> Item<'s> {
    /// Run `out`: `model` from `y0` with the start time, start memory, transient, record and
    /// strobe-only setting of `opts`.
    pub(crate) fn new(out: usize, model: &'s MeshModel, y0: [f64; 2], opts: &SimOptions) -> Self {
        Item {
            out,
            model,
            y0,
            t0: opts.tau0,
            memory: opts.start_memory,
            transient: opts.transient_periods,
            record: opts.record_periods,
            strobe_only: opts.strobe_only,
        }
    }
}

/// Work items grouped by phase table.
pub(crate) type Groups<'s> = Vec<(MeshLanes, Vec<Item<'s>>)>;

/// Phase tables built at once by [`group`] (about 80 kB each at 512 steps per cycle).
const TABLE_BATCH: usize = 64;

/// Groups runs by phase table (models with equal tables share lanes); runs starting at a
/// stroboscopic instant of `tau0` use the tables of `tau0` ([`table_time`]). The tables of the
/// distinct (model, start) pairs are built in parallel (a sweep over omega has a model per value:
/// building them one by one was a fiftieth of a sweep's time), then compared in input order.
pub(crate) fn group<'s>(runs: &[Item<'s>], steps_per_cycle: u32, tau0: f64) -> Groups<'s> {
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
/// (the settings checked for the lanes: [`LaneSim`]), in lockstep lanes; results in input order.
///
/// ```
/// use geardyn_analysis::lanes::{simulate_lanes, LaneSim};
/// use geardyn_analysis::simulate::{simulate, Method, SimOptions};
/// let m = geardyn_model::MeshModel::new(&geardyn_model::presets::classic()).unwrap();
/// let opts = SimOptions {
///     method: Method::Rk4 { steps_per_cycle: 128 },
///     transient_periods: 50,
///     record_periods: 10,
///     ..Default::default()
/// };
/// let lanes = simulate_lanes(&[(&m, [0.0, 0.0]), (&m, [0.5, 0.1])], &LaneSim::new(&opts).unwrap());
/// let scalar = simulate(&m, [0.5, 0.1], &opts).unwrap();
/// let s = &lanes[1].as_ref().unwrap().strobe;
/// assert!((s[9][1] - scalar.strobe[9][1]).abs() < 1e-12);
/// ```
pub fn simulate_lanes(
    runs: &[(&MeshModel, [f64; 2])],
    opts: &LaneSim,
) -> Vec<Result<SimResult, SimError>> {
    simulate_lanes_on::<LANES>(runs, opts, Dispatch::Auto)
}

/// As [`simulate_lanes`], on the copy of the engine `how` selects (when the CPU runs it): the
/// results are identical (for tests).
#[doc(hidden)]
pub fn simulate_lanes_dispatch(
    runs: &[(&MeshModel, [f64; 2])],
    opts: &LaneSim,
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
    opts: &LaneSim,
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
    opts: &LaneSim,
    grid_tau0: f64,
) -> Result<SimResult, SimError> {
    simulate_items(
        &[Item::new(0, model, y0, opts)],
        opts,
        grid_tau0,
        Dispatch::Auto,
        usize::MAX,
    )
    .pop()
    .expect("one run, one result")
}

fn simulate_lanes_on<const L: usize>(
    runs: &[(&MeshModel, [f64; 2])],
    opts: &LaneSim,
    how: Dispatch,
) -> Vec<Result<SimResult, SimError>> {
    let items: Vec<Item<'_>> = runs
        .iter()
        .enumerate()
        .map(|(out, &(model, y0))| Item::new(out, model, y0, opts))
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
pub(crate) fn simulate_items(
    items: &[Item<'_>],
    opts: &LaneSim,
    tau0: f64,
    how: Dispatch,
    lone: usize,
) -> Vec<Result<SimResult, SimError>> {
    let n = opts.steps_per_cycle();
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
pub(crate) fn sim_chunk<'s, const L: usize>(
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
