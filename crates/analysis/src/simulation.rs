//! One run of a gear system stated in one expression:
//! `Simulation::new(&sys, y0).solver(..).record(..).decide(..).decided()`.
//!
//! The builder groups what [`SimOptions`] holds by role — the **solver** (integrator, start time
//! and memory), the **record** (transient, recorded periods, trajectory) and the **decision**
//! (whether and how long a motion is followed before it is called chaotic, the work budget, the
//! follow's resolution) — and ends in one of three questions: the record and its summary by the
//! period test alone ([`Simulation::run`]: the decision settings are not used), the decided
//! motion ([`Simulation::decided`]) or the top Lyapunov exponent ([`Simulation::tle`]). It is the same code as [`simulate`],
//! [`simulate_decided`] and [`Engine::tle`] with the same settings.
//!
//! ```
//! use geardyn_analysis::simulation::Simulation;
//! use geardyn_analysis::simulate::Method;
//! use geardyn_model::reference::TwoMassClearance;
//! let sys = TwoMassClearance { load: [2.0, 1.0], ..Default::default() };
//! let run = Simulation::new(&sys, [2.0, 0.0, 0.0, 0.0])
//!     .solver(Method::Rk4 { steps_per_cycle: 256 })
//!     .record(200, 20)
//!     .decided()
//!     .unwrap();
//! assert_eq!(run.summary.label, "1-0-0 1-0-0"); // both meshes in contact throughout
//! ```

use crate::classify::{simulate_decided, Decide};
use crate::engine::Engine;
use crate::simulate::{simulate, summarize, Method, SimError, SimOptions, SimResult, Summary};

/// A run being stated (see the module doc).
#[derive(Clone, Debug)]
pub struct Simulation<'s, S, const N: usize> {
    sys: &'s S,
    y0: [f64; N],
    opts: SimOptions,
    how: Decide,
}

/// What a run gives: its record, the summary of the record and the settings it was recorded
/// with (a decided run may have extended its transient).
#[derive(Clone, Debug)]
pub struct Run<const N: usize> {
    /// The record.
    pub result: SimResult<N>,
    /// Its summary (decided by [`Simulation::decided`], else the period test only).
    pub summary: Summary,
    /// The settings of the record.
    pub used: SimOptions,
}

impl<'s, S: Engine<N>, const N: usize> Simulation<'s, S, N> {
    /// A run of `sys` from `y0` with the default settings ([`SimOptions::default`]).
    pub fn new(sys: &'s S, y0: [f64; N]) -> Self {
        Simulation {
            sys,
            y0,
            opts: SimOptions::default(),
            how: Decide::default(),
        }
    }

    /// All settings at once (a configuration's, say).
    pub fn options(mut self, opts: SimOptions) -> Self {
        self.opts = opts;
        self
    }

    /// The integrator.
    pub fn solver(mut self, method: Method) -> Self {
        self.opts.method = method;
        self
    }

    /// Start time `tau0` (the stroboscopic phase) and the memory of the start mode (the
    /// hysteresis factor of an impact in progress; 0 for a fresh start).
    pub fn start(mut self, tau0: f64, memory: f64) -> Self {
        self.opts.tau0 = tau0;
        self.opts.start_memory = memory;
        self
    }

    /// Excitation periods discarded as transient, then recorded.
    pub fn record(mut self, transient: u64, record: u64) -> Self {
        self.opts.transient_periods = transient;
        self.opts.record_periods = record;
        self
    }

    /// Keep the trajectory of the last `periods` recorded periods, `samples_per_cycle` samples
    /// per mesh cycle (at least).
    pub fn trajectory(mut self, samples_per_cycle: u32, periods: u64) -> Self {
        self.opts.trajectory = true;
        self.opts.samples_per_cycle = samples_per_cycle;
        self.opts.trajectory_periods = periods;
        self
    }

    /// The decision: horizon (excitation periods a positive exponent is followed before the
    /// motion is called chaotic), work budget (right-hand-side evaluations) and the follow's
    /// resolution (RK4 steps per natural period; 0: the requested integrator).
    pub fn decide(mut self, horizon: u64, budget: u64, follow_steps: u32) -> Self {
        self.opts.decision_periods = horizon;
        self.opts.decision_budget = budget;
        self.opts.follow_steps = follow_steps;
        self
    }

    /// Which evidence a decision may gather (transient extensions, the exponent).
    pub fn evidence(mut self, how: Decide) -> Self {
        self.how = how;
        self
    }

    /// The settings as they stand.
    pub fn settings(&self) -> &SimOptions {
        &self.opts
    }

    /// The record and its summary ([`simulate`], [`summarize`]).
    pub fn run(self) -> Result<Run<N>, SimError> {
        let result = simulate(self.sys, self.y0, &self.opts)?;
        let summary = summarize(self.sys, &result, &self.opts);
        Ok(Run {
            result,
            summary,
            used: self.opts,
        })
    }

    /// The decided motion ([`simulate_decided`]: period test, persistence of a positive
    /// exponent to the horizon, budget).
    pub fn decided(self) -> Result<Run<N>, SimError> {
        let (result, summary, used) = simulate_decided(self.sys, self.y0, &self.opts, self.how)?;
        Ok(Run {
            result,
            summary,
            used,
        })
    }

    /// Top Lyapunov exponent and its standard error over `periods` excitation periods after the
    /// transient ([`Engine::tle`]); `None` if it cannot be computed.
    pub fn tle(self, periods: u64) -> Result<Option<(f64, f64)>, SimError> {
        let head = SimOptions {
            record_periods: 0,
            ..self.opts
        };
        let r = simulate(self.sys, self.y0, &head)?;
        let (t, y) = r.final_state;
        Ok(self.sys.tle(&self.opts, t, y, r.final_memory, periods))
    }
}
