//! Attractor identification in the pair's lockstep lanes: the cells of a basin pass or the
//! initial states of a continuation value run together, each captured early by a known attractor
//! or recorded and described as [`crate::identify::identify_in`] would (the same outcomes).

// lane loops over several arrays read clearer (and vectorise as intended) with an index
#![allow(clippy::needless_range_loop, clippy::manual_memcpy)]

use crate::attractor::{Descriptor, IdentifyOptions, Outcome};
use crate::driver::Observer;
use crate::identify::{Capture, CellLabels};
use crate::lane_plan::chunk_len;
use crate::lane_plan::{LaneSim, LANES};
use crate::lanes::{recording_hooks, Acc, PairRecorder};
use crate::record::Recorder;
use crate::simulate::{summarize, SimOptions};
use geardyn_model::{MeshLaneBlock, MeshLanes, MeshMode, MeshModel};
use geardyn_solvers::ensemble::{run_lanes, End, LaneDriver, LaneStep, Next, Start};
use geardyn_solvers::{Step, Stop};
use rayon::prelude::*;

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

/// Lane driver of many [`identify`](crate::identify::identify) runs of one model.
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

    recording_hooks!(self, l => match self.jobs[l].as_mut() {
        Some((_, IdPhase::Record { rec, .. })) => Some(rec),
        _ => None,
    });

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

/// Whether [`identify_lanes`] can run these settings ([`LaneIdentify::new`] succeeds).
pub fn identify_lanes_apply(opts: &IdentifyOptions) -> bool {
    LaneIdentify::new(opts).is_some()
}

/// Identification settings the lanes run: those of [`LaneSim`] with a transient and a record of at
/// least one period each. [`identify_lanes`] takes this type, so that settings it cannot run are
/// refused where they are built.
#[derive(Clone, Copy, Debug)]
pub struct LaneIdentify<'a> {
    opts: &'a IdentifyOptions,
    steps_per_cycle: u32,
}

impl<'a> LaneIdentify<'a> {
    /// `opts` checked for the lanes, or `None`.
    pub fn new(opts: &'a IdentifyOptions) -> Option<Self> {
        let lane = LaneSim::new(&opts.sim).ok()?;
        (opts.sim.transient_periods > 0 && opts.sim.record_periods > 0).then_some(Self {
            opts,
            steps_per_cycle: lane.steps_per_cycle(),
        })
    }

    /// The identification settings.
    pub fn options(&self) -> &'a IdentifyOptions {
        self.opts
    }
}

/// [`identify`](crate::identify::identify) of `model` from every initial state of `y0s`, in
/// lockstep lanes, also captured by the labelled `cells` of a basin grid when given
/// ([`crate::identify::identify_in`]: the same outcomes); outcomes in input order.
/// `on_done(i, outcome)` receives each outcome as soon as it is known (from any thread).
pub fn identify_lanes<F>(
    model: &MeshModel,
    y0s: &[[f64; 2]],
    known: &[Descriptor],
    cells: Option<&CellLabels>,
    lane: LaneIdentify<'_>,
    on_done: F,
) -> Vec<Outcome>
where
    F: Fn(usize, &Outcome) + Sync,
{
    identify_lanes_in_dyn(model, y0s, known, cells, lane, &on_done)
}

/// [`identify_lanes`], compiled once (not generic over the callback: the lanes engine it
/// drives is instantiated here only).
fn identify_lanes_in_dyn(
    model: &MeshModel,
    y0s: &[[f64; 2]],
    known: &[Descriptor],
    cells: Option<&CellLabels>,
    lane: LaneIdentify<'_>,
    on_done: &(dyn Fn(usize, &Outcome) + Sync),
) -> Vec<Outcome> {
    let opts = lane.opts;
    let n = lane.steps_per_cycle;
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
