//! Lockstep ensemble RK4: `L` independent trajectories of one model family advanced together on
//! the fixed RK4 grid, in structure-of-arrays form, with events still located exactly.
//!
//! One trajectory is latency-bound (each RK4 stage waits for the previous one); the throughput of
//! the machine is only reached by advancing many independent trajectories at once, and every heavy
//! analysis (sweep values x initial states, basin cells) is such an ensemble.
//!
//! # How it works
//! * A model family implements [`Lockstep`], the batched counterpart of [`HybridSystem`]: its
//!   vector field over `L` lanes at a *step phase* (the index of a grid step within the strobe
//!   period, and the stage: start, middle or end of the step), and a guard check over the lanes.
//!   With a fixed number of steps per period every periodic coefficient takes the same values at
//!   the same phase in every period, so a model tabulates them once (phase tables); lanes only add
//!   their own constants (amplitudes, damping, step length).
//! * The RK4 stages of a lockstep step are written once, in [`rk4_lanes`]: a model supplies its
//!   field over lanes as a [`LaneKernel`] (per-step coefficients, then the field at the middle
//!   and the end of the step), any fixed dimension `N`; the default [`Lockstep::step`]
//!   ([`compose_step`]) runs it over [`Lockstep::rhs`], a model with a faster field (the gear
//!   pair's phase-table kernel) over its own kernel. Files: the engine (per-lane bookkeeping,
//!   scalar hand-over, strobe instants) in `engine`, the stages in `kernel`, the CPU dispatch in
//!   `dispatch`.
//! * All lanes sit at the same phase index `j`. A lane whose step may hold an event — a guard
//!   changes sign between the ends, or the rigorous interior bound (the one of
//!   [`HybridSystem::guard_lipschitz`]: the Hermite interpolant deviates from its chord by at most
//!   `0.25 (|r2| + |r3|)`) does not clear every surface — or whose mode the batched field does not
//!   cover, and every lane at a phase that holds a time breakpoint, is *finished by the scalar
//!   [`Integrator`](crate::Integrator)*: it resumes at the grid point ([`Integrator::resume`](crate::Integrator::resume)), takes its own steps
//!   (locating events, applying resets, landing on breakpoints, handling Zeno accumulations) up to
//!   the next grid point, and the lane rejoins the grid there. Modes, impacts, sticking and
//!   breakpoints therefore behave exactly as in the scalar integrator.
//! * Time is kept per lane exactly as the scalar integrator keeps it: grid points are
//!   `t_origin + k*h`, stroboscopic instants `t_segment + p*T` (merged with the grid point they
//!   coincide with), and each RK4 step has the length `t1 - t0` of those rounded times. A lane
//!   therefore follows the scalar RK4 path; the differences are that its periodic coefficients
//!   come from the phase tables instead of being evaluated at the rounded time (a few ulps),
//!   and that a model may take the same RK4 step with fewer operations (a tabulated affine map
//!   of a linear field), rounded differently.
//! * Work arrives from a [`LaneDriver`]: a lane is filled with a work item at a strobe instant
//!   (phase 0), runs whole strobe periods, and retires when its driver says so (a sweep value
//!   finished, a basin cell captured early); the freed lane takes the next item at once. The
//!   result of an item does not depend on the lane it ran in nor on its neighbours: per-lane
//!   arithmetic is the same in every lane and no fused multiply-add is used, so the output is the
//!   same for any chunking, thread count, and CPU dispatch path.
//! * [`run_lanes`] dispatches at run time to a copy of the engine compiled for AVX-512 (F, VL,
//!   DQ) or AVX2/FMA when the CPU has them (`is_x86_feature_detected!`), else to the baseline copy;
//!   stable Rust, no build flags (the AVX-512 copy needs Rust 1.89, `build.rs` leaves it out on
//!   older compilers). The copies run the same IEEE operations in the same order (no fused
//!   multiply-add, no fast-math), so their results are identical.
//!
//! The hot loop allocates nothing, takes no lock, and is generic (monomorphised), not dynamic.

mod dispatch;
mod engine;
mod kernel;

pub use dispatch::{dispatch_path, run_lanes, run_lanes_on, Dispatch};
pub use kernel::{combine, compose_step, fractions, rk4_lanes, stage_point, LaneKernel, CHUNK};

use crate::dense::Step;
use crate::hybrid::HybridSystem;
use crate::integrator::{SolverError, Stats, Stop};

/// Structure-of-arrays block: component `i` of lane `l` is `a[i][l]`.
pub type Soa<const N: usize, const L: usize> = [[f64; L]; N];

/// Where in a grid step a field is evaluated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// At the start `t0`.
    Start = 0,
    /// At the middle `t0 + h/2`.
    Mid = 1,
    /// At the end `t0 + h`.
    End = 2,
}

/// The batched counterpart of a [`HybridSystem`] family: its field and guard check over `L` lanes
/// at a step phase. All lanes of one batch share the phase tables (the lanes' systems differ only
/// in what [`Lockstep::Lanes`] carries).
pub trait Lockstep<const N: usize, const L: usize>: Sync {
    /// The scalar system of one lane (events, resets and breakpoints are its business).
    type Sys: HybridSystem<N>;
    /// Per-lane constants of the lanes' systems in their current modes (contact selectors,
    /// amplitudes, damping, ...), as a structure of arrays over the `L` lanes.
    type Lanes: Copy;
    /// Per-engine working storage of the batched field (e.g. tables that depend on a lane's own
    /// constants), created once per engine ([`Lockstep::new_work`]), updated by
    /// [`Lockstep::set_lane`] and read by [`Lockstep::step`]; `()` when a model needs none.
    type Work;
    /// Guards depend on the state components `0..GUARD_DIMS` only (the interior bound is taken
    /// over those).
    const GUARD_DIMS: usize = N;

    /// Grid steps per strobe period (the length of the phase tables).
    fn steps_per_period(&self) -> usize;
    /// Whether the step at phase `j` must be taken by the scalar integrator in every lane (it may
    /// hold a time breakpoint).
    fn scalar_phase(&self, j: usize) -> bool;
    /// The working storage of one engine.
    fn new_work(&self) -> Self::Work;
    /// Sets lane `l`'s constants to those of `sys` in `mode` on its grid of step `h`; `false`
    /// when the batched field does not cover that mode (the lane then steps with the scalar
    /// integrator until its mode is covered again).
    #[allow(clippy::too_many_arguments)]
    fn set_lane(
        &self,
        lanes: &mut Self::Lanes,
        work: &mut Self::Work,
        l: usize,
        sys: &Self::Sys,
        mode: &<Self::Sys as HybridSystem<N>>::Mode,
        h: f64,
    ) -> bool;
    /// Constants of idle lanes (values that keep the arithmetic finite).
    fn idle_lanes(&self) -> Self::Lanes;
    /// Sets lane `l` idle.
    fn set_idle(&self, lanes: &mut Self::Lanes, l: usize);
    /// Field of every lane at `stage` of step `j`: `dy = f(y)`. `at` gives each lane's time there,
    /// rounded as the scalar integrator rounds it, and its exact grid position (a system whose
    /// coefficients follow the rounded time may correct its tables by the difference).
    fn rhs(
        &self,
        j: usize,
        stage: Stage,
        at: &At<L>,
        lanes: &Self::Lanes,
        y: &Soa<N, L>,
        dy: &mut Soa<N, L>,
    );
    /// One RK4 grid step `s` of every lane (from `(s.y0, s.f0)` at `s.t0` to `s.t1`, see
    /// [`StepStart`]): the end states `y1`, the end fields `f1`, and the lanes whose step provably
    /// holds no event ([`Lockstep::clear`] with the interior bound over the Hermite interpolant)
    /// and stayed finite. The default composes [`Lockstep::rhs`] and [`Lockstep::clear`] exactly
    /// as the scalar RK4 step does; a model may fuse them (same arithmetic, fewer trips through
    /// memory).
    #[inline(always)]
    fn step(
        &self,
        s: &StepStart<'_, N, L>,
        lanes: &Self::Lanes,
        _work: &Self::Work,
        y1: &mut Soa<N, L>,
        f1: &mut Soa<N, L>,
    ) -> u32 {
        compose_step(self, s, lanes, y1, f1)
    }

    /// Bit `l` set when lane `l`'s step from `y0` to `y1` provably holds no event: no armed guard
    /// changes sign between the ends, and every armed guard stays farther from zero at both ends
    /// than it can move within the step given the interpolant deviation `dev[l]` (the
    /// rigorous bound of the scalar integrator: `|g(y) - g(y')| <= L_g max_i |y_i - y'_i|` and
    /// the margin `0.25 L_g dev`).
    fn clear(
        &self,
        j: usize,
        lanes: &Self::Lanes,
        y0: &Soa<N, L>,
        y1: &Soa<N, L>,
        dev: &[f64; L],
    ) -> u32;
}

/// Where each lane evaluates a field: its time (as the scalar integrator computes it: the step
/// start `t`, `t + h/2`, `t + h` with `h = t1 - t`) and its position on its grid in steps from the
/// grid origin (`k`, `k + 1/2`, `k + 1`: exact).
#[derive(Clone, Copy, Debug)]
pub struct At<const L: usize> {
    /// Times.
    pub t: [f64; L],
    /// Grid positions (steps from the origin of the lane's grid).
    pub grid: [f64; L],
}

/// Where one grid step of every lane starts, as the lanes' step functions take it
/// ([`Lockstep::step`], [`rk4_lanes`], [`compose_step`], a model's kernels): the phase index, each
/// lane's start and end times (rounded as the scalar integrator rounds them), the grid position of
/// the start (steps from the lane's grid origin; the end is one more), and the start states with
/// their fields (`f0` carried from the previous step, as the scalar integrator carries it).
#[derive(Clone, Copy)]
pub struct StepStart<'a, const N: usize, const L: usize> {
    /// Phase index of the step.
    pub j: usize,
    /// Start times.
    pub t0: &'a [f64; L],
    /// End times.
    pub t1: &'a [f64; L],
    /// Grid position of the start.
    pub grid: &'a [f64; L],
    /// States at the start.
    pub y0: &'a Soa<N, L>,
    /// Derivatives at the start.
    pub f0: &'a Soa<N, L>,
}

impl<'a, const N: usize, const L: usize> StepStart<'a, N, L> {
    /// The same step from other start states `(y0, f0)` (of another dimension: a part of the
    /// state, say).
    #[inline(always)]
    pub fn with_states<'b, const M: usize>(
        &self,
        y0: &'b Soa<M, L>,
        f0: &'b Soa<M, L>,
    ) -> StepStart<'b, M, L>
    where
        'a: 'b,
    {
        StepStart {
            j: self.j,
            t0: self.t0,
            t1: self.t1,
            grid: self.grid,
            y0,
            f0,
        }
    }
}

/// One lockstep step of the lanes in `mask`, as seen by a [`LaneDriver`].
pub struct LaneStep<'a, Ln, const N: usize, const L: usize> {
    /// Phase index of the step.
    pub j: usize,
    /// Lanes that took this step in lockstep (bit `l`).
    pub mask: u32,
    /// Lane constants.
    pub lanes: &'a Ln,
    /// Grid position of the start (steps from the lane's grid origin; the end is one more).
    pub grid: &'a [f64; L],
    /// Start times.
    pub t0: &'a [f64; L],
    /// End times.
    pub t1: &'a [f64; L],
    /// States at the start.
    pub y0: &'a Soa<N, L>,
    /// Derivatives at the start.
    pub f0: &'a Soa<N, L>,
    /// States at the end.
    pub y1: &'a Soa<N, L>,
    /// Derivatives at the end.
    pub f1: &'a Soa<N, L>,
}

impl<Ln, const N: usize, const L: usize> LaneStep<'_, Ln, N, L> {
    /// The step of lane `l` with its cubic Hermite interpolant, exactly as the scalar RK4 step
    /// would report it.
    pub fn step(&self, l: usize) -> Step<N> {
        let mut y0 = [0.0; N];
        let mut y1 = [0.0; N];
        let mut f0 = [0.0; N];
        let mut f1 = [0.0; N];
        for i in 0..N {
            y0[i] = self.y0[i][l];
            y1[i] = self.y1[i][l];
            f0[i] = self.f0[i][l];
            f1[i] = self.f1[i][l];
        }
        Step::hermite(self.t0[l], self.t1[l], &y0, &y1, &f0, &f1)
    }
}

/// A work item for a lane: the system, the start, and the grid.
pub struct Start<'s, S, const N: usize> {
    /// The lane's system.
    pub sys: &'s S,
    /// Start time (the grid origin).
    pub t0: f64,
    /// Initial state (projected by [`HybridSystem::initial_mode`]).
    pub y0: [f64; N],
    /// Memory parameter of the initial mode ([`HybridSystem::memory`]): that of the run this
    /// one continues, 0 for a fresh start.
    pub memory: f64,
    /// RK4 grid step (`period / steps_per_period`).
    pub h: f64,
    /// Strobe period.
    pub period: f64,
}

/// What a lane does after a stroboscopic instant.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Next {
    /// Integrate another period.
    Continue,
    /// Integrate another period; strobe instants count from now (a new `run_periods` call).
    Segment,
    /// Start afresh from the current time and state: a new integrator (grid origin here, mode from
    /// [`HybridSystem::initial_mode`] with the current mode's memory), strobe instants counted
    /// from now.
    Restart,
    /// The item is finished: the lane retires.
    Finish,
}

/// How an item ended.
#[derive(Clone, Debug, PartialEq)]
pub enum End<const N: usize> {
    /// Finished at a strobe instant ([`Next::Finish`]) or terminated by the system.
    Done {
        /// Final time.
        t: f64,
        /// Final state.
        y: [f64; N],
        /// Memory parameter of the final mode ([`HybridSystem::memory`]).
        memory: f64,
        /// Work: steps (lockstep and scalar) and right-hand-side evaluations.
        stats: Stats,
    },
    /// The integration failed.
    Failed(SolverError),
}

/// Supplies work items to the lanes and observes them (the ensemble's counterpart of an
/// observer plus a work queue). Lane indices are `0..L` within one engine.
pub trait LaneDriver<'s, B: Lockstep<N, L>, const N: usize, const L: usize> {
    /// The next work item for lane `lane`, or `None` when the queue is empty.
    fn next_item(&mut self, lane: usize) -> Option<Start<'s, B::Sys, N>>;
    /// A lockstep step of the lanes in `st.mask`. Returns the lanes whose step the driver wants
    /// reported through [`LaneDriver::on_step`] as well (an observer's rare case: a level
    /// crossing, say), as the scalar integrator would report it.
    fn on_lockstep(&mut self, _batch: &B, _st: &LaneStep<'_, B::Lanes, N, L>) -> u32 {
        0
    }
    /// A scalar step of lane `lane` (as [`crate::Integrator::step`] reports it; a grid point
    /// inside a strobe period is reported as [`Stop::Step`]).
    #[allow(clippy::too_many_arguments)]
    fn on_step(
        &mut self,
        _lane: usize,
        _sys: &B::Sys,
        _step: &Step<N>,
        _before: &<B::Sys as HybridSystem<N>>::Mode,
        _stop: Stop,
        _after: &<B::Sys as HybridSystem<N>>::Mode,
        _y_after: &[f64; N],
    ) {
    }
    /// The stroboscopic instant `t` of lane `lane`; says what the lane does next.
    fn on_strobe(&mut self, lane: usize, t: f64, y: &[f64; N]) -> Next;
    /// As [`LaneDriver::on_strobe`], and the driver may replace the lane's state there, keeping
    /// its mode (renormalising the tangent part of an augmented state, as
    /// [`crate::Integrator::set_state`] does for one integrator). Default: `on_strobe`.
    fn on_strobe_set(&mut self, lane: usize, t: f64, y: &mut [f64; N]) -> Next {
        self.on_strobe(lane, t, y)
    }
    /// The item of lane `lane` ended.
    fn on_end(&mut self, lane: usize, end: End<N>);
}
