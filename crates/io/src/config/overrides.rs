//! What a caller overrides on a configuration: the simulation settings given as options
//! ([`SimOverrides`]) and how each face (command line, Python) spells them ([`Face`]).

use super::*;

/// Who states a request: names its options in messages as that face spells them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Face {
    /// The command line: `--decision-periods`, assignments as `--set NAME=VALUE`.
    Cli,
    /// Python's keyword arguments: `decision_periods=`, assignments as `NAME=VALUE`.
    Python,
}

impl Face {
    /// The option `name` (snake case) as this face spells it.
    pub fn option(self, name: &str) -> String {
        match self {
            Face::Cli => format!("--{}", name.replace('_', "-")),
            Face::Python => format!("{name}="),
        }
    }

    /// The option `name` given `value`, as this face spells it (`--periods 0`, `periods=0`).
    pub fn given(self, name: &str, value: f64) -> String {
        let v = geardyn_model::error::num(value);
        match self {
            Face::Cli => format!("{} {v}", self.option(name)),
            Face::Python => format!("{}{v}", self.option(name)),
        }
    }

    /// How this face's assignments are quoted in messages.
    fn assignment_prefix(self) -> &'static str {
        match self {
            Face::Cli => "--set ",
            Face::Python => "",
        }
    }
}

/// The simulation settings a caller overrides on a configuration (`--periods`, `--transient`,
/// `--integrator`, `--steps-per-cycle`, `--decision-periods`, `--decision-budget`,
/// `--follow-steps`, `--max-work`; Python's keywords of the same names): the one list of them, applied and
/// checked by [`SimOverrides::apply`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SimOverrides {
    /// Recorded excitation periods per run (`simulation.record_periods`; option `periods`).
    pub periods: Option<f64>,
    /// Transient excitation periods per run (`simulation.transient_periods`; option `transient`).
    pub transient: Option<f64>,
    /// Integrator, `dopri` or `rk4` (`simulation.method`; option `integrator`).
    pub integrator: Option<String>,
    /// RK4 steps per mesh cycle (`simulation.steps_per_cycle`).
    pub steps_per_cycle: Option<f64>,
    /// Decision horizon in excitation periods (`simulation.decision_periods`).
    pub decision_periods: Option<f64>,
    /// Work budget of one run's decision in right-hand-side evaluations
    /// (`simulation.decision_budget`).
    pub decision_budget: Option<f64>,
    /// Resolution of a decision's follow, RK4 steps per natural period; 0 follows with the
    /// requested integrator (`simulation.follow_steps`).
    pub follow_steps: Option<f64>,
    /// Copies of the escape test; 0 turns it off (`simulation.escape_copies`).
    pub escape_copies: Option<f64>,
    /// Span of the escape test in excitation periods (`simulation.escape_periods`).
    pub escape_periods: Option<f64>,
    /// Cap on a command's estimated work (`simulation.max_work`).
    pub max_work: Option<f64>,
}

impl SimOverrides {
    /// Applies the overrides to `cfg` and checks the resulting simulation settings; `sets` are
    /// the caller's own `NAME=VALUE` assignments: a field given by both is refused (which one
    /// wins would be a silent choice), named as `face` spells it.
    ///
    /// ```
    /// use geardyn_io::config::{Face, SimOverrides};
    /// let mut cfg = geardyn_io::Config::preset("classic").unwrap();
    /// let o = SimOverrides { periods: Some(50.0), ..Default::default() };
    /// o.apply(&mut cfg, &[], Face::Cli).unwrap();
    /// assert_eq!(cfg.simulation.record_periods, 50);
    /// let twice = o.apply(&mut cfg, &["record_periods=60".into()], Face::Cli).unwrap_err();
    /// assert!(twice.to_string().contains("--periods"));
    /// ```
    pub fn apply(&self, cfg: &mut Config, sets: &[String], face: Face) -> Result<(), ConfigError> {
        let fields = [
            ("record_periods", "periods", self.periods),
            ("transient_periods", "transient", self.transient),
            ("steps_per_cycle", "steps_per_cycle", self.steps_per_cycle),
            (
                "decision_periods",
                "decision_periods",
                self.decision_periods,
            ),
            ("decision_budget", "decision_budget", self.decision_budget),
            ("follow_steps", "follow_steps", self.follow_steps),
            ("escape_copies", "escape_copies", self.escape_copies),
            ("escape_periods", "escape_periods", self.escape_periods),
            ("max_work", "max_work", self.max_work),
        ];
        for (name, option, value) in fields {
            if let Some(v) = value {
                cfg.set_by_option(
                    sets,
                    face.assignment_prefix(),
                    name,
                    &face.option(option),
                    v,
                )
                .map_err(|e| match e {
                    ConfigError::Twice { .. } => e,
                    other => ConfigError::Option {
                        given: face.given(option, v),
                        inner: Box::new(other),
                    },
                })?;
            }
        }
        if let Some(m) = &self.integrator {
            cfg.simulation.method = m.clone();
        }
        cfg.sim_options()?;
        Ok(())
    }
}
