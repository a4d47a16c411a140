//! Errors of a train's description: each names the field (as written in the description's
//! TOML, e.g. `mesh[2].gears`) and what it may be.

/// A description that cannot make a working train.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TrainError {
    /// A field outside its range.
    #[error("invalid {field} = {value}: allowed {allowed}")]
    Invalid {
        /// The field, e.g. `body[3].inertia_kgm2` or `stage.planets`.
        field: String,
        /// The rejected value as written.
        value: String,
        /// What the field may be.
        allowed: String,
    },
    /// A `--set` name the train does not have.
    #[error("unknown --set {field}: allowed {allowed}")]
    Unknown {
        /// The name given.
        field: String,
        /// The names it may be.
        allowed: String,
    },
    /// The pair physics refused a mesh's gear pair (the message names the pair).
    #[error("{mesh}: {error}")]
    Pair {
        /// The mesh or preset field group, e.g. `sun-planet pair`.
        mesh: String,
        /// The pair's error (printed here, not chained: it would print twice).
        error: geardyn_physics::PhysicsError,
    },
    /// The bodies, meshes and shafts do not make a train that turns with one input: the input
    /// does not reach the output, or the train has free or locked motions.
    #[error("{0}")]
    Kinematics(String),
    /// A description that is not valid TOML or has unknown fields.
    #[error("{0}")]
    Parse(String),
}

/// An [`TrainError::Invalid`] for `field`.
pub fn invalid(
    field: impl Into<String>,
    value: impl ToString,
    allowed: impl Into<String>,
) -> TrainError {
    TrainError::Invalid {
        field: field.into(),
        value: value.to_string(),
        allowed: allowed.into(),
    }
}
