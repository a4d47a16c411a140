//! Nonlinear analyses of geardyn: the generic driving loop with observers, time-history
//! simulation of the gear model with its recorders, period detection and motion labels.
//!
//! Units are those of the model: dimensionless time `tau`, displacement in `b_c`.
#![warn(missing_docs)]

pub mod attractor;
pub mod basins;
pub mod bifurcation;
pub mod classify;
pub mod continuation;
pub mod driver;
pub mod engine;
pub mod escape;
pub mod generic;
pub mod grid;
pub mod identify;
pub mod indicators;
pub mod lane_plan;
pub mod lanes;
pub mod lanes_decide;
pub mod lanes_identify;
pub mod lanes_tle;
pub mod lyapunov;
pub mod lyapunov_request;
pub mod map2d;
pub mod orbit_branches;
pub mod orbits;
pub mod orbits_request;
pub mod pair_engine;
pub mod period;
mod ranges;
pub mod record;
pub mod signals;
pub mod simulate;
pub mod simulation;
pub mod spectrum;
pub mod stage_signals;
pub mod summary;
mod sweep_settings;
pub mod tle_convergence;
pub mod verdict;
pub mod work;

pub use classify::{
    simulate_decided, simulate_decided_from, simulate_decided_with, Decide, Motion,
};
pub use driver::{run_periods, Discard, Observer};
pub use simulate::{simulate, summarize, Method, SimOptions, SimResult, Summary};

/// Stop requests (Ctrl-C): see [`geardyn_solvers::cancel`].
pub use geardyn_solvers::cancel;
