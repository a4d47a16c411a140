//! The dimensionless multi-state spur-gear mesh model of geardyn (docs/model.md §2–4).
//!
//! * [`ModelParams`]: the dimensionless parameter set (config-file form, `--set` names).
//! * [`MeshModel`]: the validated, tabulated model; implements
//!   [`geardyn_solvers::HybridSystem`] with state `[x, x']` in units of `b_c` and `b_c*omega_n`,
//!   time `tau = omega_n*t`.
//! * [`MeshLanes`]: its batched counterpart (phase tables) for the lockstep ensemble RK4.
//! * [`mesh_kernel`]: the mesh force and its tangent terms, written once for both.
//! * [`ContactLaw`], [`ImpactLaw`]: drive/back-side contact laws and the back-side impact law.
//! * [`presets`]: `classic` (C1), `breakage`, `internal`.
//! * [`reference`](mod@reference): other hybrid systems (Duffing, Lorenz, impact oscillator) for tests and as
//!   templates.
#![warn(missing_docs)]
// `!(v > 0.0)` is deliberate: it rejects NaN along with the out-of-range values.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod contact_law;
pub mod error;
pub mod impact;
pub mod mesh_kernel;
pub mod mesh_lanes;
pub mod mesh_model;
pub mod params;
pub mod phase;
pub mod presets;
pub mod reference;
pub mod system;

pub use contact_law::{johnson_exponent, ContactLaw};
pub use error::ModelError;
pub use impact::ImpactLaw;
pub use mesh_lanes::{MeshLane, MeshLaneBlock, MeshLanes};
pub use mesh_model::{ContactState, EventKind, MeshMode, MeshModel, Segment, Zone};
pub use params::{
    BackSide, Breakage, Friction, ModelParams, StiffnessForm, ZonePiece, PARAMETER_NAMES,
};
pub use system::GearSystem;
