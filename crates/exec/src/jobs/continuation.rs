//! Attractors continued over a parameter as a job: one item per value.

use super::settings_of;
use crate::job::{ExecError, Job};
use geardyn_analysis::continuation::{
    continuation, ContinuationOptions, ContinuationResult, ValueAttractors,
};
use geardyn_scenario::Scenario;
use std::collections::HashMap;

/// Attractors continued over a parameter: one item per value, a [`ValueAttractors`] each.
pub struct ContinuationJob<'a> {
    /// The scenario the values are set on.
    pub scenario: &'a Scenario,
    /// Checked options.
    pub opts: &'a ContinuationOptions,
}

impl Job for ContinuationJob<'_> {
    type Record = ValueAttractors;
    type Id = usize;
    type Output = ContinuationResult;
    fn kind(&self) -> &str {
        "continuation"
    }
    fn settings(&self) -> serde_json::Value {
        settings_of(self.opts)
    }
    fn total(&self) -> usize {
        self.opts.values.len()
    }
    fn id_of(&self, v: &ValueAttractors) -> Option<usize> {
        (v.index < self.total()).then_some(v.index)
    }
    fn run(
        &self,
        done: HashMap<usize, ValueAttractors>,
        on_done: &(dyn Fn(&ValueAttractors) + Sync),
    ) -> Result<ContinuationResult, ExecError> {
        continuation(self.scenario, self.opts, &done, on_done).map_err(ExecError::analysis)
    }
}
