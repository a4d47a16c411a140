//! How the analyses integrate a system: the [`Engine`] a [`GearSystem`] runs on.
//!
//! The decisions (and what builds on them: decided sweeps, the description of an attractor of a
//! gear system) take `S: Engine<N>`; identification, basins and continuation take the
//! [`crate::attractor::Recordable`] systems, a single periodic orbit any `GearSystem<N>` with a
//! tangent space ([`crate::lyapunov::TangentSpace`]). The defaults integrate one trajectory at a
//! time with the requested integrator and compute exponents by the variational equation with
//! saltation ([`crate::lyapunov`]): correct for any system. A system with a faster engine
//! overrides them: the single pair runs its follows and exponents in the lockstep lanes
//! ([`crate::lanes`], [`crate::lanes_tle`]), which step its own mesh kernel.
//!
//! ```
//! use geardyn_analysis::engine::Engine;
//! use geardyn_analysis::simulate::SimOptions;
//! use geardyn_model::reference::TwoMassClearance;
//! // a system of your own runs on the scalar engine: nothing to write
//! let sys = TwoMassClearance::default();
//! assert_eq!(sys.follow_method(&SimOptions::default()), None);
//! ```

use crate::escape::{Copy, EscapeOutcome, EscapeSettings};
use crate::lyapunov::{LyapunovOptions, TangentSpace};
use crate::simulate::{simulate, Method, SimError, SimOptions, SimResult};
use geardyn_model::GearSystem;

/// The integration engine of a [`GearSystem`] (see the module doc).
pub trait Engine<const N: usize>: GearSystem<N> + TangentSpace<N> {
    /// The integrator of a decision's *follow* ([`crate::pair_engine::follow_method`]); `None`
    /// follows with the requested integrator. Default: `None` (a coarse follow is validated
    /// per kind of system, docs/analyses.md).
    fn follow_method(&self, _opts: &SimOptions) -> Option<Method> {
        None
    }

    /// A run of [`simulate`] with `o` inside a decision whose requested settings are
    /// `requested` (a follow may run on a faster engine that integrates the same way).
    /// Default: [`simulate`].
    fn simulate_in_decision(
        &self,
        y0: [f64; N],
        o: &SimOptions,
        _requested: &SimOptions,
    ) -> Result<SimResult<N>, SimError> {
        simulate(self, y0, o)
    }

    /// The ensemble escape test ([`crate::escape`]) of the motion continuing from `start`, with
    /// the settings `test` inside a decision of settings `opts`; `None` where this engine does not
    /// run it (the decision then follows the run's own trajectory to its horizon). Default: `None`
    /// (the test follows many copies: it wants an engine that advances them together).
    fn escape(
        &self,
        _opts: &SimOptions,
        _test: &EscapeSettings,
        _start: Copy<N>,
    ) -> Option<EscapeOutcome<N>> {
        None
    }

    /// Top Lyapunov exponent and its standard error of the motion continuing from `(t, y)` in a
    /// mode of memory `memory`, over `periods` excitation periods with the integrator of `opts`;
    /// `None` if it cannot be computed. Default: the variational equation with saltation
    /// ([`crate::lyapunov::tle_variational_with`]).
    fn tle(
        &self,
        opts: &SimOptions,
        t: f64,
        y: [f64; N],
        memory: f64,
        periods: u64,
    ) -> Option<(f64, f64)> {
        let lo = LyapunovOptions {
            period: self.excitation_period(),
            transient_periods: 0,
            periods,
            d0: 1e-6,
        };
        self.tle_variational_with(opts.method.scheme(self), t, y, memory, &lo, true)
            .ok()
            .filter(|r| r.tle.is_finite() && r.spread.is_finite())
            .map(|r| (r.tle, r.spread))
    }
}

impl Engine<4> for geardyn_model::reference::TwoMassClearance {}

/// A gear train's dynamic model runs every analysis on the default engine (no lanes yet).
impl<const N: usize> Engine<N> for geardyn_train::dynamics::TrainModel<N> where
    geardyn_train::dynamics::TrainModel<N>: TangentSpace<N>
{
}
