//! geardyn: nonlinear dynamics of spur gear pairs.
//!
//! This facade re-exports the workspace crates under short names:
//! [`solvers`] (hybrid-system trait, event-aware integrators), [`model`] (dimensionless mesh model,
//! contact laws, presets, reference systems), [`analysis`] (simulation, sections, labels,
//! Lyapunov exponents, sweeps) and [`io`] (config, CSV/JSON, plots).
//!
//! ```
//! use geardyn::{analysis::simulate, model};
//! let m = model::MeshModel::new(&model::presets::classic()).unwrap();
//! let opts = simulate::SimOptions { transient_periods: 100, record_periods: 10, ..Default::default() };
//! let res = simulate::simulate(&m, [0.0, 0.0], &opts).unwrap();
//! assert_eq!(res.strobe.len(), 10);
//! ```
pub use geardyn_analysis as analysis;
pub use geardyn_io as io;
pub use geardyn_model as model;
pub use geardyn_solvers as solvers;
