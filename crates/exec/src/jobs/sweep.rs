//! A parameter sweep (`bifurcation`, `response`, a report's sweep) as a job: one item per task.

use super::settings_of;
use crate::job::{ExecError, ItemJob, Job};
use geardyn_analysis::bifurcation::{
    run_sweep, run_sweep_tasks, tasks, SweepMode, SweepOptions, Task, TaskResult,
};
use geardyn_scenario::Scenario;
use std::collections::{HashMap, HashSet};

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

impl Job for SweepJob<'_> {
    type Record = TaskResult;
    type Id = Task;
    type Output = Vec<TaskResult>;
    fn kind(&self) -> &str {
        self.kind
    }
    fn settings(&self) -> serde_json::Value {
        settings_of(self.opts)
    }
    fn total(&self) -> usize {
        self.tasks.len()
    }
    fn id_of(&self, r: &TaskResult) -> Option<Task> {
        // one of this sweep's tasks, at its value, with every run of it
        let runs_per_task = match self.opts.mode {
            SweepMode::Multi { ics, .. } => ics.max(1),
            _ => 1,
        };
        (self.tasks.contains(&r.task)
            && self.opts.values.get(r.task.index) == Some(&r.value)
            && r.runs.len() == runs_per_task)
            .then_some(r.task)
    }
    fn run(
        &self,
        done: HashMap<Task, TaskResult>,
        on_done: &(dyn Fn(&TaskResult) + Sync),
    ) -> Result<Vec<TaskResult>, ExecError> {
        run_sweep(self.scenario, self.opts, &done, on_done).map_err(ExecError::analysis)
    }
}

impl ItemJob for SweepJob<'_> {
    fn run_items(
        &self,
        items: &[Task],
        on_done: &(dyn Fn(&TaskResult) + Sync),
    ) -> Result<Vec<TaskResult>, ExecError> {
        run_sweep_tasks(self.scenario, self.opts, items, on_done).map_err(ExecError::analysis)
    }
}
