//! geardyn: nonlinear dynamics of spur gear pairs.
//!
//! This facade re-exports the workspace crates under short names — [`solvers`] (hybrid-system
//! trait, event-aware integrators, the lockstep lanes), [`physics`] (involute geometry, mesh
//! stiffness, breakage, friction), [`scenario`] (a preset or configuration with overrides → the
//! model that is integrated), [`model`] (dimensionless mesh model, contact laws, presets,
//! reference systems), [`analysis`] (simulation, decided classification, sections, labels,
//! Lyapunov exponents, sweeps, basins, continuation, maps), [`exec`] (every analysis a job: the
//! executor, requests, stores, shards) and [`io`] (configuration,
//! CSV/JSON/NPY, figures) — and gathers what a Rust caller needs in [`prelude`].
//!
//! ```
//! use geardyn::prelude::*;
//! // the built-in default pair with one override, as `geardyn simulate --set omega=0.8`
//! let mut cfg = Config::preset("classic").unwrap();
//! cfg.set("omega", 0.8).unwrap();
//! let scenario = cfg.resolve().unwrap();
//! let opts = SimOptions { transient_periods: 200, record_periods: 10, ..Default::default() };
//! let (_, summary, _) =
//!     simulate_decided(scenario.model(), [0.0, 0.0], &opts, Decide::default()).unwrap();
//! assert!(summary.motion.is_periodic());
//! assert_eq!(summary.period, 1);
//! ```
pub use geardyn_analysis as analysis;
pub use geardyn_exec as exec;
pub use geardyn_io as io;
pub use geardyn_model as model;
pub use geardyn_physics as physics;
pub use geardyn_scenario as scenario;
pub use geardyn_solvers as solvers;

/// What a Rust caller of geardyn needs most: a scenario from a preset or a configuration, the
/// requests that check what to compute, the executor that runs them (resumable, observed), the
/// analyses with their options, and their results.
pub mod prelude {
    pub use geardyn_analysis::attractor::IdentifyRequest;
    pub use geardyn_analysis::attractor::{
        decide_gear, describe_gear, Descriptor, IdentifyOptions, Recordable,
    };
    pub use geardyn_analysis::basins::{basins, Axis, BasinOptions, BasinResult, BasinsRequest};
    pub use geardyn_analysis::bifurcation::{
        linspace, run_sweep, Section, SweepMode, SweepOptions, TaskResult,
    };
    pub use geardyn_analysis::classify::{simulate_decided, Decide, Motion};
    pub use geardyn_analysis::continuation::continuation_of;
    pub use geardyn_analysis::continuation::{
        continuation, ContinuationOptions, ContinuationResult,
    };
    pub use geardyn_analysis::engine::Engine;
    pub use geardyn_analysis::generic::{decided_sweep, Family};
    pub use geardyn_analysis::grid::Slice;
    pub use geardyn_analysis::lyapunov_request::{LyapunovReport, LyapunovRequest, TleMethod};
    pub use geardyn_analysis::map2d::{map2d, MapCell, MapOptions};
    pub use geardyn_analysis::orbits::{describe_orbit, find_orbit, OrbitOptions};
    pub use geardyn_analysis::orbits_request::OrbitsRequest;
    pub use geardyn_analysis::simulate::{simulate, Method, SimOptions, SimResult, Summary};
    pub use geardyn_analysis::simulate::{summarize, SimError};
    pub use geardyn_analysis::simulation::{Run, Simulation};
    pub use geardyn_exec::request::{
        BifurcationRequest, ContinuationRequest, MapRequest, SweepSpec,
    };
    pub use geardyn_exec::{
        execute, BasinsJob, Checkpointed, ContinuationJob, Job, MapJob, Observer, Progress, Store,
        SweepJob,
    };
    pub use geardyn_io::config::{Face, SimOverrides};
    pub use geardyn_io::Config;
    pub use geardyn_model::{presets, ContactState, EventKind, GearSystem, MeshModel};
    pub use geardyn_scenario::Scenario;
    pub use geardyn_solvers::{
        Direction, EventAction, Guards, HybridSystem, Scheme, SolverError, Variational,
    };
}

// The Rust example of README.md is compiled and run as a doctest of this crate.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;

// The Rust examples of docs/library.md, likewise.
#[cfg(doctest)]
#[doc = include_str!("../docs/library.md")]
struct LibraryDoctests;
