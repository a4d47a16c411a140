//! A basin grid as a job: one item per cell.

use super::settings_of;
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

job! {
    impl[S: Recordable<2> + Sync] BasinsJob<'_, S>: (usize, Outcome) => BasinResult, by usize;
    kind(j) "basins";
    total(j) j.opts.x.n * j.opts.v.n;
    id_of(j, c) (c.0 < j.total()).then_some(c.0);
    settings(j) settings_of(j.opts);
    run(j, done, on_done) {
        let done: HashMap<usize, Outcome> = done.into_iter().map(|(k, v)| (k, v.1)).collect();
        Ok(basins(j.model, j.opts, &done, |c, o| on_done(&(c, o.clone()))))
    }
}
