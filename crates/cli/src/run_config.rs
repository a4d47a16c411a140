//! Arguments shared by every command that runs a model: preset or config file, and overrides.

use anyhow::{Context, Result};
use clap::Args;
use geardyn_io::Config;
use std::path::PathBuf;

/// Where the configuration comes from.
#[derive(Args, Debug, Clone)]
pub struct ConfigArgs {
    /// Built-in preset (see `geardyn presets`); default `classic` when no --config is given.
    #[arg(long, conflicts_with = "config")]
    pub preset: Option<String>,
    /// TOML configuration file (as printed by `geardyn show`).
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// Override a parameter: NAME=VALUE (repeatable), e.g. --set omega=1.3 --set F=0.05.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub sets: Vec<String>,
}

impl ConfigArgs {
    /// The configuration with all overrides applied and validated.
    pub fn resolve(&self) -> Result<Config> {
        let mut c = match (&self.preset, &self.config) {
            (_, Some(path)) => Config::from_file(path)?,
            (Some(name), None) => Config::preset(name)?,
            (None, None) => Config::preset("classic")?,
        };
        for s in &self.sets {
            c.apply_set(s)?;
        }
        c.build_model().context("configuration rejected")?;
        Ok(c)
    }
}
