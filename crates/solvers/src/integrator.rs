//! Event-aware explicit Runge–Kutta integration of a [`HybridSystem`].
//!
//! Own code rather than a crate: no ODE crate locates events on the dense output *and* resets the
//! state without allocating per step, and the event semantics below are part of the physics.
//!
//! Semantics, in order of precedence within one step:
//! 1. A step never passes the next time breakpoint, the caller's `tstop`, or (fixed-step scheme)
//!    the next grid point `t_origin + k*h`. Times closer than a few ulps are merged, so a zone border
//!    that coincides with a stroboscopic instant is a single stop.
//! 2. Guards are evaluated at both ends of the trial step and at `grazing_samples` interior points
//!    of its interpolant; the earliest sign change in an armed direction is the event. Interior
//!    samples catch a trajectory that enters and leaves a surface within one step (grazing).
//! 3. The crossing is bracketed on the interpolant (Illinois), then *polished on the true step map*:
//!    the event state is the result of a genuine step of the method of length `t_e - t0`, so an
//!    event costs no order of accuracy. The state is nudged to the new side of the surface, so the
//!    mode chosen by [`HybridSystem::on_event`] is consistent with it and the event cannot fire twice.
//! 4. After an event or a breakpoint the first-same-as-last derivative is recomputed in the new mode.
//!
//! Every integration terminates:
//! * an adaptive step is never shorter than [`min_step`]`(t)` (`16 eps max(|t|, 1)`, a step that
//!   still moves `t`); when the error control asks for less, [`SolverError::StepSizeTooSmall`];
//! * a fixed RK4 grid step or a system's [`HybridSystem::max_step`] that time cannot resolve at `t`
//!   is [`SolverError::TimeResolution`];
//! * an accumulation of events (Zeno: more than [`Options::max_events_without_progress`]
//!   consecutive events, each within [`Options::zeno_interval`] of the step-size scale after the
//!   previous) ends in the sticking mode the system offers through
//!   [`HybridSystem::zeno_fallback`], or in [`SolverError::Zeno`]; the criterion is relative to the
//!   step-size scale, not to the absolute time;
//! * the steps spent approaching one `tstop` are capped ([`Options::max_steps`]):
//!   [`SolverError::StepBudget`].

mod events;

use crate::dense::Step;
use crate::hybrid::{Guards, HybridSystem};
use crate::rk4::{combine, fractions, stage_point};
use crate::scheme::RK4_RESOLUTION;
pub use crate::scheme::{
    min_step, Options, Scheme, SolverError, Stats, Stop, BASE_STEP_BUDGET, DEFAULT_ATOL,
    DEFAULT_RTOL, MAX_GRAZING_SAMPLES,
};

/// A trial step: end state, end derivative, error norm and interpolant.
struct Trial<T, const N: usize> {
    y1: [f64; N],
    f1: [f64; N],
    tt1: T,
    err: f64,
    step: Step<N>,
}

// Dormand–Prince 5(4) tableau (Dormand & Prince 1980; dense output of Hairer, Nørsett & Wanner,
// Solving ODEs I, 2nd ed., routine DOPRI5 / CONTD5).
const C2: f64 = 1.0 / 5.0;
const C3: f64 = 3.0 / 10.0;
const C4: f64 = 4.0 / 5.0;
const C5: f64 = 8.0 / 9.0;
const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const A71: f64 = 35.0 / 384.0;
const A73: f64 = 500.0 / 1113.0;
const A74: f64 = 125.0 / 192.0;
const A75: f64 = -2187.0 / 6784.0;
const A76: f64 = 11.0 / 84.0;
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;
const D1: f64 = -12715105075.0 / 11282082432.0;
const D3: f64 = 87487479700.0 / 32700410799.0;
const D4: f64 = -10690763975.0 / 1880347072.0;
const D5: f64 = 701980252875.0 / 199316789632.0;
const D6: f64 = -1453857185.0 / 822651844.0;
const D7: f64 = 69997945.0 / 29380423.0;

/// Event-aware integrator of the hybrid system `S` (a generic parameter, not a trait object).
///
/// # Example: bouncing ball, first impact at `t = sqrt(2 h / g)`
/// ```
/// use geardyn_solvers::{Direction, EventAction, Guards, HybridSystem, Integrator, Scheme, Stop};
/// # struct Ball;
/// # impl HybridSystem<2> for Ball {
/// #     type Mode = (); type TimeTerms = ();
/// #     fn initial_mode(&self, _t: f64, _y: &mut [f64; 2]) {}
/// #     fn time_terms(&self, _t: f64) {}
/// #     fn rhs(&self, _t: f64, _tt: &(), y: &[f64; 2], _m: &(), dy: &mut [f64; 2]) { *dy = [y[1], -9.81]; }
/// #     fn guards(&self, _t: f64, y: &[f64; 2], _m: &(), g: &mut Guards) { g.push(y[0], Direction::Falling); }
/// #     fn on_event(&self, _t: f64, y: &mut [f64; 2], _m: &mut (), _i: usize) -> EventAction {
/// #         y[0] = 0.0; y[1] = -0.5 * y[1]; EventAction::Continue }
/// # }
/// let mut integ = Integrator::new(Ball, Scheme::dopri_default(), 0.0, [1.0, 0.0]).unwrap();
/// loop {
///     match integ.step(10.0).unwrap() {
///         Stop::Event { .. } => break,
///         Stop::Tstop => panic!("no impact"),
///         _ => {}
///     }
/// }
/// assert!((integ.t() - (2.0f64 / 9.81).sqrt()).abs() < 1e-12);
/// ```
pub struct Integrator<S: HybridSystem<N>, const N: usize> {
    sys: S,
    scheme: Scheme,
    opts: Options,
    t: f64,
    y: [f64; N],
    mode: S::Mode,
    f0: [f64; N],
    tt0: S::TimeTerms,
    f0_valid: bool,
    /// Guard values at the current state and at the end of the trial step (flipped, not copied).
    gbuf: [Guards; 2],
    gcur: usize,
    grazing_m: usize,
    g0_valid: bool,
    h_next: f64,
    grid_origin: f64,
    grid_index: i64,
    next_bp: f64,
    last: Step<N>,
    stats: Stats,
    /// Consecutive accumulating events, the time of the event before the first of them, and
    /// whether a Zeno fallback was applied without an ordinary step since.
    events_without_progress: usize,
    last_event_t: f64,
    zeno_run_start: f64,
    zeno_fallback_pending: bool,
    /// Step budget of the current request (`tstop`): its start time, size, and the value of
    /// [`Integrator::work`] at which it is spent.
    budget_tstop: f64,
    budget_t0: f64,
    budget_total: u64,
    budget_end: u64,
}

impl<S: HybridSystem<N>, const N: usize> Integrator<S, N> {
    /// Creates an integrator at `(t0, y0)`; the initial mode comes from
    /// [`HybridSystem::initial_mode`]. The RK4 grid starts at `t0`.
    pub fn new(sys: S, scheme: Scheme, t0: f64, y0: [f64; N]) -> Result<Self, SolverError> {
        match scheme {
            Scheme::DormandPrince { rtol, atol } => {
                if !(rtol > 0.0 && rtol < 1.0 && rtol.is_finite()) {
                    return Err(SolverError::Setting("rtol must lie in (0, 1)"));
                }
                if !(atol > 0.0 && atol.is_finite()) {
                    return Err(SolverError::Setting("atol must be > 0"));
                }
            }
            Scheme::Rk4 { h } => {
                if !(h > 0.0 && h.is_finite()) {
                    return Err(SolverError::Setting("RK4 step h must be > 0 and finite"));
                }
                if t0.is_finite() {
                    Self::check_grid(h, t0)?;
                }
            }
        }
        if !t0.is_finite() || y0.iter().any(|v| !v.is_finite()) {
            return Err(SolverError::NonFinite { t: t0 });
        }
        let tt0 = sys.time_terms(t0);
        let mut y = y0;
        let mode = sys.initial_mode(t0, &mut y);
        let mut it = Integrator {
            sys,
            scheme,
            opts: Options::default(),
            t: t0,
            y: y0,
            mode,
            f0: [0.0; N],
            tt0,
            f0_valid: false,
            gbuf: [Guards::EMPTY; 2],
            gcur: 0,
            grazing_m: Self::grazing_samples(scheme, &Options::default()),
            g0_valid: false,
            h_next: 0.0,
            grid_origin: t0,
            grid_index: 1,
            next_bp: f64::INFINITY,
            last: Step::empty(),
            stats: Stats::default(),
            events_without_progress: 0,
            last_event_t: f64::NAN,
            zeno_run_start: f64::NAN,
            zeno_fallback_pending: false,
            budget_tstop: f64::NAN,
            budget_t0: f64::NAN,
            budget_total: 0,
            budget_end: 0,
        };
        it.reset(t0, y)?;
        Ok(it)
    }

    /// Restarts at `(t0, y0)` (mode from [`HybridSystem::initial_mode`], RK4 grid origin `t0`).
    pub fn reset(&mut self, t0: f64, y0: [f64; N]) -> Result<(), SolverError> {
        if !t0.is_finite() || y0.iter().any(|v| !v.is_finite()) {
            return Err(SolverError::NonFinite { t: t0 });
        }
        let mut y = y0;
        self.mode = self.sys.initial_mode(t0, &mut y);
        self.t = t0;
        self.y = y;
        self.f0_valid = false;
        self.g0_valid = false;
        self.h_next = 0.0;
        self.grid_origin = t0;
        self.grid_index = 1;
        self.next_bp = self.sys.next_breakpoint(t0, &self.mode);
        self.last = Step::empty();
        self.last.t0 = t0;
        self.last.t1 = t0;
        self.last.r[0] = y;
        self.events_without_progress = 0;
        self.last_event_t = f64::NAN;
        self.zeno_run_start = f64::NAN;
        self.zeno_fallback_pending = false;
        self.budget_tstop = f64::NAN;
        Ok(())
    }

    /// Continues a fixed-step (RK4) integration that another engine advanced meanwhile (the
    /// lockstep ensemble, [`crate::ensemble`]): the state is `y` at time `t`, which is grid point
    /// `grid_index` (`t_origin + grid_index*h`, or a stop time merged with it), in the current
    /// mode. `progressed`: ordinary steps were taken since this integrator last stepped (they end
    /// a pending Zeno fallback, as an ordinary step of its own would). The event history (Zeno
    /// counters) and the work counters are kept.
    pub fn resume(&mut self, t: f64, y: [f64; N], grid_index: i64, progressed: bool) {
        self.t = t;
        self.y = y;
        self.grid_index = grid_index + 1;
        self.f0_valid = false;
        self.g0_valid = false;
        self.next_bp = self.sys.next_breakpoint(t, &self.mode);
        self.last.t0 = t;
        self.last.t1 = t;
        self.last.r = [[0.0; N]; 5];
        self.last.r[0] = y;
        if progressed {
            self.zeno_fallback_pending = false;
        }
    }

    /// Replaces the state at the current time, keeping the mode (for renormalising the tangent
    /// part of an augmented state; the caller keeps the state consistent with the mode).
    pub fn set_state(&mut self, y: [f64; N]) {
        self.y = y;
        self.f0_valid = false;
        self.g0_valid = false;
        self.last.r[0] = y;
    }

    /// Replaces the mode at the current time, keeping the state (for setting a mode's memory
    /// parameter, [`HybridSystem::with_memory`]; the caller keeps the mode consistent with the
    /// state).
    pub fn set_mode(&mut self, mode: S::Mode) {
        self.mode = mode;
        self.f0_valid = false;
        self.g0_valid = false;
        self.next_bp = self.sys.next_breakpoint(self.t, &self.mode);
    }

    /// The start mode with the memory parameter `memory` ([`HybridSystem::with_memory`]; 0
    /// leaves it as [`HybridSystem::initial_mode`] chose it): a run that continues another
    /// starts with that run's memory (the hysteresis factor of an impact in progress).
    pub fn with_memory(mut self, memory: f64) -> Self {
        if memory != 0.0 {
            let m = self.sys.with_memory(&self.mode, memory);
            self.set_mode(m);
        }
        self
    }

    /// Replaces the options.
    pub fn with_options(mut self, opts: Options) -> Self {
        self.opts = opts;
        self.grazing_m = Self::grazing_samples(self.scheme, &opts);
        self
    }

    /// Current time.
    #[inline]
    pub fn t(&self) -> f64 {
        self.t
    }
    /// Current state (after any reset of the last event).
    #[inline]
    pub fn y(&self) -> &[f64; N] {
        &self.y
    }
    /// Current mode.
    #[inline]
    pub fn mode(&self) -> &S::Mode {
        &self.mode
    }
    /// The system.
    #[inline]
    pub fn system(&self) -> &S {
        &self.sys
    }
    /// The last step (up to the event or stop that ended it), with its interpolant.
    #[inline]
    pub fn last_step(&self) -> &Step<N> {
        &self.last
    }
    /// Work counters.
    #[inline]
    pub fn stats(&self) -> Stats {
        self.stats
    }
    /// The scheme.
    #[inline]
    pub fn scheme(&self) -> Scheme {
        self.scheme
    }

    #[inline]
    fn snap(t: f64) -> f64 {
        64.0 * f64::EPSILON * t.abs().max(1.0)
    }

    /// A fixed grid step `h` must be resolvable at `t`.
    fn check_grid(h: f64, t: f64) -> Result<(), SolverError> {
        let min = RK4_RESOLUTION * Self::snap(t);
        if h < min {
            return Err(SolverError::TimeResolution { t, h, min });
        }
        Ok(())
    }

    /// Default step budget of a request from the current time to `tstop`.
    fn step_budget(&self, tstop: f64) -> u64 {
        if let Some(n) = self.opts.max_steps {
            return n;
        }
        let span = tstop - self.t;
        let h_char = match self.scheme {
            Scheme::Rk4 { h } => h,
            Scheme::DormandPrince { .. } => self.sys.max_step(),
        };
        let steps = if span > 0.0 && h_char > 0.0 && h_char.is_finite() {
            span / h_char
        } else {
            0.0
        };
        // float-to-int casts saturate
        (BASE_STEP_BUDGET as f64 + 64.0 * steps) as u64
    }

    /// Starts a request to `tstop` (a `tstop` other than the last one, or the first after a
    /// reset): its step budget, and a check that an RK4 grid is resolved all the way there.
    #[cold]
    fn new_request(&mut self, tstop: f64) -> Result<(), SolverError> {
        if let Scheme::Rk4 { h } = self.scheme {
            Self::check_grid(h, self.t.abs().max(tstop.abs()))?;
        }
        self.budget_tstop = tstop;
        self.budget_t0 = self.t;
        self.budget_total = self.step_budget(tstop);
        self.budget_end = self.work().saturating_add(self.budget_total);
        Ok(())
    }

    /// Trial steps taken so far (accepted, event and rejected ones).
    #[inline(always)]
    fn work(&self) -> u64 {
        self.stats.steps + self.stats.rejected
    }

    #[cold]
    #[inline(never)]
    fn budget_error(&self) -> SolverError {
        SolverError::StepBudget {
            t0: self.budget_t0,
            t: self.t,
            tstop: self.budget_tstop,
            steps: self.budget_total,
        }
    }

    #[inline(always)]
    fn ensure_start(&mut self) {
        if !(self.f0_valid && self.g0_valid && self.h_next > 0.0) {
            self.restart();
        }
    }

    /// Recomputes the derivative, guards and first step after a reset, event or breakpoint.
    #[cold]
    fn restart(&mut self) {
        if !self.f0_valid {
            self.tt0 = self.sys.time_terms(self.t);
            self.sys
                .rhs(self.t, &self.tt0, &self.y, &self.mode, &mut self.f0);
            self.stats.rhs_evals += 1;
            self.f0_valid = true;
        }
        if !self.g0_valid {
            guards_into(
                &self.sys,
                self.t,
                &self.y,
                &self.mode,
                &mut self.gbuf[self.gcur],
            );
            self.g0_valid = true;
        }
        if self.h_next <= 0.0 {
            self.h_next = self.initial_step();
        }
    }

    fn initial_step(&self) -> f64 {
        match self.scheme {
            Scheme::Rk4 { h } => h,
            Scheme::DormandPrince { rtol, atol } => {
                // Hairer's first guess: 1% of ||y|| / ||f|| in the tolerance-weighted norm.
                let mut d0 = 0.0;
                let mut d1 = 0.0;
                for i in 0..N {
                    let sc = atol + rtol * self.y[i].abs();
                    d0 += (self.y[i] / sc).powi(2);
                    d1 += (self.f0[i] / sc).powi(2);
                }
                let dim = self.sys.active_dim() as f64;
                let (d0, d1) = ((d0 / dim).sqrt(), (d1 / dim).sqrt());
                let h = if d0 < 1e-5 || d1 < 1e-5 {
                    1e-6
                } else {
                    0.01 * d0 / d1
                };
                let h = h.min(self.sys.max_step()).min(1.0);
                // a state or field too large for the tolerance-weighted norm gives 0 or NaN: start
                // from the shortest resolved step (the step loop raises it to that anyway)
                if h > 0.0 {
                    h
                } else {
                    min_step(self.t)
                }
            }
        }
    }

    /// A step of the scheme from the current state with length `h` (no acceptance logic).
    // always inlined: returned by value, the 144-byte trial was otherwise memmoved twice per step
    #[inline(always)]
    fn trial(&mut self, h: f64) -> Trial<S::TimeTerms, N> {
        let (t, y, f0, mode) = (self.t, &self.y, &self.f0, &self.mode);
        let sys = &self.sys;
        match self.scheme {
            Scheme::Rk4 { .. } => {
                let mut yt = [0.0; N];
                let mut k2 = [0.0; N];
                let mut k3 = [0.0; N];
                let mut k4 = [0.0; N];
                // the stage arithmetic of every RK4 step (the lanes' too)
                let (h2, h6) = fractions(h);
                let th = sys.time_terms(t + h2);
                let t1 = t + h;
                let tt1 = sys.time_terms(t1);
                for i in 0..N {
                    yt[i] = stage_point(y[i], h2, f0[i]);
                }
                sys.rhs(t + h2, &th, &yt, mode, &mut k2);
                for i in 0..N {
                    yt[i] = stage_point(y[i], h2, k2[i]);
                }
                sys.rhs(t + h2, &th, &yt, mode, &mut k3);
                for i in 0..N {
                    yt[i] = stage_point(y[i], h, k3[i]);
                }
                sys.rhs(t1, &tt1, &yt, mode, &mut k4);
                let mut y1 = [0.0; N];
                for i in 0..N {
                    y1[i] = combine(y[i], h6, f0[i], k2[i], k3[i], k4[i]);
                }
                let mut f1 = [0.0; N];
                sys.rhs(t1, &tt1, &y1, mode, &mut f1);
                self.stats.rhs_evals += 4;
                Trial {
                    y1,
                    f1,
                    tt1,
                    err: 0.0,
                    step: Step::hermite(t, t1, y, &y1, f0, &f1),
                }
            }
            Scheme::DormandPrince { rtol, atol } => {
                let k1 = f0;
                let mut k2 = [0.0; N];
                let mut k3 = [0.0; N];
                let mut k4 = [0.0; N];
                let mut k5 = [0.0; N];
                let mut k6 = [0.0; N];
                let mut k7 = [0.0; N];
                let mut yt = [0.0; N];
                for i in 0..N {
                    yt[i] = y[i] + h * A21 * k1[i];
                }
                let tc = t + C2 * h;
                sys.rhs(tc, &sys.time_terms(tc), &yt, mode, &mut k2);
                for i in 0..N {
                    yt[i] = y[i] + h * (A31 * k1[i] + A32 * k2[i]);
                }
                let tc = t + C3 * h;
                sys.rhs(tc, &sys.time_terms(tc), &yt, mode, &mut k3);
                for i in 0..N {
                    yt[i] = y[i] + h * (A41 * k1[i] + A42 * k2[i] + A43 * k3[i]);
                }
                let tc = t + C4 * h;
                sys.rhs(tc, &sys.time_terms(tc), &yt, mode, &mut k4);
                for i in 0..N {
                    yt[i] = y[i] + h * (A51 * k1[i] + A52 * k2[i] + A53 * k3[i] + A54 * k4[i]);
                }
                let tc = t + C5 * h;
                sys.rhs(tc, &sys.time_terms(tc), &yt, mode, &mut k5);
                for i in 0..N {
                    yt[i] = y[i]
                        + h * (A61 * k1[i] + A62 * k2[i] + A63 * k3[i] + A64 * k4[i] + A65 * k5[i]);
                }
                let t1 = t + h;
                let tt1 = sys.time_terms(t1);
                sys.rhs(t1, &tt1, &yt, mode, &mut k6);
                let mut y1 = [0.0; N];
                for i in 0..N {
                    y1[i] = y[i]
                        + h * (A71 * k1[i] + A73 * k3[i] + A74 * k4[i] + A75 * k5[i] + A76 * k6[i]);
                }
                sys.rhs(t1, &tt1, &y1, mode, &mut k7);
                self.stats.rhs_evals += 6;
                let mut err = 0.0;
                let mut r = [[0.0; N]; 5];
                for i in 0..N {
                    let e = h
                        * (E1 * k1[i]
                            + E3 * k3[i]
                            + E4 * k4[i]
                            + E5 * k5[i]
                            + E6 * k6[i]
                            + E7 * k7[i]);
                    let sc = atol + rtol * y[i].abs().max(y1[i].abs());
                    err += (e / sc) * (e / sc);
                    let d = y1[i] - y[i];
                    r[0][i] = y[i];
                    r[1][i] = d;
                    r[2][i] = h * k1[i] - d;
                    r[3][i] = d - h * k7[i] - r[2][i];
                    r[4][i] = h
                        * (D1 * k1[i]
                            + D3 * k3[i]
                            + D4 * k4[i]
                            + D5 * k5[i]
                            + D6 * k6[i]
                            + D7 * k7[i]);
                }
                let err = (err / sys.active_dim() as f64).sqrt();
                Trial {
                    y1,
                    f1: k7,
                    tt1,
                    err: if err.is_finite() { err } else { f64::INFINITY },
                    step: Step { t0: t, t1, r },
                }
            }
        }
    }

    /// Advances by one step, never past `tstop`, and says why it stopped.
    pub fn step(&mut self, tstop: f64) -> Result<Stop, SolverError> {
        if self.t >= tstop - Self::snap(tstop) {
            return Ok(Stop::Tstop);
        }
        if crate::cancel::requested() {
            return Err(SolverError::Cancelled);
        }
        if tstop != self.budget_tstop {
            self.new_request(tstop)?;
        }
        // (checked once per call: the rejections within one call are bounded by the step-size
        // floor, and every call that returns Ok takes a step)
        if self.work() >= self.budget_end {
            return Err(self.budget_error());
        }
        self.ensure_start();
        loop {
            // --- choose the end of the trial step
            let t = self.t;
            let bp = self.next_bp;
            let mut t_end;
            let mut on_grid = false;
            match self.scheme {
                Scheme::Rk4 { h } => {
                    let mut tg = self.grid_origin + self.grid_index as f64 * h;
                    while tg <= t + Self::snap(tg) {
                        self.grid_index += 1;
                        tg = self.grid_origin + self.grid_index as f64 * h;
                    }
                    t_end = tg;
                    on_grid = true;
                }
                Scheme::DormandPrince { .. } => {
                    let h_min = min_step(t);
                    let h_max = self.sys.max_step();
                    if h_max < h_min {
                        return Err(SolverError::TimeResolution {
                            t,
                            h: h_max,
                            min: h_min,
                        });
                    }
                    // never a step that does not move t (h_next may be 0 after a huge field)
                    let h = self.h_next.min(h_max).max(h_min);
                    t_end = t + h;
                }
            }
            let target = tstop.min(bp);
            let mut hit_tstop = false;
            let mut hit_bp = false;
            let adaptive = matches!(self.scheme, Scheme::DormandPrince { .. });
            // merge stops closer than a few ulps; stretch an adaptive step that would leave a sliver
            if t_end >= target - Self::snap(target)
                || (adaptive && t_end + 0.1 * (t_end - t) >= target)
            {
                t_end = target;
                hit_tstop = (tstop - t_end).abs() <= Self::snap(tstop);
                hit_bp = (bp - t_end).abs() <= Self::snap(t_end);
                if on_grid {
                    let tg = self.grid_origin + self.grid_index as f64 * self.rk4_h();
                    on_grid = (tg - t_end).abs() <= Self::snap(tg);
                }
            }
            let h = t_end - t;
            let trial = self.trial(h);

            if let Scheme::DormandPrince { .. } = self.scheme {
                if trial.err > 1.0 {
                    self.stats.rejected += 1;
                    let fac = if trial.err.is_finite() {
                        (0.9 * trial.err.powf(-0.2)).max(0.2)
                    } else {
                        0.1
                    };
                    self.h_next = h * fac;
                    if self.h_next < min_step(t) {
                        return Err(SolverError::StepSizeTooSmall { t });
                    }
                    continue;
                }
                let fac = if trial.err > 0.0 {
                    (0.9 * trial.err.powf(-0.2)).clamp(0.2, 5.0)
                } else {
                    5.0
                };
                // a step shortened to meet a stop does not shrink the next one
                let h_cand = h * fac;
                self.h_next = if hit_tstop || hit_bp {
                    self.h_next.max(h_cand)
                } else {
                    h_cand
                };
            }
            if trial.y1.iter().any(|v| !v.is_finite()) {
                return Err(SolverError::NonFinite { t: t_end });
            }

            // --- state events
            let (cur, next) = (self.gcur, 1 - self.gcur);
            guards_into(
                &self.sys,
                t_end,
                &trial.y1,
                &self.mode,
                &mut self.gbuf[next],
            );
            if let Some((idx, ta, ga, tb, gb)) =
                self.find_crossing(&trial, &self.gbuf[cur], &self.gbuf[next])
            {
                return self.handle_event(idx, ta, ga, tb, gb, h);
            }

            // --- accept
            self.stats.steps += 1;
            self.t = t_end;
            self.y = trial.y1;
            self.f0 = trial.f1;
            self.tt0 = trial.tt1;
            self.gcur = next;
            self.last = trial.step;
            self.zeno_fallback_pending = false;
            if on_grid {
                self.grid_index += 1;
            }
            if hit_bp {
                self.stats.breakpoints += 1;
                self.sys.on_breakpoint(self.t, &mut self.y, &mut self.mode);
                self.f0_valid = false;
                self.g0_valid = false;
                self.next_bp = self.sys.next_breakpoint(self.t, &self.mode);
                self.ensure_start();
            }
            return Ok(if hit_tstop {
                Stop::Tstop
            } else if hit_bp {
                Stop::Breakpoint
            } else {
                Stop::Step
            });
        }
    }

    fn rk4_h(&self) -> f64 {
        match self.scheme {
            Scheme::Rk4 { h } => h,
            _ => f64::NAN,
        }
    }

    /// Integrates to `tstop`, calling `observe(self, stop)` after every step.
    pub fn run_until<F>(&mut self, tstop: f64, mut observe: F) -> Result<(), SolverError>
    where
        F: FnMut(&Self, Stop),
    {
        loop {
            let stop = self.step(tstop)?;
            observe(self, stop);
            match stop {
                Stop::Tstop | Stop::Terminated { .. } => return Ok(()),
                _ => {}
            }
        }
    }
}

/// Evaluates the guards into an emptied buffer.
#[inline(always)]
fn guards_into<S: HybridSystem<N>, const N: usize>(
    sys: &S,
    t: f64,
    y: &[f64; N],
    mode: &S::Mode,
    g: &mut Guards,
) {
    g.clear();
    sys.guards(t, y, mode, g);
}
