//! Errors of the physics layer: every message names the field or the geometric defect and by how
//! much it misses.

/// Physical input that cannot describe a working gear pair.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PhysicsError {
    /// A parameter outside its range.
    #[error("invalid pair.{field} = {}: allowed {allowed}", geardyn_model::error::num(*.value))]
    Invalid {
        /// Field name as in the `[pair]` table.
        field: String,
        /// Rejected value (in the config's units).
        value: f64,
        /// Allowed range.
        allowed: String,
    },
    /// An impossible or unsupported geometry.
    #[error("impossible gear geometry: {0}")]
    Geometry(String),
}
