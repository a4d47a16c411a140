//! Decided classification of a motion (docs/analyses.md, "Classification rules").
//!
//! A run is called periodic only when the stroboscopic period test passes, chaotic only when the
//! top Lyapunov exponent is significantly positive, quasi-periodic only when it is zero within
//! its error and no period appears after the transient has been extended. Anything else first
//! gets a longer transient (doubling, [`MAX_EXTENSIONS`] times: at most
//! `2^MAX_EXTENSIONS` times the requested transient, at least [`MIN_EXTENSION`] periods per
//! round) and, if still undecided, is reported as `unsettled` with its numbers — never as chaos.
//!
//! Two more checks keep transients out of the verdict:
//! * a positive exponent is followed in blocks of growing length up to the decision horizon
//!   ([`DECISION_PERIODS`] excitation periods from the start, within the work budget
//!   [`DECISION_BUDGET`]) and measured again there; only if it is still significantly positive is
//!   the motion called chaotic (with that second exponent): a chaotic transient that lands on a
//!   periodic orbit (C1 at omega = 1.4271: 6 965 periods of transient chaos; the broken pair at
//!   omega = 1.2, F = 0.065: 6 090 revolutions) is then periodic, one that lands near a slowly
//!   attracting orbit is decided on as an undecided run, and one whose horizon the budget cuts
//!   short stays `unsettled`. The transients of those blocks (the *follow*, most of the work)
//!   run, on models whose contact law the lanes step ([`follow_validated`](crate::pair_engine::follow_validated)), as fixed-step RK4 at
//!   [`FOLLOW_STEPS`] steps per natural period ([`follow_method`](crate::pair_engine::follow_method)), in
//!   the lockstep lanes where a sweep decides its runs together; the records that decide a
//!   period and the exponents keep the requested integrator;
//! * a record too short to show every period up to `max_period` (`3 max_period` periods) is
//!   lengthened to that for the transient extensions of an undecided run: a period-3 orbit read
//!   on 8 recorded periods is not "not periodic"; a motion found periodic that way is recorded
//!   again over the requested length (whole orbit periods, at least three);
//! * a periodic record whose first points are still transient (the orbit was reached inside the
//!   record) is recorded again from its final state, so that forces, P_ID and health describe
//!   the orbit and not the approach to it.
//!
//! Why: a slowly converging periodic orbit near a bifurcation has no period within a short
//! record but a negative exponent; calling it chaotic is the error a researcher notices first.

use crate::engine::Engine;
use crate::escape::EscapeSummary;

mod escape_steps;
mod need;
use crate::period::{approaches_lower_period, lag_split, on_cycle_throughout};
use crate::simulate::{
    simulate, summarize, summarize_tol, Method, SimError, SimOptions, SimResult, Summary,
};
use crate::verdict::{significantly_negative, significantly_positive};
pub use crate::verdict::{
    DecidedBy, Motion, DECISION_BUDGET, DECISION_PERIODS, DIVERGED_SCALES, FOLLOW_STEPS,
    FOLLOW_STEPS_RANGE, MAX_DECISION_BUDGET,
};
use geardyn_model::{GearSystem, MeshModel};
pub use need::Need;
use serde::Serialize;

/// Doublings of the transient tried before a non-periodic, non-chaotic run is called
/// `unsettled`.
pub const MAX_EXTENSIONS: u32 = 4;
/// Smallest transient extension of a round (excitation periods).
pub const MIN_EXTENSION: u64 = 100;
/// Excitation periods of the Lyapunov estimate that decides chaos (at least; the record length
/// when longer).
pub const TLE_PERIODS: u64 = 100;
/// Excitation periods of the last look at the exponent of a run that the extensions and the
/// exponent over [`TLE_PERIODS`] left undecided (neither significantly positive or negative nor
/// decisively zero): ten times longer, so the standard error shrinks about threefold.
pub const TLE_LONG_PERIODS: u64 = 1000;
/// Mesh cycles (at least; the requested transient when longer) a motion with a positive TLE is
/// followed before it is called chaotic: chaotic transients of several hundred cycles are common
/// near crises (internal pair, omega = 1.80–1.89: 400–700 cycles).
pub const PERSIST_CYCLES: u64 = 500;

/// [`PERSIST_CYCLES`] in excitation periods of `model` (one period spans several mesh cycles on
/// a pair with a broken tooth).
fn persist_periods<S: GearSystem<N>, const N: usize>(sys: &S) -> u64 {
    PERSIST_CYCLES.div_ceil(u64::from(sys.cycles_per_period().max(1)))
}

/// The scale of a runaway: the largest half backlash `D_s` of the meshes, at least 1.
fn runaway_scale<S: GearSystem<N>, const N: usize>(sys: &S) -> f64 {
    (0..sys.mesh_count())
        .map(|k| sys.backlash_levels(k).1)
        .fold(f64::NEG_INFINITY, f64::max)
        .max(1.0)
}

/// The largest mesh displacement `|x_k|` of state `y` (NaN if any is).
fn largest_mesh_displacement<S: GearSystem<N>, const N: usize>(
    sys: &S,
    t: f64,
    y: &[f64; N],
) -> f64 {
    (0..sys.mesh_count()).fold(0.0, |m: f64, k| {
        let x = sys.mesh_state(t, y, k)[0].abs();
        if x.is_nan() || m.is_nan() {
            f64::NAN
        } else {
            m.max(x)
        }
    })
}
pub use crate::verdict::TLE_POSITIVE;

/// Classification effort.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Decide {
    /// Extend the transient of non-periodic, non-chaotic runs.
    pub extend: bool,
    /// Compute the TLE of non-periodic runs to tell chaos from unsettled.
    pub lyapunov: bool,
}

impl Default for Decide {
    fn default() -> Self {
        Decide {
            extend: true,
            lyapunov: true,
        }
    }
}

/// Excitation periods of the exponent that decides chaos: the record, at least [`TLE_PERIODS`].
pub fn tle_periods(opts: &SimOptions) -> u64 {
    opts.record_periods.max(TLE_PERIODS)
}

/// Factor on the period-test tolerance for motions whose TLE is significantly negative (after the
/// extended transient): their points must repeat to this many times the strict tolerance.
pub const ATTRACTING_PERIOD_TOL_FACTOR: f64 = 100.0;

/// Simulates and classifies: the periodic test first, then the TLE (chaos), then longer
/// transients; the summary's `motion` and `label` state the decision and `transient_periods`
/// in the returned options is the transient actually used.
pub fn simulate_decided<S: Engine<N>, const N: usize>(
    model: &S,
    y0: [f64; N],
    opts: &SimOptions,
    how: Decide,
) -> Result<(SimResult<N>, Summary, SimOptions), SimError> {
    if opts.record_periods == 0 {
        // (an empty record holds no evidence: no period, no range, no exponent)
        return Err(SimError::Setting {
            field: "record_periods",
            value: "0".into(),
            allowed: "at least 1 excitation period: a decision reads the record",
        });
    }
    let res = simulate(model, y0, opts)?;
    let s = summarize(model, &res, opts);
    simulate_decided_from(model, (res, s), opts, how)
}

/// As [`simulate_decided`], continuing from a first run already computed: `first` is the result
/// of [`simulate`] with `opts` (from any integrator of the same settings, e.g. the lockstep lanes
/// of [`crate::lanes`]) and its [`summarize`]; the decision (period test, TLE, transient
/// extensions) continues from its final state exactly as [`simulate_decided`] does after its own
/// first run, so the first run is never integrated twice.
pub fn simulate_decided_from<S: Engine<N>, const N: usize>(
    model: &S,
    first: (SimResult<N>, Summary),
    opts: &SimOptions,
    how: Decide,
) -> Result<(SimResult<N>, Summary, SimOptions), SimError> {
    // a follow may run on the system's faster engine ([`Engine::simulate_in_decision`]: the
    // pair's one-lane engine with its phase tables, the integration of a sweep's lanes, so a
    // run decides alike alone and in a sweep)
    let sim = |m: &S, y0: [f64; N], o: &SimOptions| m.simulate_in_decision(y0, o, opts);
    simulate_decided_with(model, first, opts, how, sim)
}

/// As [`simulate_decided_from`], the transient extensions simulated by `sim` (a function with the
/// contract of [`simulate`], e.g. [`crate::lanes::simulate_lane`] for fixed-step RK4).
pub fn simulate_decided_with<S: Engine<N>, const N: usize>(
    model: &S,
    first: (SimResult<N>, Summary),
    opts: &SimOptions,
    how: Decide,
    sim: impl Fn(&S, [f64; N], &SimOptions) -> Result<SimResult<N>, SimError>,
) -> Result<(SimResult<N>, Summary, SimOptions), SimError> {
    let mut d = Decision::new(model, first, opts, how);
    loop {
        match d.need() {
            Need::Sim { y0, opts } => d.simulated(sim(model, y0, &opts)),
            Need::Tle {
                t,
                y,
                memory,
                periods,
            } => d.tle(model.tle(opts, t, y, memory, periods)),
            Need::Escape { start, test } => d.escaped(model.escape(opts, &test, start)),
            Need::Done => return d.finish(),
        }
    }
}

/// What a [`Decision`] waits for.
#[derive(Clone, Copy, Debug)]
enum Wait {
    /// The TLE after the first record.
    TleFirst,
    /// Persistence block `k` of a positive exponent (blocks of growing length up to the
    /// decision horizon).
    Persist(u32),
    /// The follow of persistence block `k` ([`follow_method`]: the block's transient and, but in
    /// the last block, its record of the stroboscopic points). When those points show a period,
    /// or in the last block, the record with the requested integrator (`record` periods, the
    /// stroboscopic points only unless `last`) is [`Wait::Persist`] next; else block `k + 1`.
    Follow { k: u32, record: u64, last: bool },
    /// The ensemble escape test of a positive exponent.
    Escape,
    /// The record, with the requested integrator, of the orbit the escaped copies settled on.
    EscapeRecord,
    /// The TLE at the decision horizon: chaos only if it is still significantly positive.
    TlePersist,
    /// The TLE where the work budget ran out before the horizon.
    TleBudget,
    /// The full record where the work budget ran out after a block that recorded its
    /// stroboscopic points only (the numbers an `unsettled` verdict reports), then
    /// [`Wait::TleBudget`].
    BudgetRecord,
    /// Transient extension `k`.
    Extend(u32),
    /// The TLE after the last extension.
    TleLast,
    /// The TLE over [`TLE_LONG_PERIODS`] of a run the last one left undecided.
    TleLong,
    /// The record again of a periodic run (at tolerance `tol`).
    Settle(f64),
    /// A longer transient for a periodic run still approaching an orbit of lower period.
    Approach,
    /// The record again at a tighter integrator tolerance, for a period that may be the
    /// integrator's noise doubling a lower one (the period test's tolerance `tol`).
    Noise(f64),
    /// Nothing: decided.
    Done,
}

/// The decision of [`simulate_decided_with`] as a state machine: it states the integration it
/// needs next ([`Decision::need`]) and takes its result, so that the integrations of many runs
/// can be done together (the lockstep lanes of [`crate::lanes_decide::decide_lanes`]). Driven by
/// [`simulate_decided_with`] it is that function: one decision code for both.
pub struct Decision<'m, S = MeshModel, const N: usize = 2> {
    model: &'m S,
    opts: SimOptions,
    how: Decide,
    used: SimOptions,
    res: SimResult<N>,
    s: Summary,
    tle: Option<(f64, f64)>,
    /// The exponent over the short window while the long look runs ([`Wait::TleLong`]).
    short_tle: Option<(f64, f64)>,
    last_opts: SimOptions,
    wait: Wait,
    need: Need<N>,
    err: Option<SimError>,
    /// Records again and longer transients taken by [`Decision::settle`] (bounded).
    settles: u32,
    /// A periodic verdict's near-degenerate divisor already checked at a tighter tolerance.
    noise_checked: bool,
    /// The work budget ran out before the decision horizon ([`Decision::persist`]).
    budget_spent: bool,
    /// A persistence block ran (the motion was followed beyond its first record).
    persisted: bool,
    /// The period was read at the loose tolerance after a significantly negative exponent.
    loose_period: bool,
    /// The current record holds the stroboscopic points only (a persistence block that was not
    /// the last: [`SimOptions::strobe_only`]); it is recorded again before it is reported.
    strobe_record: bool,
    /// The escape test that decided the run (chaotic, or transient chaos).
    escape: Option<EscapeSummary>,
    /// The escape test was asked for (once per decision: a run it could not decide goes on as
    /// without it).
    escape_tried: bool,
}

impl<'m, S: Engine<N>, const N: usize> Decision<'m, S, N> {
    /// Starts the decision of a first run (`first`: the result of [`simulate`] with `opts` and its
    /// [`summarize`]).
    pub fn new(
        model: &'m S,
        first: (SimResult<N>, Summary),
        opts: &SimOptions,
        how: Decide,
    ) -> Self {
        let (res, s) = first;
        let mut d = Decision {
            model,
            opts: *opts,
            how,
            used: *opts,
            res,
            s,
            tle: None,
            short_tle: None,
            last_opts: *opts,
            wait: Wait::Done,
            need: Need::Done,
            err: None,
            settles: 0,
            noise_checked: false,
            budget_spent: false,
            persisted: false,
            loose_period: false,
            strobe_record: false,
            escape: None,
            escape_tried: false,
        };
        if d.runaway() {
            return d;
        }
        if d.s.motion.is_periodic() {
            d.settle(d.opts.method.period_tol());
            return d;
        }
        if how.lyapunov {
            d.ask_tle(Wait::TleFirst, tle_periods(opts));
        } else {
            d.extend_or_final(0);
        }
        d
    }

    /// The model of the run.
    pub fn model(&self) -> &'m S {
        self.model
    }

    /// The integration needed next.
    pub fn need(&self) -> Need<N> {
        self.need
    }

    /// The result of the run [`Need::Sim`] asked for.
    pub fn simulated(&mut self, r: Result<SimResult<N>, SimError>) {
        let Need::Sim { opts: more, .. } = self.need else {
            panic!("no run was asked for");
        };
        if let (Wait::Follow { k, .. }, Err(_)) = (self.wait, &r) {
            // the coarse follow failed where the requested integrator may not: that block again
            // with the requested integrator
            self.persist_with(k, false);
            return;
        }
        let res2 = match r {
            Ok(r) => r,
            Err(e) => {
                self.err = Some(e);
                self.ask(Wait::Done, Need::Done);
                return;
            }
        };
        let opts = self.opts;
        let strict = opts.method.period_tol();
        match self.wait {
            Wait::Follow { k, record, last } => {
                let x =
                    largest_mesh_displacement(self.model, res2.final_state.0, &res2.final_state.1);
                let scale = runaway_scale(self.model);
                // (NaN counts as runaway too)
                if x.is_nan() || x > DIVERGED_SCALES * scale {
                    // a runaway is decided on the requested integrator's run, not the follow's:
                    // that block again without the follow
                    self.persist_with(k, false);
                    return;
                }
                // a period in the follow's own stroboscopic points (fixed-step RK4 maps its
                // orbits onto themselves to rounding: the strict test) is confirmed by a record
                // with the requested integrator; without one the motion is followed on, and the
                // follow's periods are transient either way
                let seen = more.record_periods > 0
                    && summarize(self.model, &res2, &more).motion.is_periodic();
                self.take(res2, &more);
                let (t, y) = self.res.final_state;
                if !(seen || last) {
                    self.persist(k + 1);
                    return;
                }
                let rec = SimOptions {
                    tau0: t,
                    start_memory: self.res.final_memory,
                    transient_periods: 0,
                    record_periods: record,
                    strobe_only: !last,
                    ..self.opts
                };
                self.ask(Wait::Persist(k), Need::Sim { y0: y, opts: rec });
            }
            Wait::Persist(k) => {
                if self.continued(res2, more, strict) {
                    self.persist(k + 1);
                }
            }
            Wait::BudgetRecord => {
                self.s = summarize(self.model, &res2, &more);
                self.take(res2, &more);
                let periods = tle_periods(&self.opts);
                self.ask_tle(Wait::TleBudget, periods);
            }
            Wait::Extend(k) => {
                self.last_opts = more;
                if self.continued(res2, more, strict) {
                    self.extend_or_final(k + 1);
                }
            }
            Wait::Settle(tol) => {
                // the record again of a motion found periodic: read at the tolerance of the
                // on-orbit check (ten times the period test's), so that the integrator's noise
                // does not turn an orbit seen twice into an undecided run
                let mut s2 = summarize_tol(self.model, &res2, &more, tol);
                if !s2.motion.is_periodic() {
                    s2 = summarize_tol(self.model, &res2, &more, 10.0 * tol);
                }
                self.ask(Wait::Done, Need::Done);
                if s2.motion.is_periodic() {
                    self.take(res2, &more);
                    self.s = s2;
                    // the new record may still hold the end of a slow approach
                    self.settle(tol);
                } else {
                    // the period seen at the end of the record did not persist: it was a passage
                    // near an orbit (a saddle, or a window of a chaotic transient), not the
                    // motion; decide the run on as an undecided one
                    self.last_opts = more;
                    if self.continued(res2, more, strict) {
                        self.extend_or_final(0);
                    }
                }
            }
            Wait::Approach => {
                self.last_opts = more;
                if self.continued(res2, more, strict) {
                    // no longer periodic at the strict tolerance: decide it as a non-periodic
                    // run after its extensions
                    self.extend_or_final(MAX_EXTENSIONS);
                }
            }
            Wait::Noise(tol) => {
                // the tighter record decides between the period and its divisor; its numbers are
                // the more accurate ones either way, so it is the record when it shows the lower
                // period, and the run goes on as it was otherwise
                let s2 = summarize_tol(self.model, &res2, &more, tol);
                self.ask(Wait::Done, Need::Done);
                if s2.motion.is_periodic() && s2.period < self.s.period {
                    self.take(res2, &more);
                    self.s = s2;
                    // the rest of the decision (a record again of whole orbit periods) runs at
                    // the tolerance that showed the orbit, and the summary says so
                    self.opts.method = more.method;
                    self.used.method = more.method;
                }
                self.settle(tol);
            }
            Wait::EscapeRecord => {
                if self.continued(res2, more, strict) {
                    // the copies' orbit is no orbit of the requested integrator: follow this
                    // motion to the horizon as without the test
                    self.escape = None;
                    self.persist(0);
                }
            }
            Wait::Escape
            | Wait::TleFirst
            | Wait::TlePersist
            | Wait::TleBudget
            | Wait::TleLast
            | Wait::TleLong
            | Wait::Done => {
                panic!("no run was asked for")
            }
        }
    }

    /// The TLE [`Need::Tle`] asked for ([`Engine::tle`]).
    pub fn tle(&mut self, tle: Option<(f64, f64)>) {
        self.tle = tle;
        match self.wait {
            Wait::TleFirst => {
                if let Some((l, se)) = tle {
                    if significantly_positive(l, se) {
                        if self.how.extend && self.opts.escape.on() {
                            // a chaotic transient shows a positive exponent too: perturbed
                            // copies of the state tell a chaotic attractor (none leaves) from a
                            // chaotic saddle (they leak)
                            self.escape_test((l, se));
                        } else if self.how.extend {
                            // the motion is followed to the decision horizon before it is
                            // called chaotic
                            self.persist(0);
                        } else {
                            self.s.set_motion(Motion::Chaotic { tle: l, stderr: se });
                            self.ask(Wait::Done, Need::Done);
                        }
                        return;
                    }
                }
                self.extend_or_final(0);
            }
            Wait::TlePersist => match tle {
                Some((l, se)) if significantly_positive(l, se) => {
                    self.s.set_motion(Motion::Chaotic { tle: l, stderr: se });
                    self.ask(Wait::Done, Need::Done);
                }
                // no longer positive at the horizon: decided on as an undecided run after its
                // last extension (a sign over the long look, the loose period test)
                _ => {
                    self.wait = Wait::TleLast;
                    self.tle(tle);
                }
            },
            Wait::TleBudget => match tle {
                Some((l, se)) if significantly_positive(l, se) => {
                    self.s.set_motion(Motion::Unsettled {
                        tle: Some(l),
                        stderr: Some(se),
                    });
                    self.ask(Wait::Done, Need::Done);
                }
                _ => {
                    self.wait = Wait::TleLast;
                    self.tle(tle);
                }
            },
            Wait::TleLast => {
                // an exponent neither significant nor decisively zero over the short window (weak
                // chaos: C1 omega = 1.4045, 0.019 +- 0.010 over 100 periods, 0.0166 +- 0.0003
                // over 20 000): one longer look before calling the run unsettled
                let undecided = match tle {
                    Some((l, se)) => {
                        let zero = l.abs() <= TLE_POSITIVE && se <= TLE_POSITIVE;
                        !(significantly_positive(l, se) || significantly_negative(l, se) || zero)
                    }
                    None => false,
                };
                if undecided && tle_periods(&self.opts) < TLE_LONG_PERIODS && !self.budget_spent {
                    self.short_tle = tle;
                    self.ask_tle(Wait::TleLong, TLE_LONG_PERIODS);
                } else {
                    self.conclude();
                }
            }
            Wait::TleLong => {
                // the long look decides a sign only: an exponent near zero is no evidence of a
                // torus here (C1 at omega = 0.967336683417: a period-36 orbit, longer than the
                // period test's 32, whose exponent is -0.0009 +- 0.0002), so without a
                // significant sign the short estimate stands and the run stays unsettled
                let decisive = tle.is_some_and(|(l, se)| {
                    significantly_positive(l, se) || significantly_negative(l, se)
                });
                self.tle = if decisive { tle } else { self.short_tle };
                self.conclude()
            }
            _ => panic!("no TLE was asked for"),
        }
    }

    /// The decision: the run (its last record), its summary (`motion` and `label` state the
    /// decision) and the options actually used (`transient_periods`).
    pub fn finish(self) -> Result<(SimResult<N>, Summary, SimOptions), SimError> {
        assert!(matches!(self.need, Need::Done), "not decided yet");
        debug_assert!(
            !self.strobe_record || matches!(self.s.motion, Motion::Diverged { .. }),
            "a record of the strobe alone is never reported"
        );
        match self.err {
            Some(e) => Err(e),
            None => {
                let mut s = self.s;
                s.periods_integrated = self.used.transient_periods + self.res.strobe.len() as u64;
                if let (Some(e), Some((tle, _))) = (&self.escape, self.tle) {
                    if let (
                        Motion::Periodic { period },
                        crate::escape::Lifetime::Estimate { periods, stderr },
                    ) = (&s.motion, e.lifetime)
                    {
                        s.motion = Motion::TransientChaos {
                            period: *period,
                            lifetime: periods,
                            lifetime_stderr: stderr,
                            tle,
                        };
                    }
                }
                let by_escape = self.escape.is_some();
                s.escape = self.escape;
                s.decided_by = match s.motion {
                    Motion::TransientChaos { .. } => DecidedBy::Escape,
                    Motion::Chaotic { .. } if by_escape => DecidedBy::Escape,
                    Motion::Periodic { .. } if self.loose_period => DecidedBy::AttractingExponent,
                    Motion::Periodic { .. } => DecidedBy::PeriodTest,
                    Motion::Chaotic { .. } if self.how.extend && self.persisted => {
                        DecidedBy::PersistentChaos
                    }
                    Motion::Chaotic { .. } => DecidedBy::FirstExponent,
                    Motion::QuasiPeriodic { .. } => DecidedBy::ZeroExponent,
                    Motion::Unsettled { .. } if self.budget_spent => DecidedBy::Budget,
                    Motion::Unsettled { .. } => DecidedBy::Undecided,
                    Motion::Diverged { .. } => DecidedBy::Runaway,
                    Motion::Failed { .. } => DecidedBy::Error,
                };
                Ok((self.res, s, self.used))
            }
        }
    }

    /// Takes a continuation run (`more` after the current record) as the record; `true` when it
    /// is still undecided (neither run away nor periodic: the periodic one is settled here).
    fn continued(&mut self, res: SimResult<N>, more: SimOptions, strict: f64) -> bool {
        self.s = summarize(self.model, &res, &more);
        self.take(res, &more);
        self.ask(Wait::Done, Need::Done);
        if self.runaway() {
            return false;
        }
        if self.s.motion.is_periodic() {
            self.settle(strict);
            return false;
        }
        true
    }

    /// Excitation periods the motion has been followed so far (transients and the record).
    fn integrated(&self) -> u64 {
        self.used.transient_periods + self.res.strobe.len() as u64
    }

    /// Excitation periods the rest of the work budget ([`SimOptions::decision_budget`]) allows, at
    /// the run's mean work per period so far.
    fn budget_periods_left(&self) -> u64 {
        let used = self.res.rhs_evals;
        let per_period = (used / self.integrated().max(1)).max(1);
        self.opts.decision_budget.saturating_sub(used) / per_period
    }

    /// Persistence block `k` of a motion with a positive exponent: the run goes on (transient
    /// `B 2^k` periods, `B` the requested transient and at least [`PERSIST_CYCLES`] mesh cycles,
    /// then a record that shows every period) until the decision horizon
    /// ([`SimOptions::decision_periods`]), where the exponent is taken again
    /// ([`Wait::TlePersist`]); a period on the way ends it ([`Decision::continued`]). When the
    /// work budget cuts the horizon short, the exponent where it ran out is taken instead
    /// ([`Wait::TleBudget`]: unsettled if still positive).
    fn persist(&mut self, k: u32) {
        self.persist_with(k, true)
    }

    /// [`Decision::persist`]; `follow`: the block's transient may run with [`follow_method`].
    fn persist_with(&mut self, k: u32, follow: bool) {
        let done = self.integrated();
        let horizon = self.opts.decision_periods;
        let periods = tle_periods(&self.opts);
        if done >= horizon {
            self.ask_tle(Wait::TlePersist, periods);
            return;
        }
        let record = self.opts.record_periods.max(self.full_record());
        let left = self.budget_periods_left();
        // the horizon, or as far as the budget reaches when that is short of it
        let end = if left < horizon - done {
            if left < record {
                // not even another block's record: the budget ends the decision here (with the
                // record it reports, when the last block recorded its strobe alone)
                self.budget_spent = true;
                if self.strobe_record {
                    let (t, y0) = self.res.final_state;
                    let full = SimOptions {
                        tau0: t,
                        start_memory: self.res.final_memory,
                        transient_periods: 0,
                        ..self.opts
                    };
                    self.ask(Wait::BudgetRecord, Need::Sim { y0, opts: full });
                } else {
                    self.ask_tle(Wait::TleBudget, periods);
                }
                return;
            }
            done + left
        } else {
            horizon
        };
        let block = self
            .opts
            .transient_periods
            .max(persist_periods(self.model))
            .max(MIN_EXTENSION)
            .saturating_mul(1u64 << k.min(40));
        // the block that reaches the end records the requested length (the record a chaotic
        // verdict reports); earlier ones record enough stroboscopic points to show every period,
        // and nothing else (their only question is whether a period has appeared: a periodic
        // one is recorded again by `settle`). Within a record of the horizon the last block is a
        // record alone (it ends past it)
        let last = end - done <= block.saturating_add(record);
        let record = if last {
            self.opts.record_periods
        } else {
            record
        };
        let transient = block.min((end - done).saturating_sub(record));
        let more = SimOptions {
            tau0: self.res.final_state.0,
            start_memory: self.res.final_memory,
            transient_periods: transient,
            record_periods: record,
            strobe_only: !last,
            ..self.opts
        };
        let y0 = self.res.final_state.1;
        self.persisted = true;
        // the follow only where it is cheaper per period than the run so far (the budget reckons
        // a block at that mean: a finer follow would overrun it)
        let per_period = self.res.rhs_evals / self.integrated().max(1);
        let cheaper = |m: Method| match m {
            Method::Rk4 { steps_per_cycle } => {
                4 * u64::from(steps_per_cycle) * u64::from(self.model.cycles_per_period().max(1))
                    < per_period
            }
            Method::Dopri { .. } => false,
        };
        match self.model.follow_method(&self.opts) {
            Some(method) if follow && transient > 0 && cheaper(method) => {
                // its own record of the stroboscopic points (none in the last block: the record
                // the verdict reports follows)
                let coarse = SimOptions {
                    method,
                    record_periods: if last { 0 } else { more.record_periods },
                    strobe_only: true,
                    trajectory: false,
                    ..more
                };
                self.ask(
                    Wait::Follow {
                        k,
                        record: more.record_periods,
                        last,
                    },
                    Need::Sim { y0, opts: coarse },
                );
            }
            _ => self.ask(Wait::Persist(k), Need::Sim { y0, opts: more }),
        }
    }

    /// Takes `res` (a continuation run with `more`) as the record: the replaced record becomes
    /// transient, the record length is the new run's, and the work counters add up.
    fn take(&mut self, mut res: SimResult<N>, more: &SimOptions) {
        self.used.transient_periods += self.res.strobe.len() as u64 + more.transient_periods;
        self.used.record_periods = more.record_periods;
        self.strobe_record = more.strobe_only;
        res.steps += self.res.steps;
        res.rhs_evals += self.res.rhs_evals;
        self.res = res;
    }

    fn ask(&mut self, wait: Wait, need: Need<N>) {
        self.wait = wait;
        self.need = need;
    }

    /// Asks for the exponent over `periods` from the end of the current run.
    fn ask_tle(&mut self, wait: Wait, periods: u64) {
        // the exponent costs about three runs' work per period (the variational equation): at
        // most a third of the whole budget goes into one estimate (at omega = 0.001 one
        // revolution costs ten million evaluations: 100 periods took minutes)
        let per_period = (self.res.rhs_evals / self.integrated().max(1)).max(1);
        let periods = periods.min((self.opts.decision_budget / per_period / 3).max(1));
        let (t, y) = self.res.final_state;
        let memory = self.res.final_memory;
        self.ask(
            wait,
            Need::Tle {
                t,
                y,
                memory,
                periods,
            },
        );
    }

    /// Decided diverged if the current run ran away.
    fn runaway(&mut self) -> bool {
        let scale = runaway_scale(self.model);
        let x_max = self.res.meshes.iter().fold(0.0, |m: f64, r| {
            let x = r.x_range.0.abs().max(r.x_range.1.abs());
            if x.is_nan() || m.is_nan() {
                f64::NAN
            } else {
                m.max(x)
            }
        });
        // NaN counts as runaway too
        if x_max.is_nan() || x_max > DIVERGED_SCALES * scale {
            self.s.set_motion(Motion::Diverged { x_max });
            // (a record frozen far away may pass the period test: the label says what it is)
            let word = self.s.motion.word().to_string();
            self.s.label.clone_from(&word);
            for m in &mut self.s.meshes {
                m.label.clone_from(&word);
            }
            self.ask(Wait::Done, Need::Done);
            true
        } else {
            false
        }
    }

    /// A periodic record is taken as the orbit only when it is one:
    /// * still approaching an orbit of lower period (a slowly decaying flip mode makes a period-1
    ///   motion pass the period-2 test: [`approaches_lower_period`]), the transient is extended
    ///   (doubling, as for undecided runs);
    /// * with its head still transient (the orbit was reached inside the record), it would give
    ///   the orbit the forces, P_ID and health of its approach: it is recorded again from the
    ///   final state, until a record lies on the cycle throughout.
    ///
    /// At most [`MAX_EXTENSIONS`] such runs in all, so the cost stays bounded; after them the
    /// record at hand stands.
    fn settle(&mut self, tol: f64) {
        self.ask(Wait::Done, Need::Done);
        if self.settles >= MAX_EXTENSIONS && !self.strobe_record {
            return;
        }
        let pts = self.res.strobe_states();
        if self.how.extend && approaches_lower_period(&pts, self.s.period, tol) {
            let extra = (self.opts.transient_periods.max(MIN_EXTENSION)) << self.settles;
            self.settles += 1;
            let (t, y0) = self.res.final_state;
            let more = SimOptions {
                tau0: t,
                start_memory: self.res.final_memory,
                transient_periods: extra,
                ..self.opts
            };
            self.ask(Wait::Approach, Need::Sim { y0, opts: more });
            return;
        }
        // a divisor whose points differ by more than the tolerance but less than the loose one
        // (ATTRACTING_PERIOD_TOL_FACTOR), without decaying: either a genuine period with a small
        // split (just past a doubling) or the adaptive integrator's error repeating with the
        // doubled period (event-rich records; internal pair at omega = 0.8667: 14-6-0-6-0 at the
        // default rtol, 7-3-0-3-0 at rtol 1e-12 and with RK4 at 2048 steps per cycle). A second
        // record at a hundred times tighter tolerance tells them apart (fixed-step RK4 has no
        // such noise: its error does not depend on where the steps fall)
        let strict = tol == self.opts.method.period_tol();
        if let (false, true, true, Method::Dopri { rtol, atol }) = (
            self.noise_checked,
            self.how.extend,
            strict,
            self.opts.method,
        ) {
            if lag_split(&pts, self.s.period, tol, ATTRACTING_PERIOD_TOL_FACTOR * tol) {
                self.noise_checked = true;
                let (t, y) = self.res.final_state;
                let tight = SimOptions {
                    tau0: t,
                    start_memory: self.res.final_memory,
                    transient_periods: 0,
                    record_periods: pts.len() as u64,
                    method: Method::Dopri {
                        rtol: rtol / 100.0,
                        atol: atol / 100.0,
                    },
                    ..self.opts
                };
                self.ask(Wait::Noise(tol), Need::Sim { y0: y, opts: tight });
                return;
            }
        }
        let n = self.s.period as u64;
        let len = pts.len() as u64;
        // a head off the orbit by more than the integrator's noise (ten times the period
        // tolerance, as the mesh-cycle clock is checked): an approach, not noise
        let on_cycle = on_cycle_throughout(&pts, self.s.period, 10.0 * tol);
        // the record asked for, in whole orbit periods and at least three (the least that shows
        // the period); a longer one (an extension's, lengthened to decide) is recorded again
        let want = if n > 0 {
            self.opts.record_periods.div_ceil(n).max(3) * n
        } else {
            self.opts.record_periods
        };
        if on_cycle && (n == 0 || len.is_multiple_of(n)) && len <= want && !self.strobe_record {
            return;
        }
        // record again from the final state (on the orbit); a record of whole orbit periods
        // (the requested length rounded up to a multiple of the period), so that time fractions
        // (P_ID, durations) and counts are the orbit's and do not depend on where it was cut
        // the first time straight from the final state; if that record still held an approach
        // (the orbit seen at the end of a long chaotic transient), after a transient doubling as
        // the extensions of rule 3 do
        let transient = match self.settles {
            0 => 0,
            k => (self.opts.transient_periods.max(MIN_EXTENSION)) << (k - 1),
        };
        self.settles += 1;
        let (t, y) = self.res.final_state;
        let again = SimOptions {
            tau0: t,
            start_memory: self.res.final_memory,
            transient_periods: transient,
            record_periods: want,
            ..self.opts
        };
        self.ask(Wait::Settle(tol), Need::Sim { y0: y, opts: again });
    }

    /// Transient extension `k` (continuing in time: the stroboscopic phase stays that of tau0),
    /// or, after the last one, the TLE again and the conclusion.
    fn extend_or_final(&mut self, k: u32) {
        if self.how.extend && k < MAX_EXTENSIONS {
            let record = self.opts.record_periods.max(self.full_record());
            // the extensions draw on the decision's work budget too (at omega = 0.001 one
            // revolution costs a million evaluations): cut to what is left, none when not even
            // a record is
            let left = self.budget_periods_left();
            if left >= record {
                let extra =
                    ((self.opts.transient_periods.max(MIN_EXTENSION)) << k).min(left - record);
                let (t, y0) = self.res.final_state;
                let more = SimOptions {
                    tau0: t,
                    start_memory: self.res.final_memory,
                    transient_periods: extra,
                    record_periods: record,
                    ..self.opts
                };
                self.ask(Wait::Extend(k), Need::Sim { y0, opts: more });
                return;
            }
            self.budget_spent = true;
        }
        if self.how.extend && self.how.lyapunov {
            self.ask_tle(Wait::TleLast, tle_periods(&self.opts));
            return;
        }
        self.conclude();
    }

    /// Record length (excitation periods) that shows every period up to `max_period` three
    /// times: the least record of an extension.
    fn full_record(&self) -> u64 {
        3 * self.opts.max_period as u64
    }

    /// The verdict from the TLE at hand.
    fn conclude(&mut self) {
        let opts = self.opts;
        let strict = opts.method.period_tol();
        let how = self.how;
        self.ask(Wait::Done, Need::Done);
        if let Some((l, se)) = self.tle {
            if significantly_negative(l, se) {
                // an attracting motion of a periodically forced one-degree-of-freedom system is
                // a periodic orbit: the strict test failed on the integrator's noise (long
                // excitation periods with many events), so its period is read at a looser
                // tolerance
                let loose_tol = ATTRACTING_PERIOD_TOL_FACTOR * strict;
                let loose = summarize_tol(self.model, &self.res, &self.last_opts, loose_tol);
                if loose.motion.is_periodic() {
                    self.s = loose;
                    self.loose_period = true;
                    self.settle(loose_tol);
                    return;
                }
            }
        }
        let motion = match self.tle {
            Some((l, se)) if significantly_positive(l, se) => {
                // a positive exponent found after the extensions (a weak one the first window
                // missed) takes the escape test, or is followed to the horizon, like any other
                let done = self.integrated();
                if how.extend && !self.budget_spent && self.opts.escape.on() && !self.escape_tried {
                    self.escape_test((l, se));
                    return;
                }
                if how.extend && done < self.opts.decision_periods && !self.budget_spent {
                    self.persist(0);
                    return;
                }
                if self.budget_spent {
                    Motion::Unsettled {
                        tle: Some(l),
                        stderr: Some(se),
                    }
                } else {
                    Motion::Chaotic { tle: l, stderr: se }
                }
            }
            // quasi-periodic only on decisive evidence: an exponent precisely zero (within 1e-3,
            // with a standard error below 1e-3) and a record long enough for every period tested
            Some((l, se))
                if how.extend
                    && l.abs() <= TLE_POSITIVE
                    && se <= TLE_POSITIVE
                    && self.last_opts.record_periods >= self.full_record() =>
            {
                Motion::QuasiPeriodic { tle: l, stderr: se }
            }
            Some((l, se)) => Motion::Unsettled {
                tle: Some(l),
                stderr: Some(se),
            },
            None => Motion::default(),
        };
        self.s.set_motion(motion);
    }
}
