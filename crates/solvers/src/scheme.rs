//! What an integration is asked to do and how it ends: the scheme ([`Scheme`]: adaptive
//! Dormand–Prince 5(4) or fixed-step RK4), the integrator's limits ([`Options`]), why a step
//! stopped ([`Stop`]), why an integration failed ([`SolverError`]) and its work ([`Stats`]).

/// Most interior guard samples per step.
pub const MAX_GRAZING_SAMPLES: usize = 4;

/// Fixed part of the default step budget per `tstop` ([`Options::max_steps`]).
pub const BASE_STEP_BUDGET: u64 = 10_000_000;

/// Smallest step resolved at time `t`: `16 eps max(|t|, 1)`. A step at least this long changes
/// `t` by several ulps, so the integration advances.
#[inline]
pub fn min_step(t: f64) -> f64 {
    16.0 * f64::EPSILON * t.abs().max(1.0)
}

/// A fixed grid step must be at least this many times the merge tolerance of stop times
/// (`64 eps |t|`): a shorter one cannot be laid out at `t` (grid points would merge or round).
pub(crate) const RK4_RESOLUTION: f64 = 4.0;

/// Integration scheme and its settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Scheme {
    /// Adaptive Dormand–Prince 5(4) with its 4th-order continuous extension.
    DormandPrince {
        /// Relative tolerance.
        rtol: f64,
        /// Absolute tolerance.
        atol: f64,
    },
    /// Classical fixed-step RK4 on the grid `t_origin + k*h` with cubic Hermite dense output.
    Rk4 {
        /// Grid step.
        h: f64,
    },
}

/// The project's default relative tolerance of Dormand–Prince (docs/model.md §4); every other
/// default (config files, analyses) refers to this one.
pub const DEFAULT_RTOL: f64 = 1e-9;
/// The project's default absolute tolerance of Dormand–Prince (docs/model.md §4).
pub const DEFAULT_ATOL: f64 = 1e-12;

impl Scheme {
    /// Dormand–Prince with the project defaults [`DEFAULT_RTOL`], [`DEFAULT_ATOL`].
    pub fn dopri_default() -> Self {
        Scheme::DormandPrince {
            rtol: DEFAULT_RTOL,
            atol: DEFAULT_ATOL,
        }
    }
}

/// Why [`Integrator::step`](crate::Integrator::step) returned.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stop {
    /// An ordinary step was taken.
    Step,
    /// The step ended on a time breakpoint (already handled by the system).
    Breakpoint,
    /// A state event of guard `index` was located and handled; the step ended there.
    Event {
        /// Index of the guard (in the mode that was active before the event).
        index: usize,
    },
    /// The caller's `tstop` was reached.
    Tstop,
    /// The system asked to stop at an event of guard `index`.
    Terminated {
        /// Index of the guard.
        index: usize,
    },
}

/// Integration failures.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SolverError {
    /// The adaptive step size fell below the smallest step resolved at `t` ([`min_step`]).
    #[error(
        "step size underflow at t = {t}: the error control asks for a step below {min:e}, the \
         shortest one resolved at this time (stiff or singular vector field, or a start time far \
         from 0)",
        min = min_step(*.t)
    )]
    StepSizeTooSmall {
        /// Time of failure.
        t: f64,
    },
    /// A fixed grid step (RK4) or the system's largest step is too short to be represented at `t`.
    #[error(
        "time step {h:e} is not resolved at t = {t:e} (it must be at least {min:e} there): start \
         the run nearer t = 0 or use a longer step"
    )]
    TimeResolution {
        /// Time of failure.
        t: f64,
        /// The step that cannot be represented.
        h: f64,
        /// The shortest step usable at `t`.
        min: f64,
    },
    /// The steps spent approaching one `tstop` exceeded the budget ([`Options::max_steps`]).
    #[error(
        "step budget exhausted: {steps} steps from t = {t0} did not reach t = {tstop} (stopped at \
         t = {t}); the motion makes no progress, or needs a larger Options::max_steps"
    )]
    StepBudget {
        /// Time at which the request started.
        t0: f64,
        /// Time of failure.
        t: f64,
        /// The requested stop time.
        tstop: f64,
        /// The budget.
        steps: u64,
    },
    /// The state became NaN or infinite.
    #[error("state became non-finite at t = {t} (divergent motion or invalid parameters)")]
    NonFinite {
        /// Time of failure.
        t: f64,
    },
    /// An accumulation of events (Zeno behaviour) the system does not resolve: more than
    /// [`Options::max_events_without_progress`] consecutive events, each close to the previous,
    /// and [`HybridSystem::zeno_fallback`](crate::HybridSystem::zeno_fallback) declined (or did not end the accumulation).
    #[error(
        "Zeno behaviour at t = {t}: {count} events within {span:e} time units accumulate, and the \
         system offers no sticking mode to end them (HybridSystem::zeno_fallback)"
    )]
    Zeno {
        /// Time of failure.
        t: f64,
        /// Number of consecutive accumulating events.
        count: usize,
        /// Time spanned by them.
        span: f64,
    },
    /// Invalid settings.
    #[error("invalid integrator setting: {0}")]
    Setting(&'static str),
    /// A stop was requested ([`crate::cancel::request`]) while integrating.
    #[error("interrupted: a stop was requested (Ctrl-C)")]
    Cancelled,
}

/// Work counters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stats {
    /// Accepted steps (event-polished partial steps included).
    pub steps: u64,
    /// Rejected adaptive steps.
    pub rejected: u64,
    /// Right-hand-side evaluations.
    pub rhs_evals: u64,
    /// Located state events.
    pub events: u64,
    /// Breakpoints landed on.
    pub breakpoints: u64,
}

/// Options beyond the scheme.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    /// Interior interpolant samples per step at which guards are checked (grazing detection);
    /// `None`: 1 for RK4 (short fixed steps), 2 for Dormand–Prince.
    pub grazing_samples: Option<usize>,
    /// Most consecutive accumulating events (each within [`Options::zeno_interval`] of the
    /// previous, or at the same instant) before the accumulation is ended by
    /// [`HybridSystem::zeno_fallback`](crate::HybridSystem::zeno_fallback) or [`SolverError::Zeno`].
    pub max_events_without_progress: usize,
    /// An event that follows the previous one within this fraction of the step-size scale (the
    /// step the error control would take next, at most [`HybridSystem::max_step`](crate::HybridSystem::max_step), for
    /// Dormand–Prince; the grid step for RK4) counts as accumulating. Relative to the dynamics'
    /// own time scale, not to the absolute time. Default `1e-3`: a sequence of such events cannot
    /// be resolved motion (the error control would have shortened the steps).
    pub zeno_interval: f64,
    /// Most trial steps (rejected and event steps included) spent approaching one `tstop`
    /// (consecutive [`Integrator::step`](crate::Integrator::step) calls with the same `tstop`; checked at the start of
    /// each call, so the rejections of one call may exceed it slightly) before
    /// [`SolverError::StepBudget`]. `None`: derived from the request,
    /// [`BASE_STEP_BUDGET`]` + 64 * (tstop - t) / h_char` with `h_char` the RK4 step or the
    /// system's [`HybridSystem::max_step`](crate::HybridSystem::max_step) (no second term when that is unlimited).
    pub max_steps: Option<u64>,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            grazing_samples: None,
            max_events_without_progress: 64,
            zeno_interval: 1e-3,
            max_steps: None,
        }
    }
}
