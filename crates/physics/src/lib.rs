//! Spur gear pair physics (MODEL.md §1–3): involute geometry of external and internal pairs,
//! time-varying mesh stiffness by the potential-energy method, localized tooth breakage, load
//! sharing, friction arms and friction factors, and the normalisation that turns a dimensional
//! pair into the dimensionless [`geardyn_model::MeshModel`] tables.
//!
//! SI units throughout the API (m, rad, N, Pa, kg); the config table `[pair]` uses mm, degrees
//! and GPa and says so in its field names.
#![warn(missing_docs)]

pub mod breakage;
pub mod error;
pub mod geometry;
pub mod mesh_stiffness;
pub mod pair;
pub mod tooth;

pub use error::PhysicsError;
pub use pair::{OperatingPoint, PairModel, PairSpec};
