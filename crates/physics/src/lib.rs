//! Spur gear pair physics (docs/model.md §1–3): involute geometry of external and internal pairs,
//! time-varying mesh stiffness by the potential-energy method, localized tooth breakage, load
//! sharing, friction arms and friction factors, and the normalisation that turns a dimensional
//! pair into the dimensionless [`geardyn_model::MeshModel`] tables.
//!
//! SI units throughout the API (m, rad, N, Pa, kg); the config table `[pair]` uses mm, degrees
//! and GPa and says so in its field names.
#![warn(missing_docs)]
// `!(v > 0.0)` is deliberate: it rejects NaN along with the out-of-range values.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
#![allow(clippy::manual_range_contains)]

pub mod breakage;
pub mod error;
pub mod geometry;
pub mod lubrication;
pub mod mesh_stiffness;
pub mod pair;
pub mod planetary;
pub mod presets;
pub mod tooth;

pub use error::PhysicsError;
pub use pair::{OperatingPoint, PairModel, PairSpec};
