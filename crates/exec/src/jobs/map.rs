//! A two-parameter map as a job: one item per cell.

use super::settings_of;
use crate::job::{ExecError, ItemJob, Job};
use geardyn_analysis::map2d::{map2d, map2d_cells, MapCell, MapOptions};
use geardyn_scenario::Scenario;
use std::collections::HashMap;

/// A two-parameter map: one item per cell (row-major, x fastest), a [`MapCell`] each.
pub struct MapJob<'a> {
    /// The scenario the two parameters are set on.
    pub scenario: &'a Scenario,
    /// Checked options.
    pub opts: &'a MapOptions,
}

impl Job for MapJob<'_> {
    type Record = MapCell;
    type Id = usize;
    type Output = Vec<MapCell>;
    fn kind(&self) -> &str {
        "map2d"
    }
    fn settings(&self) -> serde_json::Value {
        settings_of(self.opts)
    }
    fn total(&self) -> usize {
        self.opts.x_values.len() * self.opts.y_values.len()
    }
    fn id_of(&self, c: &MapCell) -> Option<usize> {
        (c.index < self.total()).then_some(c.index)
    }
    fn run(
        &self,
        done: HashMap<usize, MapCell>,
        on_done: &(dyn Fn(&MapCell) + Sync),
    ) -> Result<Vec<MapCell>, ExecError> {
        map2d(self.scenario, self.opts, &done, on_done).map_err(ExecError::analysis)
    }
}

impl ItemJob for MapJob<'_> {
    fn run_items(
        &self,
        items: &[usize],
        on_done: &(dyn Fn(&MapCell) + Sync),
    ) -> Result<Vec<MapCell>, ExecError> {
        map2d_cells(self.scenario, self.opts, items, on_done).map_err(ExecError::analysis)
    }
}
