//! Arguments shared by every command that runs a model: preset or config file, and overrides,
//! resolved through the one builder (`geardyn_scenario`).

use anyhow::{Context, Result};
use clap::Args;
use geardyn_io::Config;
use geardyn_scenario::Scenario;
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
    /// A gear train's description (TOML, as `geardyn show --preset planetary` prints it and
    /// every train command writes it to system.toml, its `[operating]` point included); the
    /// commands that run trains are listed by `geardyn presets` (built-in trains: --preset
    /// planetary, two-stage, pair).
    #[arg(long, conflicts_with_all = ["config", "preset"])]
    pub system: Option<PathBuf>,
    /// Override a parameter: NAME=VALUE (repeatable), e.g. --set omega=1.3 --set F=0.05, or a
    /// field of the physical pair, e.g. --set pair.mu=0.1. On a pair with a physical operating
    /// point, omega/F/xi/c/D set here take precedence and are recorded.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub sets: Vec<String>,
    /// Contact law replacing the configuration's [model.contact] (the drive flank, and the back
    /// flank when it is in continuous contact; a back side modelled by impacts, as on the
    /// breakage preset, keeps its impact law): LAW[:EXPONENT[:RESTITUTION]], e.g. linear (seed
    /// B's dimensionless studies), power:1.5, lankarani_nikravesh:1.19:0.8.
    #[arg(long, value_name = "LAW")]
    pub contact: Option<String>,
}

impl ConfigArgs {
    /// The configuration with all overrides applied (not yet validated).
    pub fn config(&self) -> Result<Config> {
        let mut c = match (&self.preset, &self.config) {
            (_, Some(path)) => Config::from_file(path)?,
            _ if self.system.is_some() => {
                anyhow::bail!("--system names a gear train: geardyn {} run trains; this command runs the single pair's model", TRAIN_COMMANDS)
            }
            (Some(name), None)
                if geardyn_train::presets::NAMES.contains(&name.as_str())
                    && Config::preset(name).is_err() =>
            {
                anyhow::bail!("--preset {name} is a gear train: geardyn {} run trains; this command runs the single pair's model", TRAIN_COMMANDS)
            }
            (Some(name), None) => Config::preset(name)?,
            (None, None) => Config::preset("classic")?,
        };
        if let Some(law) = &self.contact {
            c.apply_contact(law)?;
        }
        for s in &self.sets {
            c.apply_set(s)?;
        }
        Ok(c)
    }

    /// What the model comes from, for titles: `preset classic` or `config <file>`.
    pub fn source(&self) -> String {
        match (&self.preset, &self.config) {
            (_, Some(path)) => format!("config {}", path.display()),
            (Some(name), None) => format!("preset {name}"),
            (None, None) => "preset classic".into(),
        }
    }

    /// The configuration and the scenario it resolves to (validated).
    pub fn resolve(&self) -> Result<(Config, Scenario)> {
        let c = self.config()?;
        let s = c.resolve().context("configuration rejected")?;
        Ok((c, s))
    }
}

/// The commands that run gear trains (for messages and `geardyn presets`).
pub const TRAIN_COMMANDS: &str =
    "modes, show, simulate, bifurcation, response, lyapunov, basins, continuation, orbits, map2d, signals";
