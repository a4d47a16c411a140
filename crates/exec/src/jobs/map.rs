//! A two-parameter map as a job: one item per cell.

use super::settings_of;
use crate::job::ExecError;
use geardyn_analysis::map2d::{map2d, map2d_cells, MapCell, MapOptions};
use geardyn_scenario::Scenario;

/// A two-parameter map: one item per cell (row-major, x fastest), a [`MapCell`] each.
pub struct MapJob<'a> {
    /// The scenario the two parameters are set on.
    pub scenario: &'a Scenario,
    /// Checked options.
    pub opts: &'a MapOptions,
}

job! {
    impl[] MapJob<'_>: MapCell => Vec<MapCell>, by usize;
    kind(j) "map2d";
    total(j) j.opts.x_values.len() * j.opts.y_values.len();
    id_of(j, c) (c.index < j.total()).then_some(c.index);
    settings(j) settings_of(j.opts);
    run(j, done, on_done) map2d(j.scenario, j.opts, &done, on_done).map_err(ExecError::analysis);
    run_items(j, items, on_done) map2d_cells(j.scenario, j.opts, items, on_done).map_err(ExecError::analysis)
}
