//! A parameter sweep (`bifurcation`, `response`, a report's sweep) as a job: one item per task.

use super::settings_of;
use crate::job::ExecError;
use geardyn_analysis::bifurcation::{
    run_sweep, run_sweep_tasks, tasks, SweepMode, SweepOptions, Task, TaskResult,
};
use geardyn_scenario::Scenario;
use std::collections::HashSet;

/// A sweep of checked options ([`crate::request::SweepSpec::options`]): one item per task, a
/// [`TaskResult`] each.
pub struct SweepJob<'a> {
    kind: &'a str,
    scenario: &'a Scenario,
    opts: &'a SweepOptions,
    tasks: HashSet<Task>,
}

impl<'a> SweepJob<'a> {
    /// The sweep `opts` from `scenario`, stored and shown as `kind`.
    pub fn new(kind: &'a str, scenario: &'a Scenario, opts: &'a SweepOptions) -> Self {
        SweepJob {
            kind,
            scenario,
            opts,
            tasks: tasks(opts).into_iter().collect(),
        }
    }
}

job! {
    impl[] SweepJob<'_>: TaskResult => Vec<TaskResult>, by Task;
    kind(j) j.kind;
    total(j) j.tasks.len();
    // one of this sweep's tasks, at its value, with every run of it
    id_of(j, r) {
        let runs_per_task = match j.opts.mode {
            SweepMode::Multi { ics, .. } => ics.max(1),
            _ => 1,
        };
        (j.tasks.contains(&r.task)
            && j.opts.values.get(r.task.index) == Some(&r.value)
            && r.runs.len() == runs_per_task)
            .then_some(r.task)
    };
    settings(j) settings_of(j.opts);
    run(j, done, on_done) run_sweep(j.scenario, j.opts, &done, on_done).map_err(ExecError::analysis);
    run_items(j, items, on_done) run_sweep_tasks(j.scenario, j.opts, items, on_done).map_err(ExecError::analysis)
}
