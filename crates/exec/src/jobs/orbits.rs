//! Periodic orbits (one orbit, or a branch continued over a parameter) as a job.

use super::settings_of;
use crate::job::{ExecError, Job};
use geardyn_analysis::orbit_branches::{BranchPoint, Continuation};
use geardyn_analysis::orbits_request::{run_orbits, OrbitsRequest};
use geardyn_scenario::Scenario;
use std::collections::HashMap;

/// The orbits of `request` from `scenario`: one result; the observer sees each orbit of the
/// branch as it is found (the total is not known in advance: it starts at 0).
pub struct OrbitsJob<'a> {
    /// The scenario the orbits are of.
    pub scenario: &'a Scenario,
    /// The request (checked when run).
    pub request: &'a OrbitsRequest,
}

impl Job for OrbitsJob<'_> {
    type Record = BranchPoint;
    type Id = usize;
    type Output = Continuation;
    fn kind(&self) -> &str {
        "orbits"
    }
    fn settings(&self) -> serde_json::Value {
        settings_of(self.request)
    }
    fn total(&self) -> usize {
        0
    }
    fn id_of(&self, _: &BranchPoint) -> Option<usize> {
        // a branch is one Newton-continued chain: not resumed point by point
        None
    }
    fn run(
        &self,
        _done: HashMap<usize, BranchPoint>,
        on_done: &(dyn Fn(&BranchPoint) + Sync),
    ) -> Result<Continuation, ExecError> {
        run_orbits(self.scenario, self.request, on_done).map_err(ExecError::analysis)
    }
}
