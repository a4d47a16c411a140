//! Time-history simulation of any [`GearSystem`] (the single pair, a train, a system of your
//! own): the integrator settings ([`Method`], [`SimOptions`]) and [`simulate`], which records
//! what [`crate::record`] describes. The motion summary (period, `n-p-q-r-s` label, healthy
//! flag, P_ID of docs/model.md §5) is [`crate::summary`].

use crate::driver::{run_periods, Discard};
use crate::record::Recorder;
use geardyn_model::GearSystem;
use geardyn_solvers::{Integrator, Scheme, SolverError};
use serde::{Deserialize, Serialize};

pub use crate::record::{
    Amplitudes, Crossing, EventRecord, Level, MeshRecord, SimResult, Strobe, TrajectoryPoint,
    MIN_SAMPLES_PER_NATURAL_PERIOD,
};
pub use crate::summary::{
    health_text, summarize, summarize_orbit, summarize_tol, MeshSummary, Summary,
};

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

    /// The solver scheme for `sys` (a fixed step is stated per mesh cycle).
    pub fn scheme<S: GearSystem<N>, const N: usize>(&self, sys: &S) -> Scheme {
        match *self {
            Method::Dopri { rtol, atol } => Scheme::DormandPrince { rtol, atol },
            Method::Rk4 { steps_per_cycle } => Scheme::Rk4 {
                h: sys.mesh_cycle_time() / steps_per_cycle.max(1) as f64,
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
    /// Memory of the start mode ([`geardyn_solvers::HybridSystem::memory`]: the hysteresis factor of a
    /// dissipative contact law's impact in progress): that of the run this one continues
    /// ([`SimResult::final_memory`]), 0 for a fresh start (a start in contact is no impact).
    #[serde(skip_serializing_if = "is_zero", default)]
    pub start_memory: f64,
    /// Decision horizon (excitation periods, counted from the start of the run): a motion whose
    /// top Lyapunov exponent is positive is followed this long before it is called chaotic
    /// ([`crate::classify`]; default [`crate::verdict::DECISION_PERIODS`]).
    pub decision_periods: u64,
    /// Work budget of one run's decision (right-hand-side evaluations in all, from the start of
    /// the run): a run whose motion is still not periodic when the budget is spent is `unsettled`,
    /// never chaotic (default [`crate::verdict::DECISION_BUDGET`]).
    pub decision_budget: u64,
    /// Resolution of a decision's *follow* (the transients of the persistence blocks, which
    /// record nothing: [`crate::pair_engine::follow_method`]): fixed-step RK4 steps per natural
    /// period (`2 pi` of dimensionless time); 0 follows with [`SimOptions::method`] itself.
    /// Default [`crate::verdict::FOLLOW_STEPS`].
    #[serde(default = "default_follow_steps")]
    pub follow_steps: u32,
    /// The ensemble escape test that decides a positive exponent ([`crate::escape`]; `copies` =
    /// 0 follows the run's own trajectory to the decision horizon instead).
    #[serde(default)]
    pub escape: crate::escape::EscapeSettings,
    /// Record the stroboscopic points only (no statistics, forces, events or mesh-cycle strobe;
    /// `x_range` from the points): the cheap record of a decision's persistence blocks, whose only
    /// question is whether a period has appeared ([`crate::verdict`]). Not an option of the
    /// commands.
    #[serde(skip)]
    pub strobe_only: bool,
}

fn default_follow_steps() -> u32 {
    crate::verdict::FOLLOW_STEPS
}

fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

impl SimOptions {
    /// The default settings but fixed-step RK4 of `steps_per_cycle` steps per mesh cycle,
    /// `transient` then `record` periods.
    pub fn rk4(steps_per_cycle: u32, transient: u64, record: u64) -> Self {
        SimOptions {
            method: Method::Rk4 { steps_per_cycle },
            transient_periods: transient,
            record_periods: record,
            ..Default::default()
        }
    }
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
            decision_periods: crate::verdict::DECISION_PERIODS,
            decision_budget: crate::verdict::DECISION_BUDGET,
            follow_steps: crate::verdict::FOLLOW_STEPS,
            escape: crate::escape::EscapeSettings::default(),
            strobe_only: false,
        }
    }
}

/// Failure of a simulation.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SimError {
    /// The integrator failed.
    #[error(transparent)]
    Solver(#[from] SolverError),
    /// A setting or a system the run cannot take (named, with what is allowed).
    #[error("bad {field} {value}: allowed {allowed}")]
    Setting {
        /// The setting.
        field: &'static str,
        /// Its value.
        value: String,
        /// What is allowed.
        allowed: &'static str,
    },
}

/// Checks what every run needs of its system: at least one mesh.
pub(crate) fn check_system<S: GearSystem<N>, const N: usize>(sys: &S) -> Result<(), SimError> {
    if sys.mesh_count() == 0 {
        return Err(SimError::Setting {
            field: "mesh_count",
            value: "0".into(),
            allowed: "at least one mesh (GearSystem::mesh_count)",
        });
    }
    Ok(())
}

/// Integrates `sys` from `y0` at `opts.tau0`: `transient_periods` excitation periods discarded,
/// `record_periods` recorded.
///
/// ```
/// use geardyn_analysis::simulate::{simulate, summarize, SimOptions};
/// let model = geardyn_model::MeshModel::new(&geardyn_model::presets::classic()).unwrap();
/// let opts = SimOptions { transient_periods: 200, record_periods: 20, ..Default::default() };
/// let res = simulate(&model, [0.0, 0.0], &opts).unwrap();
/// assert_eq!(summarize(&model, &res, &opts).period, 1);
/// ```
pub fn simulate<S: GearSystem<N>, const N: usize>(
    sys: &S,
    y0: [f64; N],
    opts: &SimOptions,
) -> Result<SimResult<N>, SimError> {
    check_system(sys)?;
    let mut integ = Integrator::new(sys, opts.method.scheme(sys), opts.tau0, y0)?
        .with_memory(opts.start_memory);
    let period = sys.excitation_period();
    run_periods(&mut integ, period, opts.transient_periods, &mut Discard)?;
    let traj_from = opts.record_periods.saturating_sub(opts.trajectory_periods);
    let mut rec = Recorder::new(
        sys,
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
    res.final_memory = sys.memory(integ.mode());
    Ok(res)
}
