//! A basin grid as a job: one item per cell.

use super::settings_of;
use geardyn_analysis::attractor::{Outcome, Recordable};
use geardyn_analysis::basins::{basins, BasinOptions, BasinResult};
use std::collections::HashMap;

/// A basin grid: one item per cell (row-major, x fastest), its [`Outcome`] stored as
/// `(cell, outcome)`. Any system that can be identified, of any state dimension `N` (the pair's
/// is 2, a gear train's grid lies on a slice of its state).
pub struct BasinsJob<'a, S, const N: usize = 2> {
    /// The model whose basins are drawn.
    pub model: &'a S,
    /// Checked options.
    pub opts: &'a BasinOptions<N>,
}

job! {
    impl[S: Recordable<N> + Sync, const N: usize] BasinsJob<'_, S, N>: (usize, Outcome<N>) => BasinResult<N>, by usize;
    kind(j) "basins";
    total(j) j.opts.x.n * j.opts.v.n;
    id_of(j, c) (c.0 < j.total()).then_some(c.0);
    settings(j) settings_of(j.opts);
    run(j, done, on_done) {
        let done: HashMap<usize, Outcome<N>> = done.into_iter().map(|(k, v)| (k, v.1)).collect();
        Ok(basins(j.model, j.opts, &done, |c, o| on_done(&(c, o.clone()))))
    }
}
