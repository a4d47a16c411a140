//! The vibration signals of a pair (and of its healthy twin) as a job.

use super::settings_of;
use crate::job::{ExecError, Job};
use geardyn_analysis::signals::{run_signals, SignalsRequest, SignalsResult};
use geardyn_scenario::Scenario;
use std::collections::HashMap;

/// The signals of `request` from `scenario`: one item, one result.
pub struct SignalsJob<'a> {
    /// The pair (broken or healthy).
    pub scenario: &'a Scenario,
    /// The request (checked when run).
    pub request: &'a SignalsRequest,
}

impl Job for SignalsJob<'_> {
    type Record = SignalsResult;
    type Id = ();
    type Output = SignalsResult;
    fn kind(&self) -> &str {
        "signals"
    }
    fn settings(&self) -> serde_json::Value {
        settings_of(self.request)
    }
    fn total(&self) -> usize {
        1
    }
    fn id_of(&self, _: &SignalsResult) -> Option<()> {
        None
    }
    fn run(
        &self,
        _done: HashMap<(), SignalsResult>,
        on_done: &(dyn Fn(&SignalsResult) + Sync),
    ) -> Result<SignalsResult, ExecError> {
        let r = run_signals(self.scenario, self.request).map_err(ExecError::analysis)?;
        on_done(&r);
        Ok(r)
    }
}
