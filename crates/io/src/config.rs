//! Run configuration: the dimensionless model plus simulation settings, read from TOML, a preset,
//! and `NAME=VALUE` overrides. The resolved configuration is echoed into every output folder.

use geardyn_analysis::simulate::{Method, SimOptions};
use geardyn_model::{presets, MeshModel, ModelError, ModelParams};
use geardyn_physics::{PairModel, PairSpec, PhysicsError};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Integrator settings as written in a config file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SimulationConfig {
    /// `"dopri"` (adaptive Dormand–Prince 5(4)) or `"rk4"` (fixed step).
    pub method: String,
    /// Relative tolerance (dopri).
    pub rtol: f64,
    /// Absolute tolerance (dopri).
    pub atol: f64,
    /// Steps per mesh cycle (rk4).
    pub steps_per_cycle: u32,
    /// Excitation periods discarded as transient.
    pub transient_periods: u64,
    /// Excitation periods recorded.
    pub record_periods: u64,
    /// Initial displacement `x0`.
    pub x0: f64,
    /// Initial velocity `v0`.
    pub v0: f64,
    /// Start time `tau0` (sets the stroboscopic phase).
    pub tau0: f64,
}

impl Default for SimulationConfig {
    fn default() -> Self {
        SimulationConfig {
            method: "dopri".into(),
            rtol: 1e-9,
            atol: 1e-12,
            steps_per_cycle: 512,
            transient_periods: 300,
            record_periods: 100,
            x0: 0.0,
            v0: 0.0,
            tau0: 0.0,
        }
    }
}

/// A complete run configuration.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Config {
    /// Dimensionless model parameters (docs/model.md §1–3). With a `[pair]`, its stiffness, zones,
    /// breakage and friction come from the pair; the study parameters stay these.
    pub model: ModelParams,
    /// Optional dimensional gear pair (mm, deg, GPa).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pair: Option<PairSpec>,
    /// Simulation settings.
    #[serde(default)]
    pub simulation: SimulationConfig,
}

/// Configuration errors: each message names the field and what is allowed.
#[derive(Debug, thiserror::Error)]
pub enum ConfigError {
    /// A file could not be read.
    #[error("cannot read {path}: {source}")]
    Read {
        /// Path.
        path: String,
        /// Cause.
        source: std::io::Error,
    },
    /// Malformed TOML or a wrong field.
    #[error("malformed config {path}: {msg}")]
    Parse {
        /// Path.
        path: String,
        /// Parser message (names the key and line).
        msg: String,
    },
    /// A bad `NAME=VALUE` override.
    #[error("bad --set '{0}': expected NAME=VALUE with a number, e.g. omega=1.3")]
    SetSyntax(String),
    /// A simulation setting out of range.
    #[error("invalid simulation.{field} = {value}: allowed {allowed}")]
    Simulation {
        /// Field.
        field: &'static str,
        /// Value.
        value: String,
        /// Allowed values.
        allowed: &'static str,
    },
    /// A model parameter error.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// A physical pair error.
    #[error(transparent)]
    Physics(#[from] PhysicsError),
}

/// Names accepted by [`Config::set`] besides the model parameters.
pub const SIMULATION_NAMES: &[&str] = &[
    "x0",
    "v0",
    "tau0",
    "rtol",
    "atol",
    "steps_per_cycle",
    "transient_periods",
    "record_periods",
];

impl Config {
    /// The configuration of a built-in preset with default simulation settings.
    pub fn preset(name: &str) -> Result<Self, ConfigError> {
        let mut model = presets::by_name(name)?;
        let pair = geardyn_physics::presets::by_name(name);
        if pair.is_some() {
            // friction comes from the pair's friction arms
            model.friction = Default::default();
        }
        Ok(Config {
            model,
            pair,
            simulation: SimulationConfig::default(),
        })
    }

    /// Reads a TOML file.
    pub fn from_file(path: &Path) -> Result<Self, ConfigError> {
        let text = std::fs::read_to_string(path).map_err(|e| ConfigError::Read {
            path: path.display().to_string(),
            source: e,
        })?;
        Self::from_toml(&text).map_err(|e| match e {
            ConfigError::Parse { msg, .. } => ConfigError::Parse {
                path: path.display().to_string(),
                msg,
            },
            e => e,
        })
    }

    /// Parses TOML text.
    pub fn from_toml(text: &str) -> Result<Self, ConfigError> {
        toml::from_str(text).map_err(|e| ConfigError::Parse {
            path: "<text>".into(),
            msg: e.message().replace('\n', " ").to_string()
                + &e.span()
                    .map(|s| {
                        let line = text[..s.start].lines().count().max(1);
                        format!(" (line {line})")
                    })
                    .unwrap_or_default(),
        })
    }

    /// The resolved configuration as TOML, ready to edit.
    pub fn to_toml(&self) -> String {
        toml::to_string_pretty(self).expect("config serialises")
    }

    /// Applies one `NAME=VALUE` override.
    pub fn apply_set(&mut self, assignment: &str) -> Result<(), ConfigError> {
        let (name, value) = assignment
            .split_once('=')
            .ok_or_else(|| ConfigError::SetSyntax(assignment.into()))?;
        let value: f64 = value
            .trim()
            .parse()
            .map_err(|_| ConfigError::SetSyntax(assignment.into()))?;
        self.set(name.trim(), value)
    }

    /// Sets a model parameter or a simulation setting by name; `pair.FIELD` (and
    /// `pair.operating.FIELD`, `pair.breakage.FIELD`) set fields of the physical pair.
    pub fn set(&mut self, name: &str, value: f64) -> Result<(), ConfigError> {
        if let Some(field) = name.strip_prefix("pair.") {
            return self.set_pair(field, value);
        }
        let s = &mut self.simulation;
        let as_count = |v: f64| -> Result<u64, ConfigError> {
            if v >= 0.0 && v.fract() == 0.0 && v < 1e12 {
                Ok(v as u64)
            } else {
                Err(ConfigError::Simulation {
                    field: "count",
                    value: v.to_string(),
                    allowed: "a non-negative integer",
                })
            }
        };
        match name {
            "x0" => s.x0 = value,
            "v0" => s.v0 = value,
            "tau0" => s.tau0 = value,
            "rtol" => s.rtol = value,
            "atol" => s.atol = value,
            "steps_per_cycle" => s.steps_per_cycle = as_count(value)? as u32,
            "transient_periods" => s.transient_periods = as_count(value)?,
            "record_periods" => s.record_periods = as_count(value)?,
            _ => self.model.set(name, value).map_err(|e| match e {
                ModelError::UnknownParameter { name, known } => ModelError::UnknownParameter {
                    name,
                    known: format!("{known}, {}", SIMULATION_NAMES.join(", ")),
                }
                .into(),
                e => ConfigError::Model(e),
            })?,
        }
        Ok(())
    }

    fn set_pair(&mut self, field: &str, value: f64) -> Result<(), ConfigError> {
        let pair = self.pair.as_ref().ok_or_else(|| {
            ConfigError::Model(ModelError::Inconsistent {
                field: format!("pair.{field}"),
                reason: "this configuration has no [pair] (use the breakage or internal preset, or add one)".into(),
            })
        })?;
        let mut v = toml::Value::try_from(pair).expect("pair serialises");
        let parts: Vec<&str> = field.split('.').collect();
        if !set_path(&mut v, &parts, value) {
            return Err(ConfigError::SetSyntax(format!("pair.{field}={value}")));
        }
        let spec: PairSpec = v
            .try_into()
            .map_err(|e: toml::de::Error| ConfigError::Parse {
                path: "--set".into(),
                msg: format!("pair.{field}: {}", e.message()),
            })?;
        self.pair = Some(spec);
        Ok(())
    }

    /// The physical pair model, if the configuration has a `[pair]`.
    pub fn pair_model(&self) -> Result<Option<PairModel>, ConfigError> {
        Ok(match &self.pair {
            Some(p) => Some(p.build()?),
            None => None,
        })
    }

    /// The dimensionless parameters the model is built from (tables filled from the pair).
    pub fn effective_params(&self) -> Result<ModelParams, ConfigError> {
        let mut p = self.model.clone();
        if let Some(pm) = self.pair_model()? {
            pm.apply(&mut p);
        }
        Ok(p)
    }

    /// Validates everything and builds the model.
    pub fn build_model(&self) -> Result<MeshModel, ConfigError> {
        self.sim_options()?;
        Ok(MeshModel::new(&self.effective_params()?)?)
    }

    /// Simulation options (validated).
    pub fn sim_options(&self) -> Result<SimOptions, ConfigError> {
        let s = &self.simulation;
        let method = match s.method.as_str() {
            "dopri" => {
                if !(s.rtol > 0.0 && s.rtol < 1.0) {
                    return Err(ConfigError::Simulation {
                        field: "rtol",
                        value: s.rtol.to_string(),
                        allowed: "(0, 1)",
                    });
                }
                if !(s.atol > 0.0 && s.atol.is_finite()) {
                    return Err(ConfigError::Simulation {
                        field: "atol",
                        value: s.atol.to_string(),
                        allowed: "(0, inf)",
                    });
                }
                Method::Dopri {
                    rtol: s.rtol,
                    atol: s.atol,
                }
            }
            "rk4" => {
                if !(8..=1_000_000).contains(&s.steps_per_cycle) {
                    return Err(ConfigError::Simulation {
                        field: "steps_per_cycle",
                        value: s.steps_per_cycle.to_string(),
                        allowed: "8 ..= 1000000",
                    });
                }
                Method::Rk4 {
                    steps_per_cycle: s.steps_per_cycle,
                }
            }
            other => {
                return Err(ConfigError::Simulation {
                    field: "method",
                    value: other.into(),
                    allowed: "\"dopri\" or \"rk4\"",
                })
            }
        };
        for (f, v) in [("x0", s.x0), ("v0", s.v0), ("tau0", s.tau0)] {
            if !v.is_finite() {
                return Err(ConfigError::Simulation {
                    field: f,
                    value: v.to_string(),
                    allowed: "a finite number",
                });
            }
        }
        if s.record_periods == 0 {
            return Err(ConfigError::Simulation {
                field: "record_periods",
                value: "0".into(),
                allowed: ">= 1",
            });
        }
        Ok(SimOptions {
            method,
            transient_periods: s.transient_periods,
            record_periods: s.record_periods,
            trajectory: false,
            samples_per_cycle: 128,
            trajectory_periods: u64::MAX,
            tau0: s.tau0,
            max_period: 32,
        })
    }
}

/// Sets `value` at a dotted path of a TOML table, creating intermediate tables; integers stay
/// integers when the value is whole.
fn set_path(v: &mut toml::Value, parts: &[&str], value: f64) -> bool {
    let Some(table) = v.as_table_mut() else {
        return false;
    };
    match parts {
        [] => false,
        [last] => {
            let new = match table.get(*last) {
                Some(toml::Value::Integer(_)) if value.fract() == 0.0 => {
                    toml::Value::Integer(value as i64)
                }
                _ => toml::Value::Float(value),
            };
            table.insert(last.to_string(), new);
            true
        }
        [first, rest @ ..] => {
            let child = table
                .entry(first.to_string())
                .or_insert_with(|| toml::Value::Table(Default::default()));
            set_path(child, rest, value)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets_round_trip_through_toml() {
        for (name, _) in presets::PRESETS {
            let c = Config::preset(name).unwrap();
            let back = Config::from_toml(&c.to_toml()).unwrap();
            assert_eq!(c, back, "{name}");
            back.build_model().unwrap();
        }
    }

    #[test]
    fn errors_name_the_field() {
        let mut c = Config::preset("classic").unwrap();
        let e = c.apply_set("omgea=1").unwrap_err().to_string();
        assert!(e.contains("omgea") && e.contains("omega"), "{e}");
        assert!(c.apply_set("omega").is_err());
        assert!(c.apply_set("omega=abc").is_err());
        c.apply_set("D=-1").unwrap();
        let e = c.build_model().unwrap_err().to_string();
        assert!(e.contains("D_d") && e.contains("(0, inf)"), "{e}");
        let e = Config::from_toml("[model]\nomega = \"fast\"")
            .unwrap_err()
            .to_string();
        assert!(e.contains("malformed"), "{e}");
        let mut t = Config::preset("classic").unwrap().to_toml();
        t = t.replace("omega = 0.8", "omega = 0.8\nomegaa = 1.0");
        let e = Config::from_toml(&t).unwrap_err().to_string();
        assert!(e.contains("omegaa"), "{e}");
    }
}
