//! The hybrid (non-smooth) dynamical system interface every integrator and analysis is generic over.
//!
//! A hybrid system is a family of smooth vector fields indexed by a discrete *mode*. Between events
//! the mode is fixed and the right-hand side is smooth (the integrator may evaluate it slightly past a
//! switching surface: each mode's field must be defined, and smooth, on both sides). Modes change at
//!
//! * **state events** — a guard function `g_i(t, y, mode)` crosses zero in its armed direction; the
//!   integrator locates the crossing and calls [`HybridSystem::on_event`], which may change the mode
//!   and reset the state (an impact law, say);
//! * **time breakpoints** — known instants where the field jumps in time (zone borders of a mesh
//!   cycle); the integrator steps exactly onto [`HybridSystem::next_breakpoint`] and calls
//!   [`HybridSystem::on_breakpoint`].
//!
//! Keeping the time-piecewise structure in the mode (rather than recomputing "which zone am I in"
//! from a rounded time) is what makes a contact boundary crossed exactly at a zone border safe.

use core::fmt::Debug;

/// Most guard functions one mode may arm (stack buffers in the integrator are this long): a gear
/// train of 24 meshes, all separated, arms two each. The integrator reuses its two buffers by
/// index, so the length costs no time per step.
pub const MAX_GUARDS: usize = 48;

/// Crossing direction in which a guard fires.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    /// From `g <= 0` to `g > 0`.
    Rising,
    /// From `g >= 0` to `g < 0`.
    Falling,
    /// Either of the above.
    Either,
}

impl Direction {
    /// Whether the change `ga -> gb` is a crossing in this direction.
    ///
    /// The half-open convention (`<= 0` to `> 0`) means a state placed exactly on the surface after
    /// an event is on neither side: it cannot re-trigger the event it came from, but does trigger
    /// the opposite guard at once if the motion turns back (a grazing touch).
    #[inline]
    pub fn crossed(self, ga: f64, gb: f64) -> bool {
        match self {
            Direction::Rising => ga <= 0.0 && gb > 0.0,
            Direction::Falling => ga >= 0.0 && gb < 0.0,
            Direction::Either => (ga <= 0.0 && gb > 0.0) || (ga >= 0.0 && gb < 0.0),
        }
    }

    /// The integrator's midpoint test of a step on a guard sampled at its start `p`, middle `a`
    /// and end `b`: `true` when it may hold a crossing in this direction (between two samples),
    /// or a graze (the parabola through the samples has its vertex inside the step, across zero
    /// or within half the smaller end value of it), which a finer search must then settle.
    #[inline]
    pub fn near_crossing(self, p: f64, a: f64, b: f64) -> bool {
        let curv = p - 2.0 * a + b;
        if self.crossed(p, a) || self.crossed(a, b) {
            true
        } else if curv != 0.0 {
            // parabola through the three samples: vertex position and value
            let th = 0.5 + 0.25 * (p - b) / curv;
            let vertex = a - (b - p) * (b - p) / (8.0 * curv);
            th > 0.0
                && th < 1.0
                && (vertex.signum() != p.signum() || vertex.abs() < 0.5 * p.abs().min(b.abs()))
        } else {
            false
        }
    }

    /// Whether `g` lies on the side this guard leads *into*.
    #[inline]
    pub fn on_new_side(self, g_before: f64, g: f64) -> bool {
        match self {
            Direction::Rising => g > 0.0,
            Direction::Falling => g < 0.0,
            Direction::Either => {
                if g_before <= 0.0 {
                    g > 0.0
                } else {
                    g < 0.0
                }
            }
        }
    }
}

/// Values and directions of the guards armed in the current mode.
#[derive(Clone, Copy, Debug)]
pub struct Guards {
    /// Number of armed guards (`<= MAX_GUARDS`).
    pub len: usize,
    /// Guard values.
    pub value: [f64; MAX_GUARDS],
    /// Crossing direction of each guard.
    pub direction: [Direction; MAX_GUARDS],
}

impl Default for Guards {
    fn default() -> Self {
        Guards {
            len: 0,
            value: [0.0; MAX_GUARDS],
            direction: [Direction::Either; MAX_GUARDS],
        }
    }
}

impl Guards {
    /// No guard armed.
    pub const EMPTY: Guards = Guards {
        len: 0,
        value: [0.0; MAX_GUARDS],
        direction: [Direction::Either; MAX_GUARDS],
    };

    /// Arms one more guard.
    #[inline(always)]
    pub fn push(&mut self, value: f64, direction: Direction) {
        debug_assert!(self.len < MAX_GUARDS, "too many guards");
        self.value[self.len] = value;
        self.direction[self.len] = direction;
        self.len += 1;
    }

    /// Disarms all guards.
    #[inline(always)]
    pub fn clear(&mut self) {
        self.len = 0;
    }
}

/// What the integrator does after an event was handled.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EventAction {
    /// Continue integrating from the (possibly reset) state in the (possibly new) mode.
    Continue,
    /// Stop: the system reached a terminal condition (divergence, say).
    Terminate,
}

/// A hybrid dynamical system of dimension `N`.
///
/// # Example: a bouncing ball (gravity, restitution 0.5)
/// ```
/// use geardyn_solvers::{Direction, EventAction, Guards, HybridSystem};
/// struct Ball;
/// impl HybridSystem<2> for Ball {
///     type Mode = ();
///     type TimeTerms = ();
///     fn initial_mode(&self, _t: f64, _y: &mut [f64; 2]) {}
///     fn time_terms(&self, _t: f64) {}
///     fn rhs(&self, _t: f64, _tt: &(), y: &[f64; 2], _m: &(), dy: &mut [f64; 2]) {
///         *dy = [y[1], -9.81];
///     }
///     fn guards(&self, _t: f64, y: &[f64; 2], _m: &(), g: &mut Guards) {
///         g.push(y[0], Direction::Falling);
///     }
///     fn on_event(&self, _t: f64, y: &mut [f64; 2], _m: &mut (), _i: usize) -> EventAction {
///         y[0] = 0.0;
///         y[1] = -0.5 * y[1];
///         EventAction::Continue
///     }
/// }
/// ```
pub trait HybridSystem<const N: usize> {
    /// Discrete state (contact state, zone index, ...). Must be cheap to copy.
    type Mode: Copy + Debug + PartialEq;
    /// Time-only part of the field (an excitation `cos(omega t)`, say), evaluated once per distinct
    /// stage time and shared by the stages that use it. Use `()` if there is none.
    type TimeTerms: Copy;

    /// Mode of the state `y` at time `t` (used at the start of a run). May project `y` onto the
    /// admissible set (a state inside a rigid stop, say).
    fn initial_mode(&self, t: f64, y: &mut [f64; N]) -> Self::Mode;

    /// Time terms at `t`.
    fn time_terms(&self, t: f64) -> Self::TimeTerms;

    /// The vector field of `mode`: `dy = f(t, y)`.
    fn rhs(&self, t: f64, tt: &Self::TimeTerms, y: &[f64; N], mode: &Self::Mode, dy: &mut [f64; N]);

    /// Guard functions armed in `mode` and their directions: `push` them onto `g`, which the
    /// integrator hands over empty. Default: none.
    fn guards(&self, _t: f64, _y: &[f64; N], _mode: &Self::Mode, _g: &mut Guards) {}

    /// Handles the crossing of guard `index` at `t`: switch the mode, reset the state.
    fn on_event(
        &self,
        _t: f64,
        _y: &mut [f64; N],
        _mode: &mut Self::Mode,
        _index: usize,
    ) -> EventAction {
        EventAction::Continue
    }

    /// Next time breakpoint strictly after the start of the current mode's time piece
    /// (`f64::INFINITY` if none). The integrator never steps over it.
    fn next_breakpoint(&self, _t: f64, _mode: &Self::Mode) -> f64 {
        f64::INFINITY
    }

    /// Called when the integrator lands on the breakpoint `t`: advance the time piece and
    /// re-evaluate the discrete state (a backlash jump may start a separation, say).
    fn on_breakpoint(&self, _t: f64, _y: &mut [f64; N], _mode: &mut Self::Mode) {}

    /// Largest step the adaptive integrator may take (keeps grazing contacts from being stepped
    /// over). Default: unlimited.
    fn max_step(&self) -> f64 {
        f64::INFINITY
    }

    /// Components of the state that move: the adaptive integrator's error norm is the RMS over
    /// this many (the others must stay exactly zero). A system of several sizes can then share
    /// one larger `N` — padded with zeros — and step exactly as at its own size, which spares a
    /// compiled copy of every analysis per size. Default: `N`.
    fn active_dim(&self) -> usize {
        N
    }

    /// Whether the model can start from `y` at `t` as it stands: `false` for a state that
    /// [`HybridSystem::initial_mode`] would have to move (inside a rigid stop, say). Grids of
    /// initial states (basins) leave such cells out rather than count the projected state.
    /// Default: every state.
    fn admissible(&self, _t: f64, _y: &[f64; N]) -> bool {
        true
    }

    /// If every guard armed in `mode` depends on the state only (not on time) with
    /// `|g(y) - g(y')| <= L max_i |y_i - y'_i|`, return `Some(L)`. The integrator then skips the
    /// interior guard samples of a step whose interpolant provably stays farther from every
    /// surface than the guards can move — most steps. Default `None`: always sample.
    fn guard_lipschitz(&self, _mode: &Self::Mode) -> Option<f64> {
        None
    }

    /// Ends an accumulation of events (a Zeno sequence), or declines to.
    ///
    /// The integrator calls this when more than [`Options::max_events_without_progress`]
    /// consecutive state events each followed the previous one within a vanishing time (see
    /// [`Options::zeno_interval`]): an impact with restitution `R < 1` against a stop the motion is
    /// pushed into, chattering on round-off once the bounces fall below the float resolution of
    /// the guard. It is called right after [`HybridSystem::on_event`] for the last event of the
    /// run (guard `index` as armed in the mode *before* that event), with the reset state and the
    /// new mode.
    ///
    /// Return `true` after switching to a mode in which the accumulation cannot continue — the
    /// accumulation point of the sequence, typically resting on the stop: put the state on the
    /// surface with zero relative velocity and select the sticking mode (whose own guard releases
    /// it). The event is then reported as usual ([`Stop::Event`]) with the new mode. Return
    /// `false` (the default) and the integration fails with [`SolverError::Zeno`]. If the fallback
    /// does not end the accumulation (another one is detected before any ordinary step), the
    /// integration fails with [`SolverError::Zeno`] as well.
    ///
    /// [`Options::max_events_without_progress`]: crate::Options::max_events_without_progress
    /// [`Options::zeno_interval`]: crate::Options::zeno_interval
    /// [`Stop::Event`]: crate::Stop::Event
    /// [`SolverError::Zeno`]: crate::SolverError::Zeno
    fn zeno_fallback(
        &self,
        _t: f64,
        _y: &mut [f64; N],
        _mode: &mut Self::Mode,
        _index: usize,
    ) -> bool {
        false
    }

    /// Memory parameter of `mode`: a quantity the field depends on that stays constant between
    /// events and is set at events from the state (a contact law's hysteresis factor, set from an
    /// impact's entry speed). It belongs to the full state: a perturbed run differs in it too.
    /// Default: none (0).
    fn memory(&self, _mode: &Self::Mode) -> f64 {
        0.0
    }

    /// `mode` with its memory parameter replaced by `p`. Default: `mode` (no memory).
    fn with_memory(&self, mode: &Self::Mode, _p: f64) -> Self::Mode {
        *mode
    }

    /// Whether the fields of modes `a` and `b` differ at most by their memory parameters (a
    /// state perturbed from a run in mode `a` and restarted in `b` then takes `a`'s memory).
    /// Default: `b` with `a`'s memory equals `a`; override where a mode also carries bookkeeping
    /// that does not change the field (a period counter, say).
    fn same_regime(&self, a: &Self::Mode, b: &Self::Mode) -> bool {
        self.with_memory(b, self.memory(a)) == *a
    }
}

/// Implements [`HybridSystem`] for a system of one mode and no time terms (`Mode = ()`,
/// `TimeTerms = ()`): the field `dy = f(t, y)` written as `|this, t, y, dy| { ... }` (`this` for
/// `self`), then any further methods of the trait (guards and events, say).
///
/// ```
/// use geardyn_solvers::{one_mode_system, Integrator, Scheme, Stop};
/// struct Decay(f64);
/// one_mode_system!(Decay, 1, |this, _t, y, dy| {
///     dy[0] = -this.0 * y[0];
/// });
/// let mut it = Integrator::new(Decay(1.0), Scheme::dopri_default(), 0.0, [1.0]).unwrap();
/// while it.step(1.0).unwrap() != Stop::Tstop {}
/// assert!((it.y()[0] - (-1.0f64).exp()).abs() < 1e-6);
/// ```
#[macro_export]
macro_rules! one_mode_system {
    ($ty:ty, $n:literal, |$this:pat_param, $t:pat_param, $y:pat_param, $dy:ident| $field:block
     $($more:tt)*) => {
        impl $crate::HybridSystem<$n> for $ty {
            type Mode = ();
            type TimeTerms = ();
            fn initial_mode(&self, _t: f64, _y: &mut [f64; $n]) {}
            fn time_terms(&self, _t: f64) {}
            fn rhs(&self, $t: f64, _tt: &(), $y: &[f64; $n], _m: &(), $dy: &mut [f64; $n]) {
                let $this = self;
                $field
            }
            $($more)*
        }
    };
}

/// A shared reference to a system is a system: many integrators (one per basin cell, say) can
/// borrow one model instead of cloning its tables.
impl<S: HybridSystem<N>, const N: usize> HybridSystem<N> for &S {
    type Mode = S::Mode;
    type TimeTerms = S::TimeTerms;
    crate::forward_methods! { to referent;
        fn initial_mode(&self, t: f64, y: &mut [f64; N]) -> S::Mode;
        fn time_terms(&self, t: f64) -> S::TimeTerms;
        fn rhs(&self, t: f64, tt: &S::TimeTerms, y: &[f64; N], mode: &S::Mode, dy: &mut [f64; N]);
        fn guards(&self, t: f64, y: &[f64; N], mode: &S::Mode, g: &mut Guards);
        fn on_event(&self, t: f64, y: &mut [f64; N], mode: &mut S::Mode, index: usize) -> EventAction;
        fn next_breakpoint(&self, t: f64, mode: &S::Mode) -> f64;
        fn on_breakpoint(&self, t: f64, y: &mut [f64; N], mode: &mut S::Mode);
        fn max_step(&self) -> f64;
        fn active_dim(&self) -> usize;
        fn admissible(&self, t: f64, y: &[f64; N]) -> bool;
        fn guard_lipschitz(&self, mode: &S::Mode) -> Option<f64>;
        fn zeno_fallback(&self, t: f64, y: &mut [f64; N], mode: &mut S::Mode, index: usize) -> bool;
        fn memory(&self, mode: &S::Mode) -> f64;
        fn with_memory(&self, mode: &S::Mode, p: f64) -> S::Mode;
        fn same_regime(&self, a: &S::Mode, b: &S::Mode) -> bool;
    }
}
