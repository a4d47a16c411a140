//! Top Lyapunov exponents of many runs in lockstep lanes: the variational equation rides with
//! the state (`x, x', dx, dx', dchi`) in the lanes of [`geardyn_solvers::ensemble`], as
//! [`tle_variational`](crate::lyapunov::tle_variational) integrates it with fixed-step RK4: the
//! same exponent to rounding on a periodic orbit (checked to 1e-9 relative; chaotic orbits of two
//! computations part after a few periods, their exponents agree within the spread).
//!
//! A lane steps the state and its tangent on the grid of the run's phase tables
//! ([`MeshLanes`]): the state by the RK4 stages; on an affine table (linear, bilateral,
//! frictionless law: C1) the tangent by the affine step's linear part
//! ([`MeshLanes::tangent_affine_step`]), otherwise by the RK4 stages too (its coefficients from
//! [`MeshLanes::tangent_coefficients`]). Every
//! step that may hold an event — where the tangent jumps by the saltation matrix — goes to the
//! scalar integrator of the augmented system ([`Tangent`]), which locates the event and applies
//! the jump, as it does for one run. At every stroboscopic instant the tangent is renormalised
//! and its log growth accumulated, as in the scalar function. Covered: the models whose contact
//! the lanes step themselves ([`crate::lanes::lanes_cover_contact`]).

// lane loops over several arrays read clearer (and vectorise as intended) with an index
#![allow(clippy::needless_range_loop)]

use crate::lane_plan::{chunk_len, lanes_cover_contact, table_time, LANES};
use crate::lyapunov::{
    tle_variational_with, Accumulator, LyapunovOptions, LyapunovResult, Tangent, TINY,
};
use crate::simulate::{Method, SimOptions};
use geardyn_model::mesh_lanes::AffineTables;
use geardyn_model::{MeshLaneBlock, MeshLanes, MeshMode, MeshModel};
use geardyn_solvers::ensemble::{
    compose_step, run_lanes, At, End, LaneDriver, Lockstep, Next, Soa, Stage, Start, StepStart,
};
use rayon::prelude::*;

/// The state and tangent of a mesh model in lanes: [`MeshLanes`] for the state, its
/// linearisation for the tangent. Guards depend on the state only.
pub struct TangentLanes<'a> {
    base: &'a MeshLanes,
}

impl<const L: usize> Lockstep<5, L> for TangentLanes<'_> {
    type Sys = Tangent<MeshModel>;
    type Lanes = MeshLaneBlock<L>;
    /// The state's affine step tables (used when the base table is affine).
    type Work = AffineTables<L>;
    const GUARD_DIMS: usize = 2;

    fn new_work(&self) -> AffineTables<L> {
        Lockstep::<2, L>::new_work(self.base)
    }

    fn steps_per_period(&self) -> usize {
        Lockstep::<2, L>::steps_per_period(self.base)
    }

    #[inline(always)]
    fn scalar_phase(&self, j: usize) -> bool {
        Lockstep::<2, L>::scalar_phase(self.base, j)
    }

    fn set_lane(
        &self,
        lanes: &mut MeshLaneBlock<L>,
        work: &mut AffineTables<L>,
        l: usize,
        sys: &Tangent<MeshModel>,
        mode: &MeshMode,
        h: f64,
    ) -> bool {
        sys.saltation && Lockstep::<2, L>::set_lane(self.base, lanes, work, l, &sys.sys, mode, h)
    }

    fn idle_lanes(&self) -> MeshLaneBlock<L> {
        Lockstep::<2, L>::idle_lanes(self.base)
    }

    fn set_idle(&self, lanes: &mut MeshLaneBlock<L>, l: usize) {
        Lockstep::<2, L>::set_idle(self.base, lanes, l)
    }

    #[inline(always)]
    fn rhs(
        &self,
        j: usize,
        stage: Stage,
        at: &At<L>,
        ln: &MeshLaneBlock<L>,
        y: &Soa<5, L>,
        dy: &mut Soa<5, L>,
    ) {
        let ys: Soa<2, L> = [y[0], y[1]];
        let mut f = [[0.0; L]; 2];
        Lockstep::<2, L>::rhs(self.base, j, stage, at, ln, &ys, &mut f);
        let (mut a, mut b) = ([0.0; L], [0.0; L]);
        self.base
            .tangent_coefficients(j, stage, at, ln, &ys, &mut a, &mut b);
        for l in 0..L {
            dy[0][l] = f[0][l];
            dy[1][l] = f[1][l];
            // (the scalar Tangent sums J[i][k] * dy[k] from 0: J = [[0, 1], [a, b]])
            dy[2][l] = 0.0 + 0.0 * y[2][l] + 1.0 * y[3][l];
            dy[3][l] = 0.0 + a[l] * y[2][l] + b[l] * y[3][l];
            // the lanes run laws without memory: the hysteresis perturbation stays 0
            dy[4][l] = 0.0;
        }
    }

    /// On an affine table the state takes the RK4 stages ([`MeshLanes::step_stages`], the
    /// scalar arithmetic) and the tangent the affine step's linear part
    /// ([`MeshLanes::tangent_affine_step`]): a few operations instead of four evaluations of its
    /// part of the field. Otherwise the composed RK4 step.
    #[inline(always)]
    fn step(
        &self,
        s: &StepStart<'_, 5, L>,
        ln: &MeshLaneBlock<L>,
        work: &AffineTables<L>,
        y1: &mut Soa<5, L>,
        f1: &mut Soa<5, L>,
    ) -> u32 {
        if !self.base.is_affine() {
            return compose_step(self, s, ln, y1, f1);
        }
        let y0 = s.y0;
        let mut s1 = [[0.0; L]; 2];
        let mut g1 = [[0.0; L]; 2];
        // the state by the RK4 stages (its trajectory is the scalar one, bit for bit, as
        // before: the decisions that continue from an exponent's end state do not move); the
        // tangent, the costly part, by the affine table
        let (y0s, f0s) = ([y0[0], y0[1]], [s.f0[0], s.f0[1]]);
        let state = s.with_states(&y0s, &f0s);
        let mut mask = self.base.step_stages(&state, ln, &mut s1, &mut g1);
        let (mut dx, mut dv) = ([0.0; L], [0.0; L]);
        let (mut a, mut b) = ([0.0; L], [0.0; L]);
        self.base.tangent_affine_step(
            &state,
            ln,
            work,
            [&y0[2], &y0[3]],
            [&mut dx, &mut dv],
            [&mut a, &mut b],
        );
        let mut fin = [0u32; L];
        for l in 0..L {
            y1[0][l] = s1[0][l];
            y1[1][l] = s1[1][l];
            y1[2][l] = dx[l];
            y1[3][l] = dv[l];
            // the lanes run laws without memory: the hysteresis perturbation stays 0
            y1[4][l] = y0[4][l];
            f1[0][l] = g1[0][l];
            f1[1][l] = g1[1][l];
            // (as `rhs`: the scalar Tangent sums J[i][k] * dy[k] from 0, J = [[0, 1], [a, b]])
            f1[2][l] = 0.0 + 0.0 * dx[l] + 1.0 * dv[l];
            f1[3][l] = 0.0 + a[l] * dx[l] + b[l] * dv[l];
            f1[4][l] = 0.0;
            // a tangent that overflowed goes to the scalar integrator
            fin[l] = u32::from((dx[l] + dv[l] + f1[3][l]).abs() < f64::INFINITY) << l;
        }
        mask &= fin.iter().fold(0, |m, b| m | b);
        mask
    }

    #[inline(always)]
    fn clear(
        &self,
        j: usize,
        ln: &MeshLaneBlock<L>,
        y0: &Soa<5, L>,
        y1: &Soa<5, L>,
        dev: &[f64; L],
    ) -> u32 {
        Lockstep::<2, L>::clear(self.base, j, ln, &[y0[0], y0[1]], &[y1[0], y1[1]], dev)
    }
}

/// Where an exponent starts: the model, the time, the state and the memory of its mode (the
/// hysteresis factor of an impact in progress, [`SimResult::final_memory`] of the run it
/// continues; 0 for a fresh start).
///
/// [`SimResult::final_memory`]: crate::simulate::SimResult::final_memory
pub type TleStart<'m> = (&'m MeshModel, f64, [f64; 2], f64);

/// One exponent to compute: the augmented system, its start and output index.
struct Item {
    out: usize,
    sys: Tangent<MeshModel>,
    t: f64,
    y: [f64; 5],
}

/// One lane's exponent in progress.
struct Job {
    out: usize,
    acc: Accumulator,
    done: u64,
    annihilated: u64,
}

struct TleDriver<'s, const L: usize> {
    items: &'s [Item],
    next: usize,
    periods: u64,
    steps_per_cycle: u32,
    jobs: [Option<Job>; L],
    out: Vec<(usize, Option<LyapunovResult>)>,
}

/// Tangent components start (and restart after an annihilation) at this value.
const UNIT: f64 = std::f64::consts::FRAC_1_SQRT_2;

impl<'s, 'b, const L: usize> LaneDriver<'s, TangentLanes<'b>, 5, L> for TleDriver<'s, L> {
    fn next_item(&mut self, l: usize) -> Option<Start<'s, Tangent<MeshModel>, 5>> {
        let it = self.items.get(self.next)?;
        self.next += 1;
        let m = &it.sys.sys;
        self.jobs[l] = Some(Job {
            out: it.out,
            acc: Accumulator::new(m.excitation_period(), self.periods),
            done: 0,
            annihilated: 0,
        });
        Some(Start {
            sys: &it.sys,
            t0: it.t,
            y0: it.y,
            memory: 0.0,
            h: m.mesh_cycle_time() / self.steps_per_cycle as f64,
            period: m.excitation_period(),
        })
    }

    fn on_step(
        &mut self,
        _l: usize,
        _sys: &Tangent<MeshModel>,
        _step: &geardyn_solvers::Step<5>,
        _before: &MeshMode,
        _stop: geardyn_solvers::Stop,
        _after: &MeshMode,
        _y: &[f64; 5],
    ) {
    }

    fn on_strobe(&mut self, _l: usize, _t: f64, _y: &[f64; 5]) -> Next {
        unreachable!("the TLE driver renormalises at every strobe (on_strobe_set)")
    }

    fn on_strobe_set(&mut self, l: usize, _t: f64, y: &mut [f64; 5]) -> Next {
        let job = self.jobs[l].as_mut().expect("busy lane");
        // as tle_variational: log growth of the tangent over the period, then renormalised
        // (summed from 0 in the scalar function's order)
        let norm = (0.0 + y[2] * y[2] + y[3] * y[3] + y[4] * y[4]).sqrt();
        if norm > TINY && norm.is_finite() {
            job.acc.push(norm.ln());
            y[2] /= norm;
            y[3] /= norm;
            y[4] /= norm;
        } else {
            job.annihilated += 1;
            job.acc.push(TINY.ln());
            y[2] = UNIT;
            y[3] = UNIT;
            y[4] = 0.0;
        }
        job.done += 1;
        if job.done >= self.periods {
            Next::Finish
        } else {
            Next::Continue
        }
    }

    fn on_end(&mut self, l: usize, end: End<5>) {
        let job = self.jobs[l].take().expect("busy lane");
        let r = match end {
            End::Done { .. } if job.done >= self.periods => Some(job.acc.finish(job.annihilated)),
            _ => None,
        };
        self.out.push((job.out, r));
    }
}

/// The top Lyapunov exponent of every `(model, t, y)` over `periods` excitation periods from
/// `(t, y)`, with fixed-step RK4 of `steps_per_cycle` steps per mesh cycle: the result of
/// [`tle_variational`](crate::lyapunov::tle_variational) (no transient, the tangent starting at
/// `(1, 1)/sqrt 2`) to rounding, in lanes of the phase tables of `tau0` (a start at a
/// stroboscopic instant of `tau0` uses the tables of the runs of a sweep starting there).
/// `None` where the integration failed or ended early. Results in input order; the models'
/// contact must be covered by the lanes
/// ([`crate::lanes::lanes_cover_contact`]), else their steps in contact go
/// to the scalar integrator. The same results for any thread count.
pub fn tle_lanes(
    runs: &[TleStart<'_>],
    periods: u64,
    steps_per_cycle: u32,
    tau0: f64,
) -> Vec<Option<LyapunovResult>> {
    tle_lanes_with::<LANES>(runs, periods, steps_per_cycle, tau0)
}

/// As [`tle_lanes`], on engines of `L` lanes (one lane: the same results, for a lone exponent).
pub fn tle_lanes_with<const L: usize>(
    runs: &[TleStart<'_>],
    periods: u64,
    steps_per_cycle: u32,
    tau0: f64,
) -> Vec<Option<LyapunovResult>> {
    let n = steps_per_cycle.max(1);
    // group by phase table (models and start phases with equal tables share lanes)
    let mut groups: Vec<(MeshLanes, Vec<Item>)> = Vec::new();
    // a table per model and start phase, built once (runs of one model share it)
    let mut seen: Vec<(*const MeshModel, u64, usize)> = Vec::new();
    // (the models the lanes cover have no memory: their starts carry 0)
    for (out, &(m, t, y, _)) in runs.iter().enumerate() {
        let tt = table_time(m, t, tau0);
        let key = (m as *const MeshModel, tt.to_bits());
        let item = Item {
            out,
            sys: Tangent {
                sys: m.clone(),
                saltation: true,
            },
            t,
            y: [y[0], y[1], UNIT, UNIT, 0.0],
        };
        let g = match seen.iter().find(|s| (s.0, s.1) == key) {
            Some(&(_, _, g)) => g,
            None => {
                let table = MeshLanes::new(m, n, tt);
                let g = groups
                    .iter()
                    .position(|(u, _)| *u == table)
                    .unwrap_or_else(|| {
                        groups.push((table, Vec::new()));
                        groups.len() - 1
                    });
                seen.push((key.0, key.1, g));
                g
            }
        };
        groups[g].1.push(item);
    }
    let mut work: Vec<(&MeshLanes, &[Item])> = Vec::new();
    for (table, items) in &groups {
        for c in items.chunks(chunk_len(items.len(), L)) {
            work.push((table, c));
        }
    }
    let parts: Vec<Vec<(usize, Option<LyapunovResult>)>> = work
        .par_iter()
        .map(|&(table, items)| {
            let batch = TangentLanes { base: table };
            let mut drv = TleDriver::<L> {
                items,
                next: 0,
                periods: periods.max(1),
                steps_per_cycle: n,
                jobs: std::array::from_fn(|_| None),
                out: Vec::with_capacity(items.len()),
            };
            run_lanes::<TangentLanes<'_>, _, 5, L>(&batch, &mut drv);
            drv.out
        })
        .collect();
    let mut out: Vec<Option<LyapunovResult>> = (0..runs.len()).map(|_| None).collect();
    for (i, r) in parts.into_iter().flatten() {
        out[i] = r;
    }
    out
}

/// Runs below which the exponents of [`tle_many`] run on one-lane engines (in parallel) rather
/// than sharing 16-lane ones (the same results either way).
const LONE_TLES: usize = 4;

/// The top Lyapunov exponent of every `(model, t, y)` over `periods` excitation periods from
/// `(t, y)` with the integrator of `sim`: with fixed-step RK4 the models whose contact the lanes
/// cover run in lockstep lanes ([`tle_lanes`], on the phase tables of `sim.tau0`; the same
/// result for a run alone or among others), the others by
/// [`tle_variational`](crate::lyapunov::tle_variational) one by one, in parallel. `None` where
/// the integration failed. Results in input order, the same for any thread count.
pub fn tle_many(
    runs: &[TleStart<'_>],
    sim: &SimOptions,
    periods: u64,
) -> Vec<Option<LyapunovResult>> {
    let scalar = |&(m, t, y, memory): &TleStart<'_>| {
        let lo = LyapunovOptions {
            period: m.excitation_period(),
            transient_periods: 0,
            periods,
            d0: 1e-6,
        };
        tle_variational_with::<_, 2, 5>(m.clone(), sim.method.scheme(m), t, y, memory, &lo, true)
            .ok()
    };
    let Method::Rk4 { steps_per_cycle } = sim.method else {
        return runs.par_iter().map(scalar).collect();
    };
    let (lanes, other): (Vec<usize>, Vec<usize>) =
        (0..runs.len()).partition(|&i| lanes_cover_contact(runs[i].0));
    let covered: Vec<TleStart<'_>> = lanes.iter().map(|&i| runs[i]).collect();
    let (a, b) = rayon::join(
        || {
            if covered.len() < LONE_TLES * rayon::current_num_threads().max(1) {
                covered
                    .par_iter()
                    .map(|r| {
                        tle_lanes_with::<1>(
                            std::slice::from_ref(r),
                            periods,
                            steps_per_cycle,
                            sim.tau0,
                        )
                        .pop()
                        .flatten()
                    })
                    .collect::<Vec<_>>()
            } else {
                tle_lanes(&covered, periods, steps_per_cycle, sim.tau0)
            }
        },
        || {
            other
                .par_iter()
                .map(|&i| scalar(&runs[i]))
                .collect::<Vec<_>>()
        },
    );
    let mut out: Vec<Option<LyapunovResult>> = (0..runs.len()).map(|_| None).collect();
    for (&i, r) in lanes.iter().zip(a).chain(other.iter().zip(b)) {
        out[i] = r;
    }
    out
}

/// [`crate::pair_engine::tle_of`] of every `(model, t, y)`, in input order ([`tle_many`]: with
/// fixed-step RK4 in lockstep lanes, the same result for a run alone or among others).
pub fn tles_of(runs: &[TleStart<'_>], opts: &SimOptions, periods: u64) -> Vec<Option<(f64, f64)>> {
    tle_many(runs, opts, periods)
        .into_iter()
        .map(|r| {
            r.filter(|r| r.tle.is_finite() && r.spread.is_finite())
                .map(|r| (r.tle, r.spread))
        })
        .collect()
}
