//! One simulation (`geardyn simulate`, Python `simulate`) as a job: the configuration resolved
//! and checked, the run decided, its folder written ([`geardyn_io::simulate_folder`]).

use crate::job::ExecError;
use geardyn_analysis::summary::Summary;
use geardyn_io::simulate_folder::{simulate, Simulated};
use geardyn_io::Config;
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

job! {
    impl[] SimulateJob<'_>: "simulate", Summary => Simulated, steps 1;
    settings(j) serde_json::json!({ "trajectory_periods": j.trajectory_periods });
    run(j, on_done) {
        let s = simulate(j.config.clone(), j.source.to_string(), j.trajectory_periods, j.out)
            .map_err(ExecError::analysis)?;
        on_done(&s.summary);
        Ok(s)
    }
}
