//! Where a request's model comes from and the settings several requests share: the
//! configuration source ([`Source`]), the integration settings ([`Sim`]), the identification
//! settings ([`Ident`]) and parameter values ([`values_of`]). Each is a dict of the Python
//! request's payload (`geardyn/_requests.py`), converted by it.

use anyhow::{bail, Context, Result};
use geardyn_analysis::attractor::{IdentifyOptions, IdentifyRequest};
use geardyn_analysis::bifurcation::{range_values, MAX_RANGE_VALUES};
use geardyn_io::config::{Face, SimOverrides};
use geardyn_io::Config;
use pyo3::prelude::*;

use crate::util::ser_to_py;

/// Where a configuration comes from: a preset, a TOML file, or a configuration as JSON (the dict
/// `geardyn.config()` returns), then `NAME=VALUE` overrides in order (as `--set`).
#[derive(Clone, Debug, FromPyObject)]
#[pyo3(from_item_all)]
pub struct Source {
    pub preset: Option<String>,
    pub config_path: Option<String>,
    pub config_json: Option<String>,
    pub sets: Vec<String>,
    pub contact: Option<String>,
}

impl Source {
    /// What the model comes from, for figure titles (as `ConfigArgs::source` of the CLI).
    pub fn source(&self) -> String {
        match (&self.preset, &self.config_path, &self.config_json) {
            (_, Some(path), _) => format!("config {path}"),
            (_, None, Some(_)) => "config dict".into(),
            (Some(name), None, None) => format!("preset {name}"),
            (None, None, None) => "preset classic".into(),
        }
    }

    /// The configuration with all overrides applied (as `ConfigArgs::config` of the CLI).
    pub fn config(&self) -> Result<Config> {
        let mut c = match (&self.preset, &self.config_path, &self.config_json) {
            (Some(_), Some(_), _) | (Some(_), _, Some(_)) => {
                bail!("preset and config exclude each other: give one of them")
            }
            (_, Some(path), _) => Config::from_file(std::path::Path::new(path))?,
            (_, None, Some(json)) => {
                let v: serde_json::Value =
                    serde_json::from_str(json).context("malformed config dict")?;
                let t = toml::Value::try_from(v)
                    .map_err(|e| anyhow::anyhow!("malformed config dict: {e}"))?;
                let text = toml::to_string(&t)
                    .map_err(|e| anyhow::anyhow!("malformed config dict: {e}"))?;
                Config::from_toml(&text)?
            }
            (Some(name), None, None) => Config::preset(name)?,
            (None, None, None) => Config::preset("classic")?,
        };
        if let Some(law) = &self.contact {
            c.apply_contact(law)?;
        }
        for s in &self.sets {
            c.apply_set(s)?;
        }
        Ok(c)
    }
}

/// Integration settings of the sweep commands (the CLI's `SimArgs`).
#[derive(Clone, Debug, Default, FromPyObject)]
#[pyo3(from_item_all)]
pub struct Sim {
    pub periods: Option<f64>,
    pub transient: Option<f64>,
    pub integrator: Option<String>,
    pub steps_per_cycle: Option<f64>,
}

impl Sim {
    /// Applies the settings; `sets` are the call's `set=` assignments (a field given by both is
    /// refused, as in the CLI).
    pub fn apply(&self, cfg: &mut Config, sets: &[String]) -> Result<()> {
        let o = SimOverrides {
            periods: self.periods,
            transient: self.transient,
            integrator: self.integrator.clone(),
            steps_per_cycle: self.steps_per_cycle,
            ..Default::default()
        };
        Ok(o.apply(cfg, sets, Face::Python)?)
    }
}

/// Attractor-identification settings (the CLI's `IdentArgs`, same defaults).
#[derive(Clone, Debug, FromPyObject)]
#[pyo3(from_item_all)]
pub struct Ident {
    pub capture_tol: f64,
    pub early_stop: bool,
    pub ident_rtol: f64,
}

impl Ident {
    /// The library's request (which checks it, as the CLI's).
    pub fn request(&self) -> IdentifyRequest {
        IdentifyRequest {
            capture_tol: self.capture_tol,
            ident_rtol: self.ident_rtol,
            early_capture: self.early_stop,
        }
    }

    /// The identification options on the configuration's simulation settings.
    pub fn options(&self, cfg: &Config) -> Result<IdentifyOptions> {
        Ok(self.request().options(cfg.sim_options()?)?)
    }
}

/// Parameter values: explicit, or `(start, stop, count)` through the library's `linspace` (the
/// CLI's `--range`).
pub fn values_of(values: Option<Vec<f64>>, range: Option<(f64, f64, usize)>) -> Result<Vec<f64>> {
    values_named("range", values, range)
}

/// [`values_of`] of an axis called `name` in messages (a map's `x`, `y`).
pub fn values_named(
    name: &str,
    values: Option<Vec<f64>>,
    range: Option<(f64, f64, usize)>,
) -> Result<Vec<f64>> {
    match (values, range) {
        (Some(_), Some(_)) => bail!("values and range exclude each other: give one of them"),
        (Some(v), None) => {
            if v.is_empty() || v.len() > 1_000_000 {
                bail!("bad values: 1 to 1000000 values");
            }
            if let Some(x) = v.iter().find(|x| !x.is_finite()) {
                bail!(
                    "bad values: {} is not finite",
                    geardyn_model::error::num(*x)
                );
            }
            Ok(v)
        }
        (None, Some(r)) => Ok(range_values(name, r, MAX_RANGE_VALUES)?),
        (None, None) => {
            bail!("give the parameter values: values=[...] or range=(start, stop, count)")
        }
    }
}

/// A configuration as a Python dict.
pub fn config_py<'py>(py: Python<'py>, cfg: &Config) -> PyResult<Bound<'py, PyAny>> {
    ser_to_py(py, &cfg.to_value())
}

/// The configuration of `src` and its resolved scenario.
pub fn resolve(src: &Source) -> Result<(Config, geardyn_scenario::Scenario)> {
    let c = src.config()?;
    let s = c.resolve().context("configuration rejected")?;
    Ok((c, s))
}
