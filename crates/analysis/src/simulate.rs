//! Time-history simulation of the gear [`MeshModel`] with the observers the analyses need:
//! stroboscopic points, level crossings (impact sections), contact-state durations, impacts with
//! velocity and peak force, mesh-force extrema, and the motion summary (period, `n-p-q-r-s`
//! label, healthy flag, P_ID) of docs/model.md §5.

use crate::classify::DecidedBy;
use crate::classify::Motion;
use crate::driver::{run_periods, Discard, Observer};
use crate::period::minimal_period_tol;
use geardyn_model::{ContactState, EventKind, MeshMode, MeshModel};
use geardyn_solvers::{HybridSystem, Integrator, Scheme, SolverError, Step, Stop};
use serde::{Deserialize, Serialize};

/// Integrator choice in model terms.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "method", rename_all = "snake_case")]
pub enum Method {
    /// Adaptive Dormand–Prince 5(4).
    Dopri {
        /// Relative tolerance.
        rtol: f64,
        /// Absolute tolerance.
        atol: f64,
    },
    /// Fixed-step RK4 with `steps_per_cycle` steps per mesh cycle.
    Rk4 {
        /// Steps per mesh cycle.
        steps_per_cycle: u32,
    },
}

/// Default RK4 steps per mesh cycle.
pub const DEFAULT_RK4_STEPS_PER_CYCLE: u32 = 512;

/// RK4 steps per mesh cycle a run accepts (the one home of this range: configuration, `--set`,
/// `geardyn bench` and Python check it here).
pub const RK4_STEPS_PER_CYCLE: std::ops::RangeInclusive<u32> = 8..=1_000_000;

/// Most excitation periods of one run's transient or record (1e7 periods already take hours).
pub const MAX_PERIODS: u64 = 10_000_000;

impl Default for Method {
    fn default() -> Self {
        Method::Dopri {
            rtol: geardyn_solvers::integrator::DEFAULT_RTOL,
            atol: geardyn_solvers::integrator::DEFAULT_ATOL,
        }
    }
}

/// Ratio of the period-test tolerance to the adaptive integrator's relative tolerance: a
/// periodic orbit recomputed over one period by DP5 repeats to a few hundred `rtol` at most
/// (local errors of ~100 steps per period, event times located to the same accuracy).
pub const PERIOD_TOL_PER_RTOL: f64 = 100.0;

impl Method {
    /// Relative tolerance of the period test for this integrator: [`PERIOD_TOL`] or, for DP5 at a
    /// loose tolerance, `PERIOD_TOL_PER_RTOL × rtol` (at the identification tolerance 1e-7 a
    /// 1e-6 test would reject orbits the integrator cannot reproduce more closely). Fixed-step
    /// RK4 maps a periodic orbit of its own discrete map onto itself to rounding, so it keeps
    /// [`PERIOD_TOL`].
    ///
    /// [`PERIOD_TOL`]: crate::period::PERIOD_TOL
    pub fn period_tol(&self) -> f64 {
        match *self {
            Method::Dopri { rtol, .. } => crate::period::PERIOD_TOL.max(PERIOD_TOL_PER_RTOL * rtol),
            Method::Rk4 { .. } => crate::period::PERIOD_TOL,
        }
    }

    /// The solver scheme for `model`.
    pub fn scheme(&self, model: &MeshModel) -> Scheme {
        match *self {
            Method::Dopri { rtol, atol } => Scheme::DormandPrince { rtol, atol },
            Method::Rk4 { steps_per_cycle } => Scheme::Rk4 {
                h: model.mesh_cycle_time() / steps_per_cycle.max(1) as f64,
            },
        }
    }
}

/// Simulation settings.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SimOptions {
    /// Integrator.
    pub method: Method,
    /// Excitation periods discarded as transient.
    pub transient_periods: u64,
    /// Excitation periods recorded.
    pub record_periods: u64,
    /// Keep the trajectory: uniform samples (`samples_per_cycle` per mesh cycle, from the dense
    /// output) plus both sides of every event.
    pub trajectory: bool,
    /// Trajectory samples per mesh cycle (at least: at low meshing frequency more, so that every
    /// natural period holds [`MIN_SAMPLES_PER_NATURAL_PERIOD`] samples).
    pub samples_per_cycle: u32,
    /// Keep the trajectory of the last this many recorded excitation periods only (all of them
    /// by default; the strobe, events and statistics always cover every recorded period).
    pub trajectory_periods: u64,
    /// Start time `tau_0` (the stroboscopic phase).
    pub tau0: f64,
    /// Largest period searched by period detection.
    pub max_period: usize,
    /// Memory of the start mode ([`HybridSystem::memory`]: the hysteresis factor of a
    /// dissipative contact law's impact in progress): that of the run this one continues
    /// ([`SimResult::final_memory`]), 0 for a fresh start (a start in contact is no impact).
    #[serde(skip_serializing_if = "is_zero", default)]
    pub start_memory: f64,
    /// Decision horizon (excitation periods, counted from the start of the run): a motion whose
    /// top Lyapunov exponent is positive is followed this long before it is called chaotic
    /// ([`crate::classify`]; default [`crate::classify::DECISION_PERIODS`]).
    pub decision_periods: u64,
    /// Work budget of one run's decision (right-hand-side evaluations in all, from the start of
    /// the run): a run whose motion is still not periodic when the budget is spent is `unsettled`,
    /// never chaotic (default [`crate::classify::DECISION_BUDGET`]).
    pub decision_budget: u64,
    /// Resolution of a decision's *follow* (the transients of the persistence blocks, which
    /// record nothing: [`crate::classify::follow_method`]): fixed-step RK4 steps per natural
    /// period (`2 pi` of dimensionless time); 0 follows with [`SimOptions::method`] itself.
    /// Default [`crate::classify::FOLLOW_STEPS`].
    #[serde(default = "default_follow_steps")]
    pub follow_steps: u32,
    /// Record the stroboscopic points only (no statistics, forces, events or mesh-cycle strobe;
    /// `x_range` from the points): the cheap record of a decision's persistence blocks, whose only
    /// question is whether a period has appeared ([`crate::classify`]). Not an option of the
    /// commands.
    #[serde(skip)]
    pub strobe_only: bool,
}

fn default_follow_steps() -> u32 {
    crate::classify::FOLLOW_STEPS
}

fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

impl Default for SimOptions {
    fn default() -> Self {
        SimOptions {
            method: Method::default(),
            transient_periods: 300,
            record_periods: 100,
            trajectory: false,
            samples_per_cycle: 128,
            trajectory_periods: u64::MAX,
            tau0: 0.0,
            max_period: 32,
            start_memory: 0.0,
            decision_periods: crate::classify::DECISION_PERIODS,
            decision_budget: crate::classify::DECISION_BUDGET,
            follow_steps: crate::classify::FOLLOW_STEPS,
            strobe_only: false,
        }
    }
}

/// One trajectory sample.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct TrajectoryPoint {
    /// Dimensionless time.
    pub tau: f64,
    /// Displacement.
    pub x: f64,
    /// Velocity.
    pub v: f64,
    /// Dynamic mesh force `F_m`.
    pub mesh_force: f64,
    /// Contact state code (drive 1, separated 0, back -1, stuck -2).
    pub state: i8,
}

/// A located event.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct EventRecord {
    /// Time.
    pub tau: f64,
    /// Position in the excitation period, in mesh cycles.
    pub cycle_position: f64,
    /// Kind.
    pub kind: EventKind,
    /// Displacement at the event (before any reset).
    pub x: f64,
    /// Velocity before the event.
    pub v_before: f64,
    /// Velocity after the event.
    pub v_after: f64,
    /// Peak impact force (impacts only, else 0).
    pub peak_force: f64,
}

/// Section levels of docs/model.md §5.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, PartialOrd, Ord, Hash)]
#[serde(rename_all = "snake_case")]
pub enum Level {
    /// `x = D_s`, upward.
    DsUp,
    /// `x = -D_s`, downward.
    DsDown,
    /// `x = D_d`, upward.
    DdUp,
    /// `x = -D_d`, downward.
    DdDown,
}

impl Level {
    /// All four, in label order `p, q, r, s`.
    pub const ALL: [Level; 4] = [Level::DsUp, Level::DsDown, Level::DdUp, Level::DdDown];
    /// Short name used on the command line and in CSV (`ds_up`, ...).
    pub fn name(self) -> &'static str {
        match self {
            Level::DsUp => "ds_up",
            Level::DsDown => "ds_down",
            Level::DdUp => "dd_up",
            Level::DdDown => "dd_down",
        }
    }
}

/// A section crossing: the state where `x` crosses a level in its direction.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Crossing {
    /// Level crossed.
    pub level: Level,
    /// Time.
    pub tau: f64,
    /// Displacement (the level).
    pub x: f64,
    /// Velocity.
    pub v: f64,
}

/// Everything recorded over the recorded periods.
#[derive(Clone, Debug, Default, Serialize)]
pub struct SimResult {
    /// Stroboscopic points `(tau, x, v)`, one per recorded excitation period (end of period).
    pub strobe: Vec<[f64; 3]>,
    /// Trajectory (if requested).
    pub trajectory: Vec<TrajectoryPoint>,
    /// Events.
    pub events: Vec<EventRecord>,
    /// Section crossings.
    pub crossings: Vec<Crossing>,
    /// States `(x, v)` at the end of every mesh cycle of the record, when the excitation period
    /// spans several mesh cycles (tooth breakage); empty otherwise.
    pub mesh_strobe: Vec<[f64; 2]>,
    /// Crossing counts `[p, q, r, s]` per recorded excitation period.
    pub counts_per_period: Vec<[u32; 4]>,
    /// Largest impact force in each recorded excitation period (0 if none).
    pub impact_force_per_period: Vec<f64>,
    /// Time in drive contact, separated, and back contact (stuck included).
    pub durations: [f64; 3],
    /// Maximum mesh force.
    pub max_force: f64,
    /// Minimum mesh force (most negative = back-side load).
    pub min_force: f64,
    /// Number of back-side impacts.
    pub impacts: u64,
    /// Time integrals of `x`, `x^2`, `F_m`, `F_m^2` over the recorded periods.
    pub integrals: [f64; 4],
    /// Smallest and largest `x`.
    pub x_range: (f64, f64),
    /// Final time and state (for continuation).
    pub final_state: (f64, [f64; 2]),
    /// Memory of the final mode (the hysteresis factor of an impact in progress at the end, 0
    /// otherwise): a continuation starts with it ([`SimOptions::start_memory`]).
    pub final_memory: f64,
    /// Solver work counters.
    pub steps: u64,
    /// Right-hand-side evaluations.
    pub rhs_evals: u64,
}

/// Response amplitudes over the recorded periods (for frequency-response curves).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, serde::Deserialize)]
pub struct Amplitudes {
    /// Mean of `x`.
    pub mean_x: f64,
    /// RMS of `x - mean(x)` (the alternating part of the dynamic transmission error).
    pub rms_x: f64,
    /// Peak-to-peak of `x`.
    pub p2p_x: f64,
    /// Mean mesh force.
    pub mean_force: f64,
    /// RMS of `F_m - mean(F_m)`.
    pub rms_force: f64,
    /// Peak-to-peak of `F_m`.
    pub p2p_force: f64,
}

impl SimResult {
    /// Means, RMS and peak-to-peak values over the recorded periods.
    pub fn amplitudes(&self) -> Amplitudes {
        let total: f64 = self.durations.iter().sum();
        let t = if total > 0.0 { total } else { 1.0 };
        let mx = self.integrals[0] / t;
        let mf = self.integrals[2] / t;
        Amplitudes {
            mean_x: mx,
            rms_x: (self.integrals[1] / t - mx * mx).max(0.0).sqrt(),
            p2p_x: self.x_range.1 - self.x_range.0,
            mean_force: mf,
            rms_force: (self.integrals[3] / t - mf * mf).max(0.0).sqrt(),
            p2p_force: self.max_force - self.min_force,
        }
    }
}

/// Motion summary (docs/model.md §5).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Summary {
    /// Minimal period in excitation periods (0 = not periodic).
    pub period: usize,
    /// Minimal period in mesh cycles of the mesh-cycle strobe, when the excitation period spans
    /// several mesh cycles (tooth breakage: one excitation period is one pinion revolution).
    pub mesh_period: Option<usize>,
    /// The decided class of the motion ([`crate::classify`]); [`summarize`] alone decides only
    /// "periodic" and otherwise says `unsettled`.
    pub motion: Motion,
    /// Label `n-p-q-r-s` (`n-p-q` when `D_s = D_d`) of a periodic motion; otherwise the class
    /// word alone (`chaotic`, `unsettled`, ...: a label carries no measured number, so that runs
    /// group by it; the crossing rates are [`Summary::rates`]).
    pub label: String,
    /// Counts `p, q, r, s` over one motion period; if `n = 0` (not periodic) their totals over the
    /// recorded periods.
    pub counts: [u32; 4],
    /// Crossings per excitation period of `x = D_s` upward, `x = -D_s` downward, `x = D_d`
    /// upward and `x = -D_d` downward (`p, q, r, s` per period: the counts over one motion period
    /// divided by its length, or the totals over the record divided by the recorded periods).
    #[serde(default)]
    pub rates: [f64; 4],
    /// Periodic without back-side contact or impact.
    pub healthy: bool,
    /// Dynamic instability proportion.
    pub p_id: f64,
    /// Maximum mesh force.
    pub max_force: f64,
    /// Minimum mesh force.
    pub min_force: f64,
    /// Number of back-side impacts over the recorded periods.
    pub impacts: u64,
    /// Largest impact force over the recorded periods.
    pub max_impact_force: f64,
    /// Excitation periods the motion was followed in all (transient, including the decision's
    /// extensions, plus the record); the exponent windows of the decision are not counted.
    pub periods_integrated: u64,
    /// The evidence that decided [`Summary::motion`] ([`crate::classify`]).
    pub decided_by: DecidedBy,
}

impl Summary {
    /// Sets the decided motion class (a non-periodic one) and rewrites the label's class word.
    pub fn set_motion(&mut self, motion: Motion) {
        if !self.motion.is_periodic() && !motion.is_periodic() {
            self.label = motion.word().to_string();
        }
        self.motion = motion;
    }

    /// The decision for people ([`Motion::describe`]), saying so when the work budget ended it.
    pub fn describe(&self) -> String {
        match (&self.motion, self.decided_by) {
            (Motion::Unsettled { tle, stderr }, DecidedBy::Budget) => format!(
                "unsettled: the work budget (decision_budget) ran out after {} periods, before a period appeared or the decision horizon (decision_periods) was reached; TLE {}",
                self.periods_integrated,
                match (tle, stderr) {
                    (Some(t), Some(s)) => format!("{t:.4} ± {s:.4}"),
                    _ => "not computed".into(),
                }
            ),
            (m, _) => m.describe(),
        }
    }

    /// `healthy`, or why not: `non-healthy (back-side contact)` / `non-healthy (not periodic)`.
    /// The seeds' word for non-healthy motions is "unstable"; it does not mean dynamically
    /// unstable (docs/analyses.md).
    pub fn health_text(&self) -> &'static str {
        health_text(self.healthy, self.period > 0)
    }
}

/// See [`Summary::health_text`].
pub fn health_text(healthy: bool, periodic: bool) -> &'static str {
    if healthy {
        "healthy"
    } else if periodic {
        "non-healthy (back-side contact)"
    } else {
        "non-healthy (not periodic)"
    }
}

/// Whether `x` crosses the section level `lv` on a step from `x0` to `x1` in the level's
/// direction: upward (`up`) `x0 <= lv < x1`, downward `x0 >= lv > x1` (the counting rule of
/// docs/analyses.md, for the scalar recorder and the lanes' copy of its step). Plain boolean
/// operators, so that a loop over lanes vectorises.
#[inline(always)]
pub(crate) fn crosses_level(up: bool, x0: f64, x1: f64, lv: f64) -> bool {
    if up {
        (x0 <= lv) & (x1 > lv)
    } else {
        (x0 >= lv) & (x1 < lv)
    }
}

/// Whether the middle one of three equally spaced samples is strictly extreme (a flat, clamped
/// run must not be extrapolated). Plain boolean operators, so that a loop over lanes vectorises.
#[inline(always)]
pub(crate) fn extreme_middle(a: f64, b: f64, c: f64) -> bool {
    (a - 2.0 * b + c != 0.0) & (((b > a) & (b > c)) | ((b < a) & (b < c)))
}

/// Extremum of the parabola through three equally spaced samples whose middle one is extreme.
#[inline]
pub(crate) fn parabola_peak(a: f64, b: f64, c: f64) -> Option<f64> {
    if extreme_middle(a, b, c) {
        let curv = a - 2.0 * b + c;
        Some(b - (c - a) * (c - a) / (8.0 * curv))
    } else {
        None
    }
}

pub(crate) struct Recorder<'a> {
    pub(crate) model: &'a MeshModel,
    pub(crate) res: SimResult,
    pub(crate) keep_traj: bool,
    /// Recorded periods completed, and the first one whose trajectory is kept.
    pub(crate) period: u64,
    pub(crate) traj_from: u64,
    /// Mesh force at the end of the previous step (time, value, mode), reused at the next start.
    pub(crate) last_end: Option<(f64, f64, MeshMode)>,
    pub(crate) sample_dt: f64,
    pub(crate) next_sample: u64,
    pub(crate) sample_origin: f64,
    pub(crate) levels: [f64; 4],
    pub(crate) count_levels: [bool; 4],
    pub(crate) counts: [u32; 4],
    pub(crate) impact_max: f64,
    /// Mesh-cycle strobe (only when an excitation period spans several mesh cycles).
    pub(crate) mesh_on: bool,
    pub(crate) mesh_dt: f64,
    pub(crate) next_mesh: u64,
    /// The stroboscopic points only ([`SimOptions::strobe_only`]).
    pub(crate) strobe_only: bool,
}

/// Fewest trajectory samples per natural period `2 pi / sqrt(k_peak)` of the stiffest mesh state
/// (dimensionless time): a curve drawn through the samples stays smooth where a mesh cycle spans
/// many natural oscillations (the broken pair at `omega` = 0.1: ten per mesh cycle, which 24
/// samples per cycle drew as a star of straight lines).
pub const MIN_SAMPLES_PER_NATURAL_PERIOD: u32 = 32;

/// Time between trajectory samples: `samples_per_cycle` per mesh cycle, or finer when the
/// natural period asks for it ([`MIN_SAMPLES_PER_NATURAL_PERIOD`]; only when the trajectory is
/// kept, so that other runs pay nothing for the stiffness scan).
fn sample_step(model: &MeshModel, samples_per_cycle: u32, keep_traj: bool) -> f64 {
    let per_cycle = model.mesh_cycle_time() / samples_per_cycle.max(1) as f64;
    if !keep_traj {
        return per_cycle;
    }
    let k = model.peak_stiffness();
    let natural = 2.0 * std::f64::consts::PI / k.max(1.0).sqrt();
    if natural.is_finite() {
        per_cycle.min(natural / MIN_SAMPLES_PER_NATURAL_PERIOD as f64)
    } else {
        per_cycle
    }
}

impl<'a> Recorder<'a> {
    pub(crate) fn new(
        model: &'a MeshModel,
        keep_traj: bool,
        samples_per_cycle: u32,
        t_start: f64,
        traj_from: u64,
    ) -> Self {
        let (dd, ds) = model.backlash_levels();
        let distinct = dd != ds;
        Recorder {
            model,
            res: SimResult {
                max_force: f64::NEG_INFINITY,
                min_force: f64::INFINITY,
                x_range: (f64::INFINITY, f64::NEG_INFINITY),
                ..Default::default()
            },
            keep_traj,
            period: 0,
            traj_from,
            last_end: None,
            sample_dt: sample_step(model, samples_per_cycle, keep_traj),
            next_sample: 0,
            sample_origin: t_start,
            levels: [ds, -ds, dd, -dd],
            count_levels: [true, true, distinct, distinct],
            counts: [0; 4],
            impact_max: 0.0,
            mesh_on: model.cycles_per_period() > 1,
            mesh_dt: model.mesh_cycle_time(),
            next_mesh: 1,
            strobe_only: false,
        }
    }

    /// The recorder of the stroboscopic points only ([`SimOptions::strobe_only`]).
    pub(crate) fn strobe_only(mut self, on: bool) -> Self {
        self.strobe_only = on;
        self
    }

    /// The finished record: `x_range` of a record of the stroboscopic points only taken from
    /// them, and the force extremes of a record without a force set to zero.
    pub(crate) fn finish(mut self) -> SimResult {
        if self.strobe_only {
            self.res.x_range = self
                .res
                .strobe
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                    (lo.min(p[1]), hi.max(p[1]))
                });
        }
        let mut res = self.res;
        if res.max_force == f64::NEG_INFINITY {
            res.max_force = 0.0;
            res.min_force = 0.0;
        }
        res
    }

    fn force(&mut self, t: f64, y: &[f64; 2], mode: &MeshMode) -> f64 {
        let f = self.model.mesh_force(t, y, mode);
        self.res.max_force = self.res.max_force.max(f);
        self.res.min_force = self.res.min_force.min(f);
        f
    }

    #[inline]
    fn traj_on(&self) -> bool {
        self.keep_traj && self.period >= self.traj_from
    }

    fn push_traj(&mut self, tau: f64, y: &[f64; 2], f: f64, mode: &MeshMode) {
        if self.traj_on() {
            self.res.trajectory.push(TrajectoryPoint {
                tau,
                x: y[0],
                v: y[1],
                mesh_force: f,
                state: mode.contact.code(),
            });
        }
    }
}

impl<'m> Observer<&'m MeshModel, 2> for Recorder<'_> {
    fn on_step(
        &mut self,
        sys: &&'m MeshModel,
        step: &Step<2>,
        before: &MeshMode,
        stop: Stop,
        after: &MeshMode,
        y_after: &[f64; 2],
    ) {
        if self.strobe_only {
            return;
        }
        let (t0, t1) = (step.t0, step.t1);
        let dt = t1 - t0;
        let slot = match before.contact {
            ContactState::Drive => 0,
            ContactState::Separated => 1,
            ContactState::Back | ContactState::Stuck => 2,
        };
        self.res.durations[slot] += dt;
        // time averages and extrema from interpolant samples: Simpson's rule on three for short
        // steps (fixed-step RK4), Boole's rule on five for long adaptive steps; a parabola through
        // the samples around an interior extremum refines the peak force.
        let y1 = step.y1();
        let long = dt > self.sample_dt * 2.0;
        let (ths, w): (&[f64], &[f64]) = if long {
            (
                &[0.0, 0.25, 0.5, 0.75, 1.0],
                &[
                    7.0 / 90.0,
                    32.0 / 90.0,
                    12.0 / 90.0,
                    32.0 / 90.0,
                    7.0 / 90.0,
                ],
            )
        } else {
            (&[0.0, 0.5, 1.0], &[1.0 / 6.0, 4.0 / 6.0, 1.0 / 6.0])
        };
        let contact = matches!(before.contact, ContactState::Drive | ContactState::Back);
        let mut xs = [0.0; 5];
        let mut fs = [0.0; 5];
        for (k, &th) in ths.iter().enumerate() {
            let y = if th == 1.0 { y1 } else { step.at_theta(th) };
            xs[k] = y[0];
            if contact {
                // the start of a step continues the end of the previous one (same mode, no reset)
                fs[k] = match self.last_end {
                    Some((t, f, m)) if k == 0 && t == t0 && m == *before => f,
                    _ => self.model.mesh_force(t0 + th * dt, &y, before),
                };
            }
        }
        self.last_end = if stop == Stop::Step {
            Some((t1, fs[ths.len() - 1], *before))
        } else {
            None
        };
        let n = ths.len();
        for k in 0..n {
            self.res.x_range = (self.res.x_range.0.min(xs[k]), self.res.x_range.1.max(xs[k]));
            self.res.max_force = self.res.max_force.max(fs[k]);
            self.res.min_force = self.res.min_force.min(fs[k]);
            self.res.integrals[0] += w[k] * dt * xs[k];
            self.res.integrals[1] += w[k] * dt * xs[k] * xs[k];
            self.res.integrals[2] += w[k] * dt * fs[k];
            self.res.integrals[3] += w[k] * dt * fs[k] * fs[k];
        }
        for k in 1..n - 1 {
            if let Some(p) = parabola_peak(xs[k - 1], xs[k], xs[k + 1]) {
                self.res.x_range = (self.res.x_range.0.min(p), self.res.x_range.1.max(p));
            }
            if contact {
                if let Some(p) = parabola_peak(fs[k - 1], fs[k], fs[k + 1]) {
                    self.res.max_force = self.res.max_force.max(p);
                    self.res.min_force = self.res.min_force.min(p);
                }
            }
        }
        if self.traj_on() {
            // uniform samples from the dense output, times computed from an integer index
            loop {
                let ts = self.sample_origin + self.next_sample as f64 * self.sample_dt;
                if ts > t1 {
                    break;
                }
                if ts >= t0 {
                    let y = step.interpolate(ts);
                    let f = self.model.mesh_force(ts, &y, before);
                    self.push_traj(ts, &y, f, before);
                }
                self.next_sample += 1;
            }
        }
        if self.mesh_on {
            // the state at every mesh cycle, from the dense output (times from an integer index)
            loop {
                let tm = self.sample_origin + self.next_mesh as f64 * self.mesh_dt;
                if tm > t1 {
                    break;
                }
                if tm >= t0 {
                    let y = step.interpolate(tm);
                    self.res.mesh_strobe.push([y[0], y[1]]);
                }
                self.next_mesh += 1;
            }
        }
        // level crossings on this step (x is continuous within it)
        let (x0, x1) = (step.y0()[0], y1[0]);
        for (i, &lv) in self.levels.iter().enumerate() {
            if !self.count_levels[i] {
                continue;
            }
            let up = i % 2 == 0;
            if crosses_level(up, x0, x1, lv) {
                self.counts[i] += 1;
                // locate on the interpolant for the section point
                let br = geardyn_solvers::root::illinois(
                    |t| step.interpolate(t)[0] - lv,
                    t0,
                    x0 - lv,
                    t1,
                    x1 - lv,
                    1e-13 * t1.abs().max(1.0),
                    |g| if up { g > 0.0 } else { g < 0.0 },
                );
                let y = step.interpolate(br.b);
                self.res.crossings.push(Crossing {
                    level: Level::ALL[i],
                    tau: br.b,
                    x: lv,
                    v: y[1],
                });
            }
        }
        if let Stop::Event { index } = stop {
            let kind = sys.event_kind(before, after, index);
            let peak = if kind == EventKind::Impact {
                self.res.impacts += 1;
                let p = sys.impact_peak_force(y1[1]);
                self.impact_max = self.impact_max.max(p);
                p
            } else {
                0.0
            };
            let u = sys.cycle_position(t1);
            self.res.events.push(EventRecord {
                tau: t1,
                cycle_position: u,
                kind,
                x: y1[0],
                v_before: y1[1],
                v_after: y_after[1],
                peak_force: peak,
            });
            let fb = self.model.mesh_force(t1, &y1, before);
            self.push_traj(t1, &y1, fb, before);
            let fa = self.force(t1, y_after, after);
            self.push_traj(t1, y_after, fa, after);
        } else if before.contact != after.contact {
            // a contact change without a state event is a breakpoint (it may coincide with the
            // stroboscopic instant, reported as Tstop)
            // A backlash jump (time-varying D) that closes the gap is a contact entry: relative
            // to the moving contact surface, x crossed it. It counts as a crossing of the level
            // it enters at (docs/analyses.md, "Counting rule").
            let entry = match (before.contact, after.contact) {
                (ContactState::Separated, ContactState::Drive) => Some(0),
                (ContactState::Separated, ContactState::Back | ContactState::Stuck) => Some(1),
                _ => None,
            };
            if let Some(side) = entry {
                // only a decrease of the backlash (D_s -> D_d) closes a gap: the entry is at D_d
                let i = if self.count_levels[2] { side + 2 } else { side };
                self.counts[i] += 1;
                self.res.crossings.push(Crossing {
                    level: Level::ALL[i],
                    tau: t1,
                    x: y1[0],
                    v: y1[1],
                });
            }
            let fa = self.force(t1, y_after, after);
            self.push_traj(t1, y_after, fa, after);
        }
    }

    fn on_strobe(&mut self, t: f64, y: &[f64; 2]) {
        self.res.strobe.push([t, y[0], y[1]]);
        self.res.counts_per_period.push(self.counts);
        self.counts = [0; 4];
        self.res.impact_force_per_period.push(self.impact_max);
        self.impact_max = 0.0;
        self.period += 1;
        if self.period == self.traj_from {
            // the kept window starts here: uniform samples from this instant
            self.sample_origin = t;
            self.next_sample = 0;
        }
    }
}

/// Failure of a simulation.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SimError {
    /// The integrator failed.
    #[error(transparent)]
    Solver(#[from] SolverError),
}

/// Integrates `model` from `y0` at `opts.tau0`: `transient_periods` discarded, `record_periods`
/// recorded.
///
/// ```
/// use geardyn_analysis::simulate::{simulate, summarize, SimOptions};
/// let model = geardyn_model::MeshModel::new(&geardyn_model::presets::classic()).unwrap();
/// let opts = SimOptions { transient_periods: 200, record_periods: 20, ..Default::default() };
/// let res = simulate(&model, [0.0, 0.0], &opts).unwrap();
/// assert_eq!(summarize(&model, &res, &opts).period, 1);
/// ```
pub fn simulate(model: &MeshModel, y0: [f64; 2], opts: &SimOptions) -> Result<SimResult, SimError> {
    let mut integ = Integrator::new(model, opts.method.scheme(model), opts.tau0, y0)?
        .with_memory(opts.start_memory);
    let period = model.excitation_period();
    run_periods(&mut integ, period, opts.transient_periods, &mut Discard)?;
    let traj_from = opts.record_periods.saturating_sub(opts.trajectory_periods);
    let mut rec = Recorder::new(
        model,
        opts.trajectory,
        opts.samples_per_cycle,
        integ.t(),
        traj_from,
    )
    .strobe_only(opts.strobe_only);
    run_periods(&mut integ, period, opts.record_periods, &mut rec)?;
    let mut res = rec.finish();
    let st = integ.stats();
    res.steps = st.steps;
    res.rhs_evals = st.rhs_evals;
    res.final_state = (integ.t(), *integ.y());
    res.final_memory = model.memory(integ.mode());
    Ok(res)
}

fn lcm(a: usize, b: usize) -> usize {
    fn gcd(a: usize, b: usize) -> usize {
        if b == 0 {
            a
        } else {
            gcd(b, a % b)
        }
    }
    a / gcd(a, b) * b
}

/// Period, label, healthy flag and P_ID of a simulation.
pub fn summarize(model: &MeshModel, res: &SimResult, opts: &SimOptions) -> Summary {
    summarize_tol(model, res, opts, opts.method.period_tol())
}

/// As [`summarize`], with relative period-test tolerance `period_tol` (the classification uses a
/// looser one only for motions whose Lyapunov exponent shows them attracting:
/// `crate::classify`).
pub fn summarize_tol(
    model: &MeshModel,
    res: &SimResult,
    opts: &SimOptions,
    period_tol: f64,
) -> Summary {
    let pts: Vec<[f64; 2]> = res.strobe.iter().map(|p| [p[1], p[2]]).collect();
    let period = minimal_period_tol(&pts, opts.max_period, period_tol).unwrap_or(0);
    let cycles = model.cycles_per_period() as usize;
    // The excitation strobe is exact (integrator stops); the mesh-cycle strobe is interpolated.
    // The mesh period is the smallest divisor m of period*cycles at which the mesh strobe
    // repeats to ten times the period tolerance (the interpolant's accuracy), so the two clocks
    // never contradict each other.
    let mesh_period = if cycles > 1 && period > 0 {
        let whole = period * cycles;
        let pts = &res.mesh_strobe;
        let scale = 1.0
            + pts
                .iter()
                .flat_map(|p| p.iter())
                .fold(0.0f64, |m, v| m.max(v.abs()));
        // a hundred times the period tolerance: on the broken pair's 3-60-0 orbit (omega 1.2,
        // F 0.1-0.11) the interpolated strobe repeats after 6 cycles to 2e-6-9e-6 (other shifts:
        // 0.8), and ten times read 6, 60 or 120 cycles at neighbouring loads
        let tol = 100.0 * opts.method.period_tol() * scale;
        (1..=whole)
            .filter(|&m| whole.is_multiple_of(m))
            .find(|&m| {
                pts.len() >= 2 * m
                    && (m..pts.len()).all(|j| {
                        (pts[j][0] - pts[j - m][0]).abs() + (pts[j][1] - pts[j - m][1]).abs() <= tol
                    })
            })
            .or(Some(whole))
    } else {
        None
    };
    // The two clocks agree: a mesh strobe that repeats after m mesh cycles repeats the excitation
    // strobe after lcm(m, cycles) / cycles periods. When that is a proper divisor of the period
    // found, the excitation strobe test failed the shorter period on the integrator's noise
    // (many events per period, as on the breakage pair) and the shorter one is the period.
    let period = match mesh_period {
        Some(m) if period > 0 => {
            let p = lcm(m, cycles) / cycles;
            if p < period && period.is_multiple_of(p) {
                p
            } else {
                period
            }
        }
        _ => period,
    };
    summary_of_period(model, res, opts, period, mesh_period)
}

/// The summary of a record of the orbit of `period` excitation periods, known by other means
/// (shooting: [`crate::orbits`]): the record is read as that orbit (its last `period` periods
/// give the counts) whatever the period test would say of a record this short.
pub fn summarize_orbit(
    model: &MeshModel,
    res: &SimResult,
    opts: &SimOptions,
    period: usize,
) -> Summary {
    summary_of_period(model, res, opts, period, None)
}

/// The summary of a record whose period (0: none) is `period`.
fn summary_of_period(
    model: &MeshModel,
    res: &SimResult,
    opts: &SimOptions,
    period: usize,
    mesh_period: Option<usize>,
) -> Summary {
    let counts = if period > 0 && res.counts_per_period.len() >= period {
        let mut c = [0u32; 4];
        for row in &res.counts_per_period[res.counts_per_period.len() - period..] {
            for i in 0..4 {
                c[i] += row[i];
            }
        }
        c
    } else {
        // not periodic: totals over the record (the label gives them per period); rounded
        // per-period means would read 0 for a crossing every third period
        let mut c = [0u32; 4];
        for i in 0..4 {
            c[i] = res.counts_per_period.iter().map(|r| r[i]).sum();
        }
        c
    };
    let (dd, ds) = model.backlash_levels();
    let n_lv = if dd == ds { 2 } else { 4 };
    let label = if period > 0 {
        let parts: Vec<String> = counts[..n_lv].iter().map(|c| c.to_string()).collect();
        format!("{}-{}", period, parts.join("-"))
    } else {
        Motion::default().word().to_string()
    };
    let per = if period > 0 {
        period
    } else {
        res.counts_per_period.len().max(1)
    } as f64;
    let rates = counts.map(|c| f64::from(c) / per);
    let [t_drive, t_sep, t_back] = res.durations;
    let total = t_drive + t_sep + t_back;
    let any_back = t_back > 0.0 || res.impacts > 0 || counts[1] > 0 || counts[3] > 0;
    Summary {
        period,
        mesh_period,
        motion: if period > 0 {
            Motion::Periodic { period }
        } else {
            Motion::default()
        },
        label,
        counts,
        rates,
        healthy: period > 0 && !any_back,
        p_id: if total > 0.0 {
            (t_sep + t_back) / total
        } else {
            0.0
        },
        max_force: res.max_force,
        min_force: res.min_force,
        impacts: res.impacts,
        max_impact_force: res
            .impact_force_per_period
            .iter()
            .cloned()
            .fold(0.0, f64::max),
        periods_integrated: opts.transient_periods + res.strobe.len() as u64,
        decided_by: if period > 0 {
            DecidedBy::PeriodTest
        } else {
            DecidedBy::Undecided
        },
    }
}
