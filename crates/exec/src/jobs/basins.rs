//! A basin grid as a job: one item per cell.

use super::settings_of;
use crate::job::{ExecError, Job};
use geardyn_analysis::attractor::{Outcome, Recordable};
use geardyn_analysis::basins::{basins, BasinOptions, BasinResult};
use std::collections::HashMap;

/// A basin grid: one item per cell (row-major, x fastest), its [`Outcome`] stored as
/// `(cell, outcome)`.
pub struct BasinsJob<'a, S> {
    /// The model whose basins are drawn.
    pub model: &'a S,
    /// Checked options.
    pub opts: &'a BasinOptions,
}

impl<S: Recordable<2> + Sync> Job for BasinsJob<'_, S> {
    type Record = (usize, Outcome);
    type Id = usize;
    type Output = BasinResult;
    fn kind(&self) -> &str {
        "basins"
    }
    fn settings(&self) -> serde_json::Value {
        settings_of(self.opts)
    }
    fn total(&self) -> usize {
        self.opts.x.n * self.opts.v.n
    }
    fn id_of(&self, c: &(usize, Outcome)) -> Option<usize> {
        (c.0 < self.total()).then_some(c.0)
    }
    fn run(
        &self,
        done: HashMap<usize, (usize, Outcome)>,
        on_done: &(dyn Fn(&(usize, Outcome)) + Sync),
    ) -> Result<BasinResult, ExecError> {
        let done: HashMap<usize, Outcome> = done.into_iter().map(|(k, v)| (k, v.1)).collect();
        Ok(basins(self.model, self.opts, &done, |c, o| {
            on_done(&(c, o.clone()))
        }))
    }
}
