//! The top Lyapunov exponent of one motion as a job.

use super::settings_of;
use crate::job::{ExecError, Job};
use geardyn_analysis::lyapunov_request::{LyapunovReport, LyapunovRequest};
use geardyn_analysis::simulate::SimOptions;
use geardyn_analysis::tle_convergence::Round;
use geardyn_model::MeshModel;
use std::collections::HashMap;

/// The exponent of the motion from `y0`: one result; the observer sees each round of the
/// doubling run lengths as it ends.
pub struct LyapunovJob<'a> {
    /// The model.
    pub model: &'a MeshModel,
    /// Integration, transient and record settings.
    pub sim: &'a SimOptions,
    /// Initial state `[x, x']`.
    pub y0: [f64; 2],
    /// The request (checked when run).
    pub request: &'a LyapunovRequest,
}

impl Job for LyapunovJob<'_> {
    type Record = Round;
    type Id = u64;
    type Output = LyapunovReport;
    fn kind(&self) -> &str {
        "lyapunov"
    }
    fn settings(&self) -> serde_json::Value {
        serde_json::json!({ "request": settings_of(self.request), "sim": settings_of(self.sim), "y0": self.y0 })
    }
    fn total(&self) -> usize {
        0
    }
    fn id_of(&self, _: &Round) -> Option<u64> {
        None
    }
    fn run(
        &self,
        _done: HashMap<u64, Round>,
        on_done: &(dyn Fn(&Round) + Sync),
    ) -> Result<LyapunovReport, ExecError> {
        self.request
            .run(self.model, self.sim, self.y0, |r| on_done(r))
            .map_err(ExecError::analysis)
    }
}
