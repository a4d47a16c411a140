//! Event-aware integrators for hybrid (non-smooth) dynamical systems.
//!
//! * [`HybridSystem`]: the public interface (vector field per mode, guards with crossing direction,
//!   resets, time breakpoints) that every geardyn integrator and analysis is generic over.
//! * [`Integrator`]: adaptive Dormand–Prince 5(4) or fixed-step RK4 ([`Scheme`]), stepping exactly
//!   onto breakpoints and locating state events on the dense output; [`Integrator::step`] returns
//!   why it stopped ([`Stop`]).
//! * [`forward_methods!`]: the body of an `impl Trait for &S` that forwards to `S` (or of a
//!   wrapper that forwards to the value it wraps).
//! * [`ensemble`]: the lockstep ensemble RK4 engine (`L` trajectories in structure-of-arrays
//!   lanes, events finished by the scalar integrator), for sweeps and basins.
//!
//! Time and state are in whatever units the system uses (geardyn's gear model is dimensionless).
#![warn(missing_docs)]
// Runge–Kutta stage formulas over several arrays read clearer with an index.
#![allow(clippy::needless_range_loop)]

pub mod cancel;
pub mod dense;
pub mod ensemble;
pub mod forward;
pub mod hybrid;
pub mod integrator;
pub mod rk4;
pub mod root;
pub mod scheme;
pub mod variational;

pub use dense::Step;
pub use hybrid::{Direction, EventAction, Guards, HybridSystem, MAX_GUARDS};
pub use integrator::{
    min_step, Integrator, Options, Scheme, SolverError, Stats, Stop, BASE_STEP_BUDGET,
};
pub use variational::Variational;
