//! Attractors continued over a parameter as a job: one item per value.

use super::settings_of;
use crate::job::ExecError;
use geardyn_analysis::continuation::{
    continuation, ContinuationOptions, ContinuationResult, ValueAttractors,
};
use geardyn_scenario::Scenario;

/// Attractors continued over a parameter: one item per value, a [`ValueAttractors`] each.
pub struct ContinuationJob<'a> {
    /// The scenario the values are set on.
    pub scenario: &'a Scenario,
    /// Checked options.
    pub opts: &'a ContinuationOptions,
}

job! {
    impl[] ContinuationJob<'_>: ValueAttractors => ContinuationResult, by usize;
    kind(j) "continuation";
    total(j) j.opts.values.len();
    id_of(j, v) (v.index < j.total()).then_some(v.index);
    settings(j) settings_of(j.opts);
    run(j, done, on_done) continuation(j.scenario, j.opts, &done, on_done).map_err(ExecError::analysis)
}
