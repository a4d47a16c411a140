//! Errors of model construction.

/// A model parameter outside its allowed range, or an unknown parameter name.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModelError {
    /// A parameter value outside its range.
    #[error("invalid {field} = {}: allowed {allowed}", crate::error::num(*.value))]
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

/// A number for an error message: plain for ordinary magnitudes, scientific for tiny or huge
/// ones (so `1e-300` is not printed with 300 digits).
pub fn num(v: f64) -> String {
    if v == 0.0 || !v.is_finite() || (1e-4..1e9).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
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
