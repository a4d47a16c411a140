//! Errors of model construction.

/// A model parameter outside its allowed range, or an unknown parameter name.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModelError {
    /// A parameter value outside its range.
    #[error("invalid {field} = {value}: allowed {allowed}")]
    Invalid {
        /// Dotted field name as in the config file (`back_side.R`, `D_d`, ...).
        field: String,
        /// The rejected value.
        value: f64,
        /// Allowed range, in words.
        allowed: String,
    },
    /// An inconsistent combination of parameters.
    #[error("invalid {field}: {reason}")]
    Inconsistent {
        /// Field name.
        field: String,
        /// What is wrong.
        reason: String,
    },
    /// An unknown parameter name (in `--set NAME=VALUE` or a sweep).
    #[error("unknown parameter '{name}': known are {known}")]
    UnknownParameter {
        /// The name given.
        name: String,
        /// Comma-separated list of known names.
        known: String,
    },
}

impl ModelError {
    pub(crate) fn invalid(field: &str, value: f64, allowed: &str) -> Self {
        ModelError::Invalid {
            field: field.to_string(),
            value,
            allowed: allowed.to_string(),
        }
    }
}

impl From<(&'static str, f64, &'static str)> for ModelError {
    fn from((f, v, a): (&'static str, f64, &'static str)) -> Self {
        ModelError::invalid(f, v, a)
    }
}
