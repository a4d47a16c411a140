//! The one builder of geardyn: what a user asked for (a dimensionless `[model]`, an optional
//! physical `[pair]`, explicit dimensionless overrides) resolved into the model that is
//! integrated. Every command, sweep, map and report study goes through [`ScenarioSpec::resolve`]
//! and [`Scenario::with`], so what was set is what ran.
//!
//! # The operating-point rule (docs/configuration.md)
//! A pair with a physical operating point (`pair.operating`: speed, torque, error amplitude,
//! half backlash) states `omega`, `F`, `xi`, `D_d`, `D_s`; `pair.damping_ratio` states `c`.
//! An explicit dimensionless value of one of these keys (a `--set`, a swept value, a key of the
//! config's `[set]` table) takes precedence over the physical value and is recorded in
//! [`ScenarioSpec::overrides`]; the pair's tables (stiffness, friction, film, thermal state,
//! backlash physics) stay evaluated at the physical operating point. Quantities the pair
//! computes (`eps`, the stiffness form, `eps_b`, friction) cannot be set as dimensionless keys
//! on a pair: the error names the `pair.*` field to use instead.
//!
//! ```
//! use geardyn_scenario::ScenarioSpec;
//! let spec = ScenarioSpec::preset("internal").unwrap();
//! let s = spec.resolve().unwrap();
//! let faster = s.with("omega", 2.0).unwrap();
//! assert_eq!(faster.params().omega, 2.0);
//! assert_eq!(faster.spec().overrides["omega"], 2.0);
//! assert!(s.with("eps", 1.7).unwrap_err().to_string().contains("[pair]"));
//! ```

use geardyn_model::{presets, BackSide, ContactLaw, Friction, MeshModel, ModelError, ModelParams};
use geardyn_physics::{PairModel, PairSpec, PhysicsError};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::sync::Arc;

/// Dimensionless operating-point keys a physical pair may state (`c` through its damping
/// ratio). `D` (static half backlash) is an alias that sets `D_s` and shifts `D_d`.
pub const OPERATING_KEYS: &[&str] = &["omega", "F", "xi", "c", "D_d", "D_s"];

/// Dimensionless keys that a physical pair computes, with the `pair.*` field to set instead.
pub const PAIR_DERIVED_KEYS: &[(&str, &str)] = &[
    ("eps", "pair geometry (z1, z2, module_mm, addendum, x1, x2)"),
    (
        "kappa",
        "pair geometry and material (mesh stiffness tables)",
    ),
    ("k", "pair geometry and material (mesh stiffness tables)"),
    (
        "k_double",
        "pair geometry and material (mesh stiffness tables)",
    ),
    (
        "k_single",
        "pair geometry and material (mesh stiffness tables)",
    ),
    (
        "eps_b",
        "pair.breakage.removed_height_mm or pair.breakage.tip_radius_mm",
    ),
    ("k_zone2", "pair.breakage.removed_height_mm"),
    ("mu", "pair.mu (or pair.lubrication)"),
    ("arm", "pair geometry (friction arms)"),
    ("pitch", "pair geometry (pitch point)"),
];

/// Errors of scenario resolution: each names the key and what to do instead.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ScenarioError {
    /// A dimensionless parameter error.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// A physical pair error.
    #[error(transparent)]
    Physics(#[from] PhysicsError),
    /// A key that the pair computes, or a `pair.*` key without a pair.
    #[error("{key}: {reason}")]
    Key {
        /// The key as given.
        key: String,
        /// What is wrong and which key to use.
        reason: String,
    },
}

fn key_err(key: &str, reason: impl Into<String>) -> ScenarioError {
    ScenarioError::Key {
        key: key.to_string(),
        reason: reason.into(),
    }
}

/// What the user asked for: the inputs of the builder, routed but not yet validated.
#[derive(Clone, Debug, PartialEq)]
pub struct ScenarioSpec {
    /// The dimensionless `[model]` table. With a pair, its pair-derived fields are placeholders
    /// and its operating-point fields are used only where the pair states none.
    pub model: ModelParams,
    /// The physical pair (mm, deg, GPa), if any.
    pub pair: Option<PairSpec>,
    /// Explicit dimensionless values of [`OPERATING_KEYS`] that take precedence over the pair's
    /// physical operating point (empty without a pair).
    pub overrides: BTreeMap<String, f64>,
}

impl ScenarioSpec {
    /// A purely dimensionless scenario.
    pub fn dimensionless(model: ModelParams) -> Self {
        ScenarioSpec {
            model,
            pair: None,
            overrides: BTreeMap::new(),
        }
    }

    /// A built-in preset: dimensionless parameters and, for `breakage` and `internal`, the
    /// physical pair.
    pub fn preset(name: &str) -> Result<Self, ScenarioError> {
        let mut model = presets::by_name(name)?;
        let pair = geardyn_physics::presets::by_name(name);
        if pair.is_some() {
            model.friction = Friction::default();
        }
        Ok(ScenarioSpec {
            model,
            pair,
            overrides: BTreeMap::new(),
        })
    }

    /// Whether the pair states this dimensionless key (so a value for it is an override).
    pub fn pair_states(&self, key: &str) -> bool {
        let Some(pair) = &self.pair else { return false };
        match key {
            "c" => pair.damping_ratio.is_some(),
            "omega" | "F" | "xi" | "D" | "D_d" | "D_s" => pair.operating.is_some(),
            _ => false,
        }
    }

    /// Sets a parameter by name: `pair.FIELD` (dotted, e.g. `pair.breakage.removed_height_mm`)
    /// sets a field of the pair; an operating-point key the pair states becomes an override;
    /// other dimensionless keys set the `[model]` table; a key the pair computes is an error.
    /// Values are range-checked by [`ScenarioSpec::resolve`].
    pub fn set(&mut self, name: &str, value: f64) -> Result<(), ScenarioError> {
        if let Some(field) = name.strip_prefix("pair.") {
            return self.set_pair(field, value);
        }
        if self.pair.is_some() {
            if let Some((_, instead)) = PAIR_DERIVED_KEYS.iter().find(|(k, _)| *k == name) {
                // a lubricated pair takes its friction from the film, not from pair.mu
                let lubricated = self.pair.as_ref().is_some_and(|p| p.lubrication.is_some());
                let instead = if name == "mu" && lubricated {
                    "pair.lubrication.boundary_mu (the friction follows [pair.lubrication])"
                } else {
                    instead
                };
                return Err(key_err(
                    name,
                    format!("computed from the physical [pair] of this configuration; set {instead} instead"),
                ));
            }
        }
        if self.pair_states(name) {
            if name == "D" {
                // keep the pair's D_s - D_d, as `D` does on dimensionless parameters
                let p = self.resolve_params(None)?.0;
                self.overrides
                    .insert("D_d".into(), value - (p.d_single - p.d_double));
                self.overrides.insert("D_s".into(), value);
            } else {
                self.overrides.insert(name.to_string(), value);
            }
            return Ok(());
        }
        Ok(self.model.set(name, value)?)
    }

    /// Value of a named parameter as resolved (`pair.*` fields read from the pair).
    pub fn get(&self, name: &str) -> Result<f64, ScenarioError> {
        if let Some(field) = name.strip_prefix("pair.") {
            let pair = self.pair_or_err(name)?;
            let v = toml::Value::try_from(pair).expect("pair serialises");
            let mut cur = &v;
            for part in field.split('.') {
                cur = cur
                    .get(part)
                    .ok_or_else(|| key_err(name, "no such pair field (or it is not set)"))?;
            }
            return cur
                .as_float()
                .or_else(|| cur.as_integer().map(|i| i as f64))
                .ok_or_else(|| key_err(name, "not a number"));
        }
        Ok(self.resolve_params(None)?.0.get(name)?)
    }

    fn pair_or_err(&self, name: &str) -> Result<&PairSpec, ScenarioError> {
        self.pair.as_ref().ok_or_else(|| {
            key_err(
                name,
                "this configuration has no [pair] (use the breakage or internal preset, or add one)",
            )
        })
    }

    fn set_pair(&mut self, field: &str, value: f64) -> Result<(), ScenarioError> {
        let name = format!("pair.{field}");
        let pair = self.pair_or_err(&name)?;
        if !value.is_finite() {
            return Err(key_err(&name, format!("{value} is not a finite number")));
        }
        if field == "mu" && pair.lubrication.is_some() {
            return Err(key_err(
                &name,
                "has no effect on this pair: its friction follows [pair.lubrication] (film \
                 thickness and regime along the path); set pair.lubrication.boundary_mu (the \
                 boundary-regime coefficient) or remove [pair.lubrication] for a constant mu",
            ));
        }
        let mut v = toml::Value::try_from(pair).expect("pair serialises");
        let parts: Vec<&str> = field.split('.').collect();
        set_path(&mut v, &parts, value).map_err(|why| key_err(&name, why))?;
        let spec: PairSpec = v.try_into().map_err(|e: toml::de::Error| {
            let m = e.message();
            let why = if m.contains("expected u32") || m.contains("expected u64") {
                format!("{value}: a whole number >= 0 is needed")
            } else if let Some(f) = m.strip_prefix("missing field ") {
                // (a sub-table the configuration does not have was begun with this one field)
                format!(
                    "this pair has no such table, and one needs {f} too: write the table in a \
                     configuration file (`geardyn show` prints the pair)"
                )
            } else {
                m.to_string()
            };
            key_err(&name, why)
        })?;
        self.pair = Some(spec);
        Ok(())
    }

    /// The dimensionless parameters that are integrated, and the pair model they came from.
    /// `cached` is reused when it was built from the same pair.
    fn resolve_params(
        &self,
        cached: Option<&Arc<PairModel>>,
    ) -> Result<(ModelParams, Option<Arc<PairModel>>), ScenarioError> {
        let mut p = self.model.clone();
        let pm = match &self.pair {
            None => {
                if !self.overrides.is_empty() {
                    // without a pair an override is just the model's value
                    for (k, v) in &self.overrides {
                        p.set(k, *v)?;
                    }
                }
                return Ok((p, None));
            }
            Some(spec) => match cached {
                Some(c) if &c.spec == spec => c.clone(),
                _ => Arc::new(spec.build()?),
            },
        };
        p.friction = Friction::default();
        pm.apply(&mut p);
        for (k, v) in &self.overrides {
            if !OPERATING_KEYS.contains(&k.as_str()) {
                return Err(key_err(
                    k,
                    format!(
                        "only operating-point keys can be overridden ({})",
                        OPERATING_KEYS.join(", ")
                    ),
                ));
            }
            p.set(k, *v)?;
        }
        Ok((p, Some(pm)))
    }

    /// Validates everything and builds the model.
    pub fn resolve(&self) -> Result<Scenario, ScenarioError> {
        self.resolve_cached(None)
    }

    fn resolve_cached(&self, cached: Option<&Arc<PairModel>>) -> Result<Scenario, ScenarioError> {
        let (params, pair_model) = self.resolve_params(cached)?;
        let model = MeshModel::new(&params).map_err(|e| self.name_the_source(e))?;
        Ok(Scenario {
            spec: self.clone(),
            pair_model,
            params,
            model,
        })
    }
}

impl ScenarioSpec {
    /// A range error on an operating-point value the pair computed (not set by the user): names
    /// the `pair.*` fields it came from, which are what the user can change.
    fn name_the_source(&self, e: ModelError) -> ScenarioError {
        let ModelError::Invalid {
            field,
            value,
            allowed,
        } = &e
        else {
            return e.into();
        };
        let from = match field.as_str() {
            "omega" => "pair.operating.speed_rpm",
            "F" => "pair.operating.torque_nm",
            "xi" => "pair.operating.error_amplitude_um",
            "c" => "pair.damping_ratio",
            "D_d" | "D_s" => "pair.operating.half_backlash_um (and the thermal state)",
            _ => return e.into(),
        };
        if !self.pair_states(field) || self.overrides.contains_key(field.as_str()) {
            return e.into();
        }
        key_err(
            from,
            format!(
                "gives {field} = {} (dimensionless), allowed {allowed}",
                geardyn_model::error::num(*value)
            ),
        )
    }
}

/// A resolved, validated scenario: the parameters and the model that are integrated.
#[derive(Clone, Debug)]
pub struct Scenario {
    spec: ScenarioSpec,
    pair_model: Option<Arc<PairModel>>,
    params: ModelParams,
    model: MeshModel,
}

impl Scenario {
    /// A purely dimensionless scenario (validated).
    pub fn dimensionless(model: ModelParams) -> Result<Self, ScenarioError> {
        ScenarioSpec::dimensionless(model).resolve()
    }

    /// What was asked for.
    pub fn spec(&self) -> &ScenarioSpec {
        &self.spec
    }

    /// The dimensionless parameters that are integrated (pair tables filled in).
    pub fn params(&self) -> &ModelParams {
        &self.params
    }

    /// The model that is integrated.
    pub fn model(&self) -> &MeshModel {
        &self.model
    }

    /// The physical pair model (geometry, tables, normalisation), if any.
    pub fn pair_model(&self) -> Option<&PairModel> {
        self.pair_model.as_deref()
    }

    /// The same scenario with one parameter changed, through the same routing as `--set`
    /// (`pair.*` fields rebuild the pair; other keys reuse its tables).
    pub fn with(&self, name: &str, value: f64) -> Result<Scenario, ScenarioError> {
        self.with_all(&[(name, value)])
    }

    /// The same scenario with several parameters changed, applied in order.
    pub fn with_all(&self, sets: &[(&str, f64)]) -> Result<Scenario, ScenarioError> {
        let mut spec = self.spec.clone();
        for (n, v) in sets {
            spec.set(n, *v)?;
        }
        spec.resolve_cached(self.pair_model.as_ref())
    }

    /// Value of a named parameter as integrated (`pair.*` read from the pair).
    pub fn get(&self, name: &str) -> Result<f64, ScenarioError> {
        if name.starts_with("pair.") {
            return self.spec.get(name);
        }
        Ok(self.params.get(name)?)
    }

    /// The healthy twin: the same scenario without tooth breakage.
    pub fn healthy(&self) -> Result<Scenario, ScenarioError> {
        let mut spec = self.spec.clone();
        if let Some(p) = &mut spec.pair {
            p.breakage = None;
        }
        spec.model.breakage = None;
        spec.resolve()
    }

    /// The resolved dimensionless parameters as a flat record (for `summary.json`, `run.json`,
    /// sweep tables): the operating point, backlash, contact ratio and what was overridden.
    pub fn record(&self) -> ResolvedRecord {
        let p = &self.params;
        ResolvedRecord {
            omega: p.omega,
            load: p.load,
            xi: p.xi,
            c: p.c,
            d_double: p.d_double,
            d_single: p.d_single,
            eps: p.eps,
            eps_b: p.breakage.map(|b| b.eps_b),
            cycles_per_period: p.cycles_per_period(),
            contact: p.contact,
            back_side: p.back_side,
            physical_pair: self.spec.pair.is_some(),
            overrides: self.spec.overrides.clone(),
        }
    }
}

/// The resolved dimensionless parameters that were integrated (docs/model.md §1–3).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ResolvedRecord {
    /// Dimensionless mesh frequency.
    pub omega: f64,
    /// Mean load `F`.
    #[serde(rename = "F")]
    pub load: f64,
    /// Error amplitude `xi`.
    pub xi: f64,
    /// Mesh damping `c = 2 zeta`.
    pub c: f64,
    /// Half backlash in double-tooth zones.
    #[serde(rename = "D_d")]
    pub d_double: f64,
    /// Half backlash in single-tooth zones.
    #[serde(rename = "D_s")]
    pub d_single: f64,
    /// Contact ratio.
    pub eps: f64,
    /// Contact ratio of the broken tooth, if any.
    pub eps_b: Option<f64>,
    /// Mesh cycles per excitation period.
    pub cycles_per_period: u32,
    /// Contact law (as in the configuration's `[model.contact]`).
    pub contact: ContactLaw,
    /// Back-side model (as in the configuration's `[model.back_side]`).
    pub back_side: BackSide,
    /// Whether a physical pair supplied the tables.
    pub physical_pair: bool,
    /// Dimensionless values set explicitly over the pair's physical operating point.
    pub overrides: BTreeMap<String, f64>,
}

/// Sets `value` at a dotted path of a TOML table, creating intermediate tables; integers stay
/// integers when the value is whole.
fn set_path(v: &mut toml::Value, parts: &[&str], value: f64) -> Result<(), &'static str> {
    let Some(table) = v.as_table_mut() else {
        return Err("not a numeric field of [pair]");
    };
    match parts {
        [] => Err("not a numeric field of [pair]"),
        [last] => {
            let new = match table.get(*last) {
                Some(toml::Value::Integer(_)) if value.fract() == 0.0 && value.abs() < 9e15 => {
                    toml::Value::Integer(value as i64)
                }
                Some(toml::Value::Integer(_)) => return Err("must be a whole number"),
                Some(toml::Value::Table(_)) => {
                    return Err(
                        "a table, not a number (set one of its fields: pair.FIELD.SUBFIELD)",
                    )
                }
                Some(toml::Value::String(_)) => {
                    return Err("a name, not a number (set it in a configuration file)")
                }
                _ => toml::Value::Float(value),
            };
            table.insert(last.to_string(), new);
            Ok(())
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
    fn dimensionless_set_on_a_physical_operating_point_takes_precedence() {
        let s = ScenarioSpec::preset("internal").unwrap().resolve().unwrap();
        let base = s.params().clone();
        for (k, v) in [("omega", 2.0), ("F", 0.16), ("xi", 0.09), ("c", 0.2)] {
            let t = s.with(k, v).unwrap();
            assert_eq!(t.get(k).unwrap(), v, "{k}");
            assert_eq!(t.spec().overrides[k], v);
        }
        let t = s.with("D", 1.3).unwrap();
        assert_eq!(t.params().d_single, 1.3);
        let diff = base.d_single - base.d_double;
        assert!((t.params().d_single - t.params().d_double - diff).abs() < 1e-12);
        // the pair's stiffness tables stay the same
        assert_eq!(t.params().stiffness, base.stiffness);
    }

    #[test]
    fn pair_derived_keys_are_refused_with_the_key_to_use() {
        let s = ScenarioSpec::preset("breakage").unwrap().resolve().unwrap();
        for k in ["eps", "mu", "eps_b", "kappa"] {
            let e = s.with(k, 0.1).unwrap_err().to_string();
            assert!(e.contains(k) && e.contains("pair"), "{e}");
        }
        // classic has no pair: pair.* is refused, eps is fine
        let c = ScenarioSpec::preset("classic").unwrap().resolve().unwrap();
        assert!(c.with("pair.mu", 0.1).is_err());
        assert_eq!(c.with("eps", 1.7).unwrap().params().eps, 1.7);
    }

    #[test]
    fn pair_fields_rebuild_what_depends_on_them() {
        let s = ScenarioSpec::preset("breakage").unwrap().resolve().unwrap();
        let t = s.with("pair.mu", 0.0).unwrap();
        assert_ne!(s.params().stiffness, t.params().stiffness);
        assert_eq!(t.get("pair.mu").unwrap(), 0.0);
        let h = s.healthy().unwrap();
        assert!(h.params().breakage.is_none() && s.params().breakage.is_some());
        // no operating point on the breakage pair: omega is the model's own value
        let o = s.with("omega", 1.2).unwrap();
        assert!(o.spec().overrides.is_empty());
        assert_eq!(o.params().omega, 1.2);
    }
}
