//! Run configuration: the dimensionless model plus simulation settings, read from TOML, a preset,
//! and `NAME=VALUE` overrides. The resolved configuration is echoed into every output folder.

use geardyn_analysis::simulate::{Method, SimOptions};
use geardyn_model::{presets, ContactLaw, ModelError, ModelParams};
use geardyn_physics::{PairSpec, PhysicsError};
use geardyn_scenario::{Scenario, ScenarioError, ScenarioSpec};
use serde::{Deserialize, Serialize};
use std::borrow::Cow;
use std::collections::BTreeMap;
use std::path::Path;

/// Integrator settings as written in a config file.
///
/// Every key is optional: a missing one takes its default ([`SimulationConfig::default`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
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
    /// Decision horizon (excitation periods from the start of a run) a motion with a positive
    /// Lyapunov exponent is followed before it is called chaotic.
    pub decision_periods: u64,
    /// Work budget of one run's decision (right-hand-side evaluations in all); a run still not periodic when it
    /// is spent is `unsettled`.
    pub decision_budget: u64,
    /// Resolution of a decision's follow (the transients of its persistence blocks, on models
    /// whose contact law the lanes step: `geardyn_analysis::pair_engine::follow_validated`): fixed-step RK4 steps per
    /// natural period; 0 follows with the requested integrator.
    pub follow_steps: u32,
    /// Copies of a chaotic state the ensemble escape test follows (0: no test; the motion is
    /// followed to the decision horizon instead).
    pub escape_copies: u32,
    /// Span of the escape test (excitation periods); 0: the copies' spread, then two decision horizons of copy-periods.
    pub escape_periods: u64,
    /// Cap on a command's estimated work (right-hand-side evaluations in all runs, the
    /// decisions' worst case included): a command above it is refused before it starts.
    pub max_work: f64,
}

impl Default for SimulationConfig {
    fn default() -> Self {
        SimulationConfig {
            method: "dopri".into(),
            rtol: geardyn_solvers::integrator::DEFAULT_RTOL,
            atol: geardyn_solvers::integrator::DEFAULT_ATOL,
            steps_per_cycle: geardyn_analysis::simulate::DEFAULT_RK4_STEPS_PER_CYCLE,
            transient_periods: 300,
            record_periods: 100,
            x0: 0.0,
            v0: 0.0,
            tau0: 0.0,
            decision_periods: geardyn_analysis::classify::DECISION_PERIODS,
            decision_budget: geardyn_analysis::classify::DECISION_BUDGET,
            follow_steps: geardyn_analysis::classify::FOLLOW_STEPS,
            escape_copies: geardyn_analysis::escape::ESCAPE_COPIES,
            escape_periods: geardyn_analysis::escape::ESCAPE_PERIODS,
            max_work: geardyn_analysis::work::DEFAULT_MAX_WORK,
        }
    }
}

/// A complete run configuration: the inputs of the one builder ([`geardyn_scenario`]) plus the
/// simulation settings.
///
/// With a physical `[pair]`, the `[model]` table holds only what the pair does not compute
/// (contact law, back side, and the operating point where the pair states none): the pair's
/// quantities are never written twice (docs/configuration.md).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Config {
    /// Dimensionless model parameters (docs/model.md §1–3).
    pub model: ModelParams,
    /// Optional dimensional gear pair (mm, deg, GPa).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pair: Option<PairSpec>,
    /// Dimensionless operating-point values that take precedence over the pair's physical
    /// operating point (`omega`, `F`, `xi`, `c`, `D_d`, `D_s`).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub set: BTreeMap<String, f64>,
    /// Simulation settings.
    #[serde(default)]
    pub simulation: SimulationConfig,
}

/// Configuration errors: each message names the field and what is allowed.
#[derive(Debug, thiserror::Error)]
pub enum ConfigError {
    /// A file could not be read.
    #[error("cannot read {path}: {cause}")]
    Read {
        /// Path.
        path: String,
        /// Cause (not chained, so that it is printed once).
        cause: std::io::Error,
    },
    /// A file larger than a configuration can be.
    #[error("{path} is not a configuration file: larger than {limit} bytes")]
    TooLarge {
        /// Path.
        path: String,
        /// Limit in bytes.
        limit: u64,
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
    /// A bad `--contact` value.
    #[error("bad --contact '{value}': {msg}; expected LAW[:EXPONENT[:RESTITUTION]] with LAW one of linear, power, hunt_crossley, lankarani_nikravesh, impact_damping (e.g. linear, power:1.5, lankarani_nikravesh:1.1:0.8)")]
    Contact {
        /// The value given.
        value: String,
        /// What is wrong.
        msg: String,
    },
    /// A field given both by an option (a command-line flag, a Python keyword) and by `--set`.
    #[error("{name} is given twice, by {by} and by {set}: give one of them")]
    Twice {
        /// Field.
        name: String,
        /// The option that gives it.
        by: String,
        /// The assignment that gives it too, as the caller wrote it (`--set NAME=VALUE`).
        set: String,
    },
    /// A command's estimated work above `simulation.max_work` ([`Config::check_work`]).
    #[error("{0}")]
    Work(String),
    /// A bad value of an option (a flag, a keyword), with the field's own message.
    #[error("bad {given}: {inner}")]
    Option {
        /// The option and its value as the caller wrote them (`--periods 0`, `periods=0`).
        given: String,
        /// What the field says of the value.
        inner: Box<ConfigError>,
    },
    /// A simulation setting out of range.
    #[error("invalid simulation.{field} = {value}: allowed {allowed}")]
    Simulation {
        /// Field.
        field: &'static str,
        /// Value.
        value: String,
        /// Allowed values.
        allowed: Cow<'static, str>,
    },
    /// A model parameter error.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// A physical pair error.
    #[error(transparent)]
    Physics(#[from] PhysicsError),
    /// A scenario (routing or resolution) error.
    #[error(transparent)]
    Scenario(#[from] ScenarioError),
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
    "decision_periods",
    "decision_budget",
    "follow_steps",
    "escape_copies",
    "escape_periods",
    "max_work",
];

/// A setting that is 0 (`zero`: what 0 means) or a whole number in `lo..=hi` (`unit`: what it
/// counts), checked.
fn zero_or_count(
    field: &'static str,
    v: f64,
    (lo, hi): (u64, u64),
    zero: &str,
    unit: &str,
) -> Result<u64, ConfigError> {
    if v == 0.0 || (v.fract() == 0.0 && v >= lo as f64 && v <= hi as f64) {
        Ok(v as u64)
    } else {
        Err(ConfigError::Simulation {
            field,
            value: geardyn_model::error::num(v),
            allowed: format!("0 ({zero}) or a whole number in [{lo}, {hi}] ({unit})").into(),
        })
    }
}

/// `simulation.escape_copies` checked: 0 (no escape test) or a whole number in
/// [`geardyn_analysis::escape::ESCAPE_COPIES_RANGE`].
fn escape_copies(v: f64) -> Result<u32, ConfigError> {
    let r = geardyn_analysis::escape::ESCAPE_COPIES_RANGE;
    let n = zero_or_count(
        "escape_copies",
        v,
        (u64::from(*r.start()), u64::from(*r.end())),
        "no escape test: follow the run to the decision horizon",
        "copies of a chaotic state",
    )?;
    Ok(n as u32)
}

/// `simulation.escape_periods` checked: 0 (the default span) or a whole number in
/// [`geardyn_analysis::escape::ESCAPE_PERIODS_RANGE`].
fn escape_periods(v: f64) -> Result<u64, ConfigError> {
    let r = geardyn_analysis::escape::ESCAPE_PERIODS_RANGE;
    zero_or_count(
        "escape_periods",
        v,
        (*r.start(), *r.end()),
        "the default: the copies' spread, then two decision horizons of copy-periods",
        "excitation periods of the escape test",
    )
}

/// `simulation.follow_steps` checked: 0 (follow with the requested integrator) or a whole number
/// in [`geardyn_analysis::classify::FOLLOW_STEPS_RANGE`].
fn follow_steps(v: f64) -> Result<u32, ConfigError> {
    let r = geardyn_analysis::classify::FOLLOW_STEPS_RANGE;
    let n = zero_or_count(
        "follow_steps",
        v,
        (u64::from(*r.start()), u64::from(*r.end())),
        "follow with the requested integrator",
        "RK4 steps per natural period",
    )?;
    Ok(n as u32)
}

/// Largest configuration file read (bytes): a config is a few kilobytes.
pub const MAX_CONFIG_BYTES: u64 = 1 << 20;

/// `[model]` keys a physical pair computes (never written with a pair).
const PAIR_MODEL_KEYS: &[&str] = &["eps", "stiffness", "breakage", "friction"];
/// `[model]` keys a pair's physical operating point states.
const OPERATING_MODEL_KEYS: &[&str] = &["omega", "F", "xi", "D_d", "D_s"];

/// Whether the `NAME=VALUE` assignment `set` (a `--set`) assigns the field `name`.
pub fn assigns(set: &str, name: &str) -> bool {
    set.split_once('=').is_some_and(|(n, _)| n.trim() == name)
}

fn parse_err(msg: impl Into<String>) -> ConfigError {
    ConfigError::Parse {
        path: "<text>".into(),
        msg: short_numbers(&msg.into()),
    }
}

/// `msg` with every number written out in more than 16 digits (the parser prints a float such as
/// 1e300 in full, 301 digits) rewritten in exponent form.
fn short_numbers(msg: &str) -> String {
    let mut out = String::with_capacity(msg.len());
    let mut rest = msg;
    while let Some(start) = rest.find(|c: char| c.is_ascii_digit()) {
        out.push_str(&rest[..start]);
        let tail = &rest[start..];
        let end = tail
            .find(|c: char| !(c.is_ascii_digit() || c == '.'))
            .unwrap_or(tail.len());
        let number = &tail[..end];
        let digits = number.chars().filter(char::is_ascii_digit).count();
        match number.trim_end_matches('.').parse::<f64>() {
            Ok(v) if digits > 16 => out.push_str(&format!("{v:e}")),
            _ => out.push_str(number),
        }
        rest = &tail[end..];
    }
    out.push_str(rest);
    out
}

impl Config {
    /// The configuration of a built-in preset with default simulation settings.
    pub fn preset(name: &str) -> Result<Self, ConfigError> {
        let spec = ScenarioSpec::preset(name)?;
        let c = Config {
            model: spec.model,
            pair: spec.pair,
            set: spec.overrides,
            simulation: SimulationConfig::default(),
        };
        // canonical form: what the pair states is held as the same placeholders a file gets
        Self::from_toml(&c.to_toml())
    }

    /// Reads a TOML file (at most [`MAX_CONFIG_BYTES`]).
    pub fn from_file(path: &Path) -> Result<Self, ConfigError> {
        use std::io::Read;
        let read_err = |e| ConfigError::Read {
            path: path.display().to_string(),
            cause: e,
        };
        // a FIFO or a device would block the open or never end: regular files only
        if !std::fs::metadata(path).map_err(read_err)?.is_file() {
            return Err(read_err(std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "not a regular file",
            )));
        }
        let f = std::fs::File::open(path).map_err(read_err)?;
        let mut bytes = Vec::new();
        f.take(MAX_CONFIG_BYTES + 1)
            .read_to_end(&mut bytes)
            .map_err(read_err)?;
        if bytes.len() as u64 > MAX_CONFIG_BYTES {
            return Err(ConfigError::TooLarge {
                path: path.display().to_string(),
                limit: MAX_CONFIG_BYTES,
            });
        }
        let text = String::from_utf8(bytes).map_err(|_| ConfigError::Parse {
            path: path.display().to_string(),
            msg: "not UTF-8 text".into(),
        })?;
        Self::from_toml(&text).map_err(|e| match e {
            ConfigError::Parse { msg, .. } => ConfigError::Parse {
                path: path.display().to_string(),
                msg,
            },
            e => e,
        })
    }

    /// Parses TOML text. With a `[pair]`, `[model]` must not state what the pair computes or
    /// what its physical operating point states (the error names the key to use instead).
    pub fn from_toml(text: &str) -> Result<Self, ConfigError> {
        let mut v: toml::Value = toml::from_str(text).map_err(|e| {
            parse_err(
                e.message().replace('\n', " ")
                    + &e.span()
                        .map(|s| {
                            let line = text[..s.start].matches('\n').count() + 1;
                            format!(" (line {line})")
                        })
                        .unwrap_or_default(),
            )
        })?;
        Self::check_unit_variants(&v)?;
        Self::fill_pair_placeholders(&mut v)?;
        // (through serde_path_to_error: serde's own message names the type, not the field)
        serde_path_to_error::deserialize(v).map_err(|e| {
            let path = e.path().to_string();
            let msg = e.into_inner().message().replace('\n', " ");
            let msg = msg.replace("expected f64", "expected a number");
            let msg = msg.replace("expected u64", "expected a whole number");
            let msg = msg.replace("expected u32", "expected a whole number");
            parse_err(if path.is_empty() || path == "." {
                msg
            } else {
                format!("{path}: {msg}")
            })
        })
    }

    /// Tables whose variant takes no parameters must not carry any: serde ignores unknown keys
    /// beside a unit variant's tag, which would silently drop e.g. `R = 0.5` under
    /// `model = "contact"`.
    fn check_unit_variants(v: &toml::Value) -> Result<(), ConfigError> {
        for (table, tag, unit) in [
            ("back_side", "model", "contact"),
            ("contact", "law", "linear"),
        ] {
            let Some(t) = v
                .get("model")
                .and_then(|m| m.get(table))
                .and_then(|t| t.as_table())
            else {
                continue;
            };
            if t.get(tag).and_then(|x| x.as_str()) == Some(unit) {
                if let Some(extra) = t.keys().find(|k| k.as_str() != tag) {
                    return Err(parse_err(format!(
                        "model.{table}.{extra}: {tag} = \"{unit}\" takes no parameters (remove {extra}, or choose another {tag})"
                    )));
                }
            }
        }
        Ok(())
    }

    /// With a pair, the `[model]` keys the pair states are absent from a file: refuse them if
    /// present, and fill in placeholders (never integrated: the pair replaces them).
    fn fill_pair_placeholders(v: &mut toml::Value) -> Result<(), ConfigError> {
        let Some(root) = v.as_table_mut() else {
            return Ok(());
        };
        let Some(pair) = root.get("pair").and_then(|p| p.as_table()).cloned() else {
            if root.contains_key("set") {
                return Err(parse_err(
                    "[set] overrides a physical operating point, but there is no [pair]: write the values under [model]",
                ));
            }
            return Ok(());
        };
        let operating = pair.contains_key("operating");
        let damping = pair.contains_key("damping_ratio");
        let placeholder = toml::Value::try_from(presets::classic()).expect("serialises");
        let model = root
            .entry("model")
            .or_insert_with(|| toml::Value::Table(Default::default()))
            .as_table_mut()
            .ok_or_else(|| parse_err("[model] must be a table"))?;
        let mut stated: Vec<&str> = PAIR_MODEL_KEYS.to_vec();
        if operating {
            stated.extend(OPERATING_MODEL_KEYS);
        }
        if damping {
            stated.push("c");
        }
        for key in stated {
            if model.contains_key(key) {
                let instead = match key {
                    "omega" => "pair.operating.speed_rpm, or omega under [set] to override it",
                    "F" => "pair.operating.torque_nm, or F under [set] to override it",
                    "xi" => "pair.operating.error_amplitude_um, or xi under [set] to override it",
                    "D_d" | "D_s" => {
                        "pair.operating.half_backlash_um, or D_d/D_s under [set] to override them"
                    }
                    "c" => "pair.damping_ratio, or c under [set] to override it",
                    "friction" => "pair.mu or pair.lubrication",
                    "breakage" => "pair.breakage",
                    _ => "the [pair] geometry and material",
                };
                return Err(parse_err(format!(
                    "model.{key} is stated by the physical [pair] of this file; remove it from [model] and use {instead}"
                )));
            }
            if key != "friction" && key != "breakage" {
                model.insert(key.to_string(), placeholder[key].clone());
            }
        }
        if let Some(set) = root.get("set").and_then(|s| s.as_table()) {
            for k in set.keys() {
                let ok = match k.as_str() {
                    "c" => damping,
                    "omega" | "F" | "xi" | "D_d" | "D_s" => operating,
                    _ => false,
                };
                if !ok {
                    return Err(parse_err(format!(
                        "set.{k}: [set] holds only operating-point keys that the pair states physically (omega, F, xi, D_d, D_s with [pair.operating]; c with pair.damping_ratio); write {k} under [model]"
                    )));
                }
            }
        }
        Ok(())
    }

    /// The resolved configuration as TOML, ready to edit (pair-stated keys are not repeated in
    /// `[model]`).
    pub fn to_toml(&self) -> String {
        toml::to_string_pretty(&self.to_value()).expect("config serialises")
    }

    /// The configuration as written by [`Config::to_toml`], as a TOML value.
    pub fn to_value(&self) -> toml::Value {
        let mut v = toml::Value::try_from(self).expect("config serialises");
        if let Some(pair) = &self.pair {
            let mut drop: Vec<&str> = PAIR_MODEL_KEYS.to_vec();
            if pair.operating.is_some() {
                drop.extend(OPERATING_MODEL_KEYS);
            }
            if pair.damping_ratio.is_some() {
                drop.push("c");
            }
            if let Some(m) = v.get_mut("model").and_then(|m| m.as_table_mut()) {
                for k in drop {
                    m.remove(k);
                }
            }
        }
        v
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

    /// Refuses, before any work, a command of `runs` runs of `model` with `sim` (`decided`: each
    /// run decided, with the decision's worst case) whose estimated work
    /// ([`geardyn_analysis::work`]) is above `simulation.max_work` — the one check of the CLI's
    /// commands and the Python module's calls.
    pub fn check_work(
        &self,
        model: &geardyn_model::MeshModel,
        sim: &SimOptions,
        runs: usize,
        decided: bool,
    ) -> Result<(), ConfigError> {
        let per_run = geardyn_analysis::work::per_run(model, sim, decided);
        geardyn_analysis::work::check(runs, per_run, self.simulation.max_work)
            .map(|_| ())
            .map_err(ConfigError::Work)
    }

    /// Sets `name` to `value` on behalf of option `by` (a command-line flag such as `--periods`, a
    /// Python keyword), refused when one of the assignments `sets` (`NAME=VALUE`, given as
    /// `via` says: `--set` on the command line) names the same field (which one should win would
    /// be a silent choice).
    pub fn set_by_option(
        &mut self,
        sets: &[String],
        via: &str,
        name: &str,
        by: &str,
        value: f64,
    ) -> Result<(), ConfigError> {
        if let Some(s) = sets.iter().find(|s| assigns(s, name)) {
            return Err(ConfigError::Twice {
                name: name.into(),
                by: by.into(),
                set: format!("{via}{s}"),
            });
        }
        self.set(name, value)
    }

    /// Replaces the contact law (`[model.contact]`: the drive flank, and the back flank when it is
    /// in continuous contact; a back side modelled by impacts keeps its impact law):
    /// `LAW[:EXPONENT[:RESTITUTION]]`, the fields of
    /// `[model.contact]` in order (`linear`, `power:1.5`, `lankarani_nikravesh:1.1:0.8`). The
    /// law is range-checked with the rest of the model by [`Config::resolve`].
    pub fn apply_contact(&mut self, value: &str) -> Result<(), ConfigError> {
        let err = |msg: String| ConfigError::Contact {
            value: value.into(),
            msg,
        };
        let mut parts = value.split(':').map(str::trim);
        let law = parts.next().unwrap_or_default();
        if law.is_empty() {
            return Err(err("no law name".into()));
        }
        if !law.chars().all(|c| c.is_ascii_lowercase() || c == '_') {
            return Err(err(format!(
                "'{law}' is not a law name (names are lower case, with '_')"
            )));
        }
        let mut toml_text = format!("law = \"{law}\"\n");
        for (field, part) in ["exponent", "restitution"].iter().zip(parts.by_ref()) {
            let v: f64 = part
                .parse()
                .map_err(|_| err(format!("{field} '{part}' is not a number")))?;
            if !v.is_finite() {
                return Err(err(format!("{field} {v} is not finite")));
            }
            toml_text.push_str(&format!("{field} = {v:?}\n"));
        }
        if parts.next().is_some() {
            return Err(err("more than three fields".into()));
        }
        let law_value: ContactLaw =
            toml::from_str(&toml_text).map_err(|e| err(e.message().to_string()))?;
        // a field the law does not have would otherwise be dropped without a word
        let back = toml::Value::try_from(law_value).map_err(|e| err(e.to_string()))?;
        let given = toml_text.lines().count() - 1;
        let kept = back.as_table().map_or(0, |t| t.len() - 1);
        if given > kept {
            let field = ["exponent", "restitution"][kept];
            return Err(err(format!("{law} has no {field}")));
        }
        self.model.contact = law_value;
        Ok(())
    }

    /// The builder inputs of this configuration.
    pub fn spec(&self) -> ScenarioSpec {
        ScenarioSpec {
            model: self.model.clone(),
            pair: self.pair.clone(),
            overrides: self.set.clone(),
        }
    }

    /// Validates everything and resolves the model that is integrated: the only way from a
    /// configuration to a model.
    pub fn resolve(&self) -> Result<Scenario, ConfigError> {
        self.sim_options()?;
        let sc = self.spec().resolve()?;
        // the initial state on the model's scale: beyond it a run only measures its own blow-up
        let scale = sc.params().d_single.max(1.0);
        let s = &self.simulation;
        for (field, v, lim) in [("x0", s.x0, 1e3 * scale), ("v0", s.v0, 1e3 * scale)] {
            if v.abs() > lim {
                return Err(ConfigError::Simulation {
                    field,
                    value: geardyn_model::error::num(v),
                    allowed: "|value| <= 1000 max(D_s, 1) (the model's length scale)".into(),
                });
            }
        }
        Ok(sc)
    }

    /// Sets a simulation setting, or a parameter through the scenario's routing
    /// ([`ScenarioSpec::set`]): `pair.FIELD` sets a field of the pair, an operating-point key
    /// the pair states becomes an override under `[set]`, a key the pair computes is refused.
    pub fn set(&mut self, name: &str, value: f64) -> Result<(), ConfigError> {
        let s = &mut self.simulation;
        // (the same ranges sim_options checks: a record of at least one period)
        let as_count = |field: &'static str, v: f64| -> Result<u64, ConfigError> {
            let steps = &geardyn_analysis::simulate::RK4_STEPS_PER_CYCLE;
            let most = geardyn_analysis::simulate::MAX_PERIODS;
            let (min, max) = match field {
                "steps_per_cycle" => (*steps.start() as u64, *steps.end() as u64),
                "record_periods" => (1, most),
                "decision_budget" => (0, geardyn_analysis::classify::MAX_DECISION_BUDGET),
                _ => (0, most),
            };
            let allowed = if field == "steps_per_cycle" {
                format!("a whole number in [{min}, {max}]")
            } else if field == "decision_budget" {
                format!("a whole number in [{min}, {max}] (right-hand-side evaluations of one run's decision)")
            } else {
                format!("a whole number in [{min}, {max}] ({max} excitation periods already take hours)")
            };
            let (min, max) = (min as f64, max as f64);
            if v >= min && v.fract() == 0.0 && v <= max {
                Ok(v as u64)
            } else {
                Err(ConfigError::Simulation {
                    field,
                    value: geardyn_model::error::num(v),
                    allowed: allowed.into(),
                })
            }
        };
        match name {
            "x0" => s.x0 = value,
            "v0" => s.v0 = value,
            "tau0" => s.tau0 = value,
            "rtol" => s.rtol = value,
            "atol" => s.atol = value,
            "steps_per_cycle" => s.steps_per_cycle = as_count("steps_per_cycle", value)? as u32,
            "transient_periods" => s.transient_periods = as_count("transient_periods", value)?,
            "record_periods" => s.record_periods = as_count("record_periods", value)?,
            "decision_periods" => s.decision_periods = as_count("decision_periods", value)?,
            "decision_budget" => s.decision_budget = as_count("decision_budget", value)?,
            "follow_steps" => {
                s.follow_steps = follow_steps(value)?;
            }
            "escape_copies" => s.escape_copies = escape_copies(value)?,
            "escape_periods" => s.escape_periods = escape_periods(value)?,
            "max_work" => {
                if !(value.is_finite() && (1e6..=1e18).contains(&value)) {
                    return Err(ConfigError::Simulation {
                        field: "max_work",
                        value: geardyn_model::error::num(value),
                        allowed: "[1e6, 1e18] (right-hand-side evaluations of a whole command)"
                            .into(),
                    });
                }
                s.max_work = value;
            }
            _ => {
                let mut spec = self.spec();
                spec.set(name, value).map_err(|e| match e {
                    ScenarioError::Model(ModelError::UnknownParameter { name, known }) => {
                        ConfigError::Model(ModelError::UnknownParameter {
                            name,
                            known: format!("{known}, {}, pair.FIELD", SIMULATION_NAMES.join(", ")),
                        })
                    }
                    e => e.into(),
                })?;
                self.model = spec.model;
                self.pair = spec.pair;
                self.set = spec.overrides;
            }
        }
        Ok(())
    }

    /// Simulation options (validated).
    pub fn sim_options(&self) -> Result<SimOptions, ConfigError> {
        let s = &self.simulation;
        let method = match s.method.as_str() {
            "dopri" => {
                if !(s.rtol >= 1e-14 && s.rtol <= 1e-2) {
                    return Err(ConfigError::Simulation {
                        field: "rtol",
                        value: geardyn_model::error::num(s.rtol),
                        allowed: "[1e-14, 1e-2]".into(),
                    });
                }
                if !(s.atol >= 1e-16 && s.atol <= 1e-2) {
                    return Err(ConfigError::Simulation {
                        field: "atol",
                        value: geardyn_model::error::num(s.atol),
                        allowed: "[1e-16, 1e-2]".into(),
                    });
                }
                Method::Dopri {
                    rtol: s.rtol,
                    atol: s.atol,
                }
            }
            "rk4" => {
                if !geardyn_analysis::simulate::RK4_STEPS_PER_CYCLE.contains(&s.steps_per_cycle) {
                    return Err(ConfigError::Simulation {
                        field: "steps_per_cycle",
                        value: s.steps_per_cycle.to_string(),
                        allowed: {
                            let r = &geardyn_analysis::simulate::RK4_STEPS_PER_CYCLE;
                            format!("a whole number in [{}, {}]", r.start(), r.end()).into()
                        },
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
                    allowed: "\"dopri\" or \"rk4\"".into(),
                })
            }
        };
        for (f, v) in [("x0", s.x0), ("v0", s.v0), ("tau0", s.tau0)] {
            if !v.is_finite() {
                return Err(ConfigError::Simulation {
                    field: f,
                    value: v.to_string(),
                    allowed: "a finite number".into(),
                });
            }
        }
        if s.tau0.abs() > 1e9 {
            return Err(ConfigError::Simulation {
                field: "tau0",
                value: geardyn_model::error::num(s.tau0),
                allowed: "[-1e9, 1e9] (the time resolution of f64 must resolve a mesh cycle)"
                    .into(),
            });
        }
        let most = geardyn_analysis::simulate::MAX_PERIODS;
        if s.transient_periods > most || s.record_periods > most {
            return Err(ConfigError::Simulation {
                field: "transient_periods/record_periods",
                value: format!("{}/{}", s.transient_periods, s.record_periods),
                allowed: format!("<= {most} each ({most} excitation periods already take hours)")
                    .into(),
            });
        }
        if s.decision_periods > most {
            return Err(ConfigError::Simulation {
                field: "decision_periods",
                value: s.decision_periods.to_string(),
                allowed: format!("<= {most}").into(),
            });
        }
        let most_cycles = geardyn_analysis::classify::MAX_DECISION_BUDGET;
        if s.decision_budget > most_cycles {
            return Err(ConfigError::Simulation {
                field: "decision_budget",
                value: s.decision_budget.to_string(),
                allowed: format!(
                    "<= {most_cycles} (right-hand-side evaluations of one run's decision)"
                )
                .into(),
            });
        }
        follow_steps(f64::from(s.follow_steps))?;
        escape_copies(f64::from(s.escape_copies))?;
        escape_periods(s.escape_periods as f64)?;
        if s.record_periods == 0 {
            return Err(ConfigError::Simulation {
                field: "record_periods",
                value: "0".into(),
                allowed: ">= 1".into(),
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
            start_memory: 0.0,
            decision_periods: s.decision_periods,
            decision_budget: s.decision_budget,
            follow_steps: s.follow_steps,
            escape: geardyn_analysis::escape::EscapeSettings {
                copies: s.escape_copies,
                periods: s.escape_periods,
                ..Default::default()
            },
            ..SimOptions::default()
        })
    }
}

mod overrides;
pub use overrides::{Face, SimOverrides};

#[cfg(test)]
mod tests;
