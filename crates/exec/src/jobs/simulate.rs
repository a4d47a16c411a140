//! One simulation (`geardyn simulate`, Python `simulate`) as a job: the configuration resolved
//! and checked, the run decided, its folder written ([`geardyn_io::simulate_folder`]).

use crate::job::{ExecError, Job};
use geardyn_analysis::summary::Summary;
use geardyn_io::simulate_folder::{simulate, Simulated};
use geardyn_io::Config;
use std::collections::HashMap;
use std::path::Path;

/// One simulation of `config`: one item, its [`Summary`] given to the observer, the whole run
/// the output.
pub struct SimulateJob<'a> {
    /// The configuration, every override applied.
    pub config: &'a Config,
    /// What it comes from, for titles (`preset breakage`).
    pub source: &'a str,
    /// Excitation periods of the trajectory kept (`None`: all).
    pub trajectory_periods: Option<u64>,
    /// The folder written (`None`: none).
    pub out: Option<&'a Path>,
}

impl Job for SimulateJob<'_> {
    type Record = Summary;
    type Id = ();
    type Output = Simulated;
    fn kind(&self) -> &str {
        "simulate"
    }
    fn settings(&self) -> serde_json::Value {
        serde_json::json!({ "trajectory_periods": self.trajectory_periods })
    }
    fn total(&self) -> usize {
        1
    }
    fn id_of(&self, _: &Summary) -> Option<()> {
        None
    }
    fn run(
        &self,
        _done: HashMap<(), Summary>,
        on_done: &(dyn Fn(&Summary) + Sync),
    ) -> Result<Simulated, ExecError> {
        let s = simulate(
            self.config.clone(),
            self.source.to_string(),
            self.trajectory_periods,
            self.out,
        )
        .map_err(ExecError::analysis)?;
        on_done(&s.summary);
        Ok(s)
    }
}
