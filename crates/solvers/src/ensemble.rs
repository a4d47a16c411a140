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
//! * All lanes sit at the same phase index `j`. A lane whose step may hold an event — a guard
//!   changes sign between the ends, or the rigorous interior bound (the one of
//!   [`HybridSystem::guard_lipschitz`]: the Hermite interpolant deviates from its chord by at most
//!   `0.25 (|r2| + |r3|)`) does not clear every surface — or whose mode the batched field does not
//!   cover, and every lane at a phase that holds a time breakpoint, is *finished by the scalar
//!   [`Integrator`]*: it resumes at the grid point ([`Integrator::resume`]), takes its own steps
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

use crate::dense::Step;
use crate::hybrid::HybridSystem;
use crate::integrator::{Integrator, Scheme, SolverError, Stats, Stop};

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
    /// One RK4 grid step of every lane from `(y0, f0)` at `t0` to `t1` (`f0` the field at the
    /// start, as the scalar integrator carries it from the previous step): the end states `y1`,
    /// the end fields `f1`, and the lanes whose step provably holds no event ([`Lockstep::clear`]
    /// with the interior bound over the Hermite interpolant) and stayed finite. The default
    /// composes [`Lockstep::rhs`] and [`Lockstep::clear`] exactly as the scalar RK4 step does; a
    /// model may fuse them (same arithmetic, fewer trips through memory).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn step(
        &self,
        j: usize,
        t0: &[f64; L],
        t1: &[f64; L],
        grid: &[f64; L],
        lanes: &Self::Lanes,
        _work: &Self::Work,
        y0: &Soa<N, L>,
        f0: &Soa<N, L>,
        y1: &mut Soa<N, L>,
        f1: &mut Soa<N, L>,
    ) -> u32 {
        compose_step(self, j, t0, t1, grid, lanes, y0, f0, y1, f1)
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

/// The RK4 step of [`Lockstep::step`] composed from [`Lockstep::rhs`] and [`Lockstep::clear`]
/// exactly as the scalar RK4 step does (the trait's default, for models that take the composed
/// step in some cases and their own in others).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn compose_step<B: Lockstep<N, L> + ?Sized, const N: usize, const L: usize>(
    b: &B,
    j: usize,
    t0: &[f64; L],
    t1: &[f64; L],
    grid: &[f64; L],
    lanes: &B::Lanes,
    y0: &Soa<N, L>,
    f0: &Soa<N, L>,
    y1: &mut Soa<N, L>,
    f1: &mut Soa<N, L>,
) -> u32 {
    let mut h = [0.0; L];
    let mut h2 = [0.0; L];
    let mut h6 = [0.0; L];
    let mut mid = At {
        t: [0.0; L],
        grid: [0.0; L],
    };
    let mut end = mid;
    for l in 0..L {
        h[l] = t1[l] - t0[l];
        h2[l] = 0.5 * h[l];
        h6[l] = h[l] * (1.0 / 6.0);
        mid.t[l] = t0[l] + h2[l];
        end.t[l] = t0[l] + h[l];
        mid.grid[l] = grid[l] + 0.5;
        end.grid[l] = grid[l] + 1.0;
    }
    let y = y0;
    let mut yt = [[0.0; L]; N];
    let mut k2 = [[0.0; L]; N];
    let mut k3 = [[0.0; L]; N];
    let mut k4 = [[0.0; L]; N];
    for i in 0..N {
        for l in 0..L {
            yt[i][l] = y[i][l] + h2[l] * f0[i][l];
        }
    }
    b.rhs(j, Stage::Mid, &mid, lanes, &yt, &mut k2);
    for i in 0..N {
        for l in 0..L {
            yt[i][l] = y[i][l] + h2[l] * k2[i][l];
        }
    }
    b.rhs(j, Stage::Mid, &mid, lanes, &yt, &mut k3);
    for i in 0..N {
        for l in 0..L {
            yt[i][l] = y[i][l] + h[l] * k3[i][l];
        }
    }
    b.rhs(j, Stage::End, &end, lanes, &yt, &mut k4);
    for i in 0..N {
        for l in 0..L {
            y1[i][l] = y[i][l] + h6[l] * (f0[i][l] + 2.0 * (k2[i][l] + k3[i][l]) + k4[i][l]);
        }
    }
    b.rhs(j, Stage::End, &end, lanes, y1, f1);
    // interior bound of the Hermite interpolant over the guard components, and finiteness
    let mut dev = [0.0f64; L];
    let mut finite = [true; L];
    for i in 0..N {
        for l in 0..L {
            let d = y1[i][l] - y[i][l];
            let r2 = h[l] * f0[i][l] - d;
            let r3 = d - h[l] * f1[i][l] - r2;
            if i < B::GUARD_DIMS {
                dev[l] = dev[l].max(r2.abs() + r3.abs());
            }
            finite[l] &= (y1[i][l].abs() < f64::INFINITY) & (f1[i][l].abs() < f64::INFINITY);
        }
    }
    let mut fin = 0u32;
    for l in 0..L {
        fin |= (finite[l] as u32) << l;
    }
    let clear = b.clear(j, lanes, y, y1, &dev);
    clear & fin
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

/// Per-lane bookkeeping outside the hot arrays.
struct Slot<'s, S: HybridSystem<N>, const N: usize> {
    integ: Option<Integrator<&'s S, N>>,
    sys: Option<&'s S>,
    lock_rhs: u64,
    /// Work of integrators replaced by a restart.
    prior: Stats,
}

struct Engine<'s, B: Lockstep<N, L>, const N: usize, const L: usize>
where
    B::Sys: 's,
{
    /// States and derivatives, double-buffered: `y[cur]` is current, a lockstep step writes the
    /// other buffer and becomes current (lanes that did not take it are copied over), so a step
    /// costs no per-lane commit.
    y: [Soa<N, L>; 2],
    f: [Soa<N, L>; 2],
    cur: usize,
    t: [f64; L],
    idx: [f64; L],
    origin: [f64; L],
    h: [f64; L],
    tseg: [f64; L],
    kseg: [f64; L],
    period: [f64; L],
    lanes: B::Lanes,
    work: B::Work,
    lock_steps: [u64; L],
    /// busy lanes, lanes the batched field covers, lanes whose `f` must be recomputed
    active: u32,
    lockable: u32,
    stale: u32,
    /// lanes that took lockstep steps since their last scalar step
    progressed: u32,
    slots: [Slot<'s, B::Sys, N>; L],
}

impl<'s, B: Lockstep<N, L>, const N: usize, const L: usize> Engine<'s, B, N, L>
where
    B::Sys: 's,
{
    fn new(batch: &B) -> Self {
        Engine {
            y: [[[0.0; L]; N]; 2],
            f: [[[0.0; L]; N]; 2],
            cur: 0,
            t: [0.0; L],
            idx: [0.0; L],
            origin: [0.0; L],
            h: [0.0; L],
            tseg: [0.0; L],
            kseg: [0.0; L],
            period: [0.0; L],
            lanes: batch.idle_lanes(),
            work: batch.new_work(),
            lock_steps: [0; L],
            active: 0,
            lockable: 0,
            stale: 0,
            progressed: 0,
            slots: core::array::from_fn(|_| Slot {
                integ: None,
                sys: None,
                lock_rhs: 0,
                prior: Stats::default(),
            }),
        }
    }

    /// Takes the lane's state from its integrator (after a start, a restart or scalar steps).
    fn load_from_integ(&mut self, batch: &B, l: usize) {
        let slot = &self.slots[l];
        let integ = slot.integ.as_ref().expect("busy lane");
        let y = integ.y();
        for i in 0..N {
            self.y[self.cur][i][l] = y[i];
        }
        self.t[l] = integ.t();
        let bit = 1u32 << l;
        if batch.set_lane(
            &mut self.lanes,
            &mut self.work,
            l,
            slot.sys.expect("busy lane"),
            integ.mode(),
            self.h[l],
        ) {
            self.lockable |= bit;
            self.stale |= bit;
        } else {
            batch.set_idle(&mut self.lanes, l);
            self.lockable &= !bit;
        }
    }

    fn retire(&mut self, batch: &B, l: usize) {
        let bit = 1u32 << l;
        self.active &= !bit;
        self.lockable &= !bit;
        self.stale &= !bit;
        batch.set_idle(&mut self.lanes, l);
        for b in 0..2 {
            for i in 0..N {
                self.y[b][i][l] = 0.0;
                self.f[b][i][l] = 0.0;
            }
        }
        self.progressed &= !bit;
        let slot = &mut self.slots[l];
        slot.integ = None;
        slot.sys = None;
    }

    /// Memory parameter of lane `l`'s mode (its scalar integrator holds the mode: lockstep steps
    /// change no mode).
    fn memory(&self, l: usize) -> f64 {
        let slot = &self.slots[l];
        match (slot.sys, slot.integ.as_ref()) {
            (Some(sys), Some(integ)) => sys.memory(integ.mode()),
            _ => 0.0,
        }
    }

    fn stats(&self, l: usize) -> Stats {
        let slot = &self.slots[l];
        let mut s = slot.integ.as_ref().map(|i| i.stats()).unwrap_or_default();
        s.steps += slot.prior.steps + self.lock_steps[l];
        s.rejected += slot.prior.rejected;
        s.rhs_evals += slot.prior.rhs_evals + slot.lock_rhs + 4 * self.lock_steps[l];
        s.events += slot.prior.events;
        s.breakpoints += slot.prior.breakpoints;
        s
    }

    /// A fresh integrator for lane `l` at `(t0, y0)`; false (lane retired) if it cannot start.
    #[allow(clippy::too_many_arguments)]
    fn begin<D: LaneDriver<'s, B, N, L>>(
        &mut self,
        batch: &B,
        drv: &mut D,
        l: usize,
        sys: &'s B::Sys,
        t0: f64,
        y0: [f64; N],
        memory: f64,
        h: f64,
    ) -> bool {
        match Integrator::new(sys, Scheme::Rk4 { h }, t0, y0) {
            Ok(integ) => {
                let integ = integ.with_memory(memory);
                let slot = &mut self.slots[l];
                if let Some(old) = slot.integ.take() {
                    let s = old.stats();
                    slot.prior.steps += s.steps;
                    slot.prior.rejected += s.rejected;
                    slot.prior.rhs_evals += s.rhs_evals;
                    slot.prior.events += s.events;
                    slot.prior.breakpoints += s.breakpoints;
                }
                slot.integ = Some(integ);
                slot.sys = Some(sys);
                self.progressed &= !(1 << l);
                self.origin[l] = t0;
                self.idx[l] = 0.0;
                self.h[l] = h;
                self.tseg[l] = t0;
                self.kseg[l] = 0.0;
                self.active |= 1 << l;
                self.load_from_integ(batch, l);
                true
            }
            Err(e) => {
                drv.on_end(l, End::Failed(e));
                self.retire(batch, l);
                false
            }
        }
    }

    fn fill<D: LaneDriver<'s, B, N, L>>(&mut self, batch: &B, drv: &mut D) {
        for l in 0..L {
            while self.active & (1 << l) == 0 {
                let Some(st) = drv.next_item(l) else { break };
                if crate::cancel::requested() {
                    // (not started: it ends at once)
                    drv.on_end(l, End::Failed(SolverError::Cancelled));
                    continue;
                }
                self.period[l] = st.period;
                self.lock_steps[l] = 0;
                self.slots[l].lock_rhs = 0;
                self.slots[l].prior = Stats::default();
                self.begin(batch, drv, l, st.sys, st.t0, st.y0, st.memory, st.h);
            }
        }
    }

    /// Lane `l` takes the step to `target` (grid point `idx + 1`) with its scalar integrator.
    #[cold]
    #[inline(never)]
    fn scalar_step<D: LaneDriver<'s, B, N, L>>(
        &mut self,
        batch: &B,
        drv: &mut D,
        l: usize,
        target: f64,
        period_end: bool,
    ) {
        let mut y = [0.0; N];
        for i in 0..N {
            y[i] = self.y[self.cur][i][l];
        }
        let progressed = self.progressed & (1 << l) != 0;
        self.progressed &= !(1 << l);
        let slot = &mut self.slots[l];
        let sys = slot.sys.expect("busy lane");
        let integ = slot.integ.as_mut().expect("busy lane");
        integ.resume(self.t[l], y, self.idx[l] as i64, progressed);
        loop {
            let before = *integ.mode();
            match integ.step(target) {
                Ok(stop) => {
                    let shown = if stop == Stop::Tstop && !period_end {
                        Stop::Step
                    } else {
                        stop
                    };
                    drv.on_step(
                        l,
                        sys,
                        integ.last_step(),
                        &before,
                        shown,
                        integ.mode(),
                        integ.y(),
                    );
                    match stop {
                        Stop::Tstop => break,
                        Stop::Terminated { .. } => {
                            let (t, y) = (integ.t(), *integ.y());
                            let stats = self.stats(l);
                            let memory = self.memory(l);
                            drv.on_end(
                                l,
                                End::Done {
                                    t,
                                    y,
                                    memory,
                                    stats,
                                },
                            );
                            self.retire(batch, l);
                            return;
                        }
                        _ => {}
                    }
                }
                Err(e) => {
                    drv.on_end(l, End::Failed(e));
                    self.retire(batch, l);
                    return;
                }
            }
        }
        self.idx[l] += 1.0;
        self.load_from_integ(batch, l);
    }

    /// Reports lockstep steps of the lanes in `mask` through [`LaneDriver::on_step`].
    #[cold]
    #[inline(never)]
    fn explain<D: LaneDriver<'s, B, N, L>>(
        &self,
        drv: &mut D,
        st: &LaneStep<'_, B::Lanes, N, L>,
        mut mask: u32,
        period_end: bool,
    ) {
        let stop = if period_end { Stop::Tstop } else { Stop::Step };
        while mask != 0 {
            let l = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            let slot = &self.slots[l];
            let (Some(sys), Some(integ)) = (slot.sys, slot.integ.as_ref()) else {
                continue;
            };
            let step = st.step(l);
            let mode = *integ.mode();
            let mut y1 = [0.0; N];
            for i in 0..N {
                y1[i] = st.y1[i][l];
            }
            drv.on_step(l, sys, &step, &mode, stop, &mode, &y1);
        }
    }

    /// Recomputes the start derivative of the stale lanes at the start of step `j`.
    #[inline(always)]
    fn refresh(&mut self, batch: &B, j: usize) {
        let stale = self.stale & self.lockable & self.active;
        if stale == 0 {
            return;
        }
        let mut f = [[0.0; L]; N];
        let at = At {
            t: self.t,
            grid: self.idx,
        };
        let c = self.cur;
        batch.rhs(j, Stage::Start, &at, &self.lanes, &self.y[c], &mut f);
        for l in 0..L {
            if stale & (1 << l) != 0 {
                for i in 0..N {
                    self.f[c][i][l] = f[i][l];
                }
                self.slots[l].lock_rhs += 1;
            }
        }
        self.stale = 0;
    }

    /// One grid step of every busy lane: phase `j` of `s_per`.
    #[inline(always)]
    fn step<D: LaneDriver<'s, B, N, L>>(&mut self, batch: &B, drv: &mut D, j: usize, s_per: usize) {
        let period_end = j + 1 == s_per;
        let mut t1 = [0.0; L];
        if period_end {
            for l in 0..L {
                t1[l] = self.tseg[l] + (self.kseg[l] + 1.0) * self.period[l];
            }
        } else {
            grid_times(&mut t1, &self.origin, &self.idx, &self.h);
        }
        let mut scalar = self.active;
        if !batch.scalar_phase(j) {
            self.refresh(batch, j);
            let c = self.cur;
            let (y0, y1) = pair(&mut self.y, c);
            let (f0, f1) = pair(&mut self.f, c);
            let clear = batch.step(
                j,
                &self.t,
                &t1,
                &self.idx,
                &self.lanes,
                &self.work,
                y0,
                f0,
                y1,
                f1,
            );
            let ok = self.active & self.lockable & clear;
            if ok != 0 {
                let st = LaneStep {
                    j,
                    mask: ok,
                    lanes: &self.lanes,
                    grid: &self.idx,
                    t0: &self.t,
                    t1: &t1,
                    y0: &self.y[c],
                    f0: &self.f[c],
                    y1: &self.y[1 - c],
                    f1: &self.f[1 - c],
                };
                let explain = drv.on_lockstep(batch, &st) & ok;
                if explain != 0 {
                    self.explain(drv, &st, explain, period_end);
                }
                // the lanes that took the step advance: one more grid step (an exact integer)
                // and lockstep step; the buffer the step wrote becomes current, with the state of
                // the busy lanes that did not take the step copied over (idle lanes stay at their
                // zero state either way)
                for l in 0..L {
                    self.idx[l] += 1.0;
                    self.lock_steps[l] += 1;
                }
                let mut t = t1;
                let mut keep = self.active & !ok;
                while keep != 0 {
                    let l = keep.trailing_zeros() as usize;
                    keep &= keep - 1;
                    for i in 0..N {
                        self.y[1 - c][i][l] = self.y[c][i][l];
                        self.f[1 - c][i][l] = self.f[c][i][l];
                    }
                    t[l] = self.t[l];
                    self.idx[l] -= 1.0;
                    self.lock_steps[l] -= 1;
                }
                self.t = t;
                self.cur = 1 - c;
                self.progressed |= ok;
            }
            scalar &= !ok;
        }
        while scalar != 0 {
            let l = scalar.trailing_zeros() as usize;
            scalar &= scalar - 1;
            self.scalar_step(batch, drv, l, t1[l], period_end);
        }
    }

    /// Ends every busy lane with [`SolverError::Cancelled`] (a stop was requested).
    #[cold]
    #[inline(never)]
    fn cancel_all<D: LaneDriver<'s, B, N, L>>(&mut self, batch: &B, drv: &mut D) {
        for l in 0..L {
            if self.active & (1 << l) != 0 {
                drv.on_end(l, End::Failed(SolverError::Cancelled));
                self.retire(batch, l);
            }
        }
    }

    /// The strobe instant at the end of a period for every busy lane.
    fn strobe<D: LaneDriver<'s, B, N, L>>(&mut self, batch: &B, drv: &mut D) {
        for l in 0..L {
            if self.active & (1 << l) == 0 {
                continue;
            }
            self.kseg[l] += 1.0;
            let mut y = [0.0; N];
            for i in 0..N {
                y[i] = self.y[self.cur][i][l];
            }
            let before = y;
            let next = drv.on_strobe_set(l, self.t[l], &mut y);
            if (0..N).any(|i| y[i].to_bits() != before[i].to_bits()) {
                // a replaced state: its derivative is recomputed before the next step
                for i in 0..N {
                    self.y[self.cur][i][l] = y[i];
                }
                self.stale |= (1 << l) & self.lockable;
                self.progressed |= 1 << l;
            }
            match next {
                Next::Continue => {}
                Next::Segment => {
                    self.tseg[l] = self.t[l];
                    self.kseg[l] = 0.0;
                }
                Next::Restart => {
                    let sys = self.slots[l].sys.expect("busy lane");
                    let (t, h) = (self.t[l], self.h[l]);
                    let memory = self.memory(l);
                    self.begin(batch, drv, l, sys, t, y, memory, h);
                }
                Next::Finish => {
                    let stats = self.stats(l);
                    let memory = self.memory(l);
                    drv.on_end(
                        l,
                        End::Done {
                            t: self.t[l],
                            y,
                            memory,
                            stats,
                        },
                    );
                    self.retire(batch, l);
                }
            }
        }
    }
}

/// `t1 = origin + (idx + 1) h` lane by lane, in whole vector blocks of 8 lanes (the times of a
/// grid step as the scalar integrator computes them). Written as blocks because the plain lane
/// loop was vectorised in odd pieces (8 + 4 + 1 + 2 + 1 lanes) whose loads could not be
/// forwarded from the previous step's stores: a tenth of the engine's time went to that stall.
#[inline(always)]
fn grid_times<const L: usize>(t1: &mut [f64; L], origin: &[f64; L], idx: &[f64; L], h: &[f64; L]) {
    const B: usize = 8;
    let mut t = t1.chunks_exact_mut(B);
    let mut o = origin.chunks_exact(B);
    let mut k = idx.chunks_exact(B);
    let mut hh = h.chunks_exact(B);
    for (((t, o), k), hh) in (&mut t).zip(&mut o).zip(&mut k).zip(&mut hh) {
        for i in 0..B {
            t[i] = o[i] + (k[i] + 1.0) * hh[i];
        }
    }
    let (t, o, k, hh) = (
        t.into_remainder(),
        o.remainder(),
        k.remainder(),
        hh.remainder(),
    );
    for i in 0..t.len() {
        t[i] = o[i] + (k[i] + 1.0) * hh[i];
    }
}

/// The current buffer and the other one of a double buffer.
#[inline(always)]
fn pair<T>(b: &mut [T; 2], cur: usize) -> (&T, &mut T) {
    let [b0, b1] = b;
    if cur == 0 {
        (b0, b1)
    } else {
        (b1, b0)
    }
}

#[inline(always)]
fn drive<'s, B, D, const N: usize, const L: usize>(batch: &B, drv: &mut D)
where
    B: Lockstep<N, L>,
    B::Sys: 's,
    D: LaneDriver<'s, B, N, L>,
{
    assert!(L >= 1 && L <= 32, "1 to 32 lanes");
    let s_per = batch.steps_per_period();
    assert!(s_per >= 1, "a period has at least one step");
    let mut e: Engine<'s, B, N, L> = Engine::new(batch);
    loop {
        e.fill(batch, drv);
        if e.active == 0 {
            return;
        }
        if crate::cancel::requested() {
            e.cancel_all(batch, drv);
            continue;
        }
        for j in 0..s_per {
            e.step(batch, drv, j, s_per);
            if e.active == 0 {
                break;
            }
        }
        if e.active != 0 {
            e.strobe(batch, drv);
        }
    }
}

#[cfg(all(target_arch = "x86_64", geardyn_avx512))]
#[target_feature(enable = "avx512f,avx512vl,avx512dq,avx2,fma")]
fn drive_avx512<'s, B, D, const N: usize, const L: usize>(batch: &B, drv: &mut D)
where
    B: Lockstep<N, L>,
    B::Sys: 's,
    D: LaneDriver<'s, B, N, L>,
{
    drive(batch, drv)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn drive_avx2<'s, B, D, const N: usize, const L: usize>(batch: &B, drv: &mut D)
where
    B: Lockstep<N, L>,
    B::Sys: 's,
    D: LaneDriver<'s, B, N, L>,
{
    drive(batch, drv)
}

#[inline(never)]
fn drive_base<'s, B, D, const N: usize, const L: usize>(batch: &B, drv: &mut D)
where
    B: Lockstep<N, L>,
    B::Sys: 's,
    D: LaneDriver<'s, B, N, L>,
{
    drive(batch, drv)
}

/// The copies of the engine [`run_lanes_on`] can run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dispatch {
    /// The best copy this CPU runs (AVX-512, else AVX2/FMA, else baseline).
    Auto,
    /// The AVX2/FMA copy when the CPU has those features, else the baseline.
    Avx2,
    /// The baseline copy (x86-64 SSE2 on x86_64).
    Baseline,
}

/// Which copy of the engine [`run_lanes`] uses on this CPU: `"avx512"`, `"avx2+fma"` or
/// `"baseline"`.
pub fn dispatch_path() -> &'static str {
    if has_avx512() {
        "avx512"
    } else if has_avx2() {
        "avx2+fma"
    } else {
        "baseline"
    }
}

fn has_avx2() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

fn has_avx512() -> bool {
    #[cfg(all(target_arch = "x86_64", geardyn_avx512))]
    {
        has_avx2()
            && std::is_x86_feature_detected!("avx512f")
            && std::is_x86_feature_detected!("avx512vl")
            && std::is_x86_feature_detected!("avx512dq")
    }
    #[cfg(not(all(target_arch = "x86_64", geardyn_avx512)))]
    {
        false
    }
}

/// Runs every item the driver supplies through `L` lockstep lanes until its queue is empty.
/// Dispatches to the AVX-512 or AVX2/FMA copy of the engine when the CPU has those features (the
/// results are identical: the same IEEE operations in the same order, no fused multiply-add).
pub fn run_lanes<'s, B, D, const N: usize, const L: usize>(batch: &B, drv: &mut D)
where
    B: Lockstep<N, L>,
    B::Sys: 's,
    D: LaneDriver<'s, B, N, L>,
{
    run_lanes_on(Dispatch::Auto, batch, drv)
}

/// As [`run_lanes`], always on the baseline copy (for tests and benchmarks).
pub fn run_lanes_baseline<'s, B, D, const N: usize, const L: usize>(batch: &B, drv: &mut D)
where
    B: Lockstep<N, L>,
    B::Sys: 's,
    D: LaneDriver<'s, B, N, L>,
{
    run_lanes_on(Dispatch::Baseline, batch, drv)
}

/// As [`run_lanes`], on the copy `how` selects (when the CPU runs it; for tests and benchmarks).
pub fn run_lanes_on<'s, B, D, const N: usize, const L: usize>(how: Dispatch, batch: &B, drv: &mut D)
where
    B: Lockstep<N, L>,
    B::Sys: 's,
    D: LaneDriver<'s, B, N, L>,
{
    #[cfg(all(target_arch = "x86_64", geardyn_avx512))]
    {
        if how == Dispatch::Auto && has_avx512() {
            // SAFETY: the CPU supports the features the function was compiled for.
            unsafe { drive_avx512(batch, drv) };
            return;
        }
    }
    #[cfg(target_arch = "x86_64")]
    {
        if how != Dispatch::Baseline && has_avx2() {
            // SAFETY: the CPU supports the features the function was compiled for.
            unsafe { drive_avx2(batch, drv) };
            return;
        }
    }
    drive_base(batch, drv)
}
