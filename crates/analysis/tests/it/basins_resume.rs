//! A damaged basin checkpoint never panics and never changes the result: records that cannot
//! belong to the run (a capture by an attractor the pass does not know) are recomputed.

use crate::common::double_well;
use crate::common::identify_periods;
use geardyn_analysis::attractor::Outcome;
use geardyn_analysis::basins::{basins, Axis, BasinOptions};
use std::collections::HashMap;

#[test]
fn an_out_of_range_attractor_id_is_recomputed_not_trusted() {
    let sys = double_well();
    let axis = Axis {
        min: -2.0,
        max: 2.0,
        n: 12,
    };
    let opts = BasinOptions {
        slice: Default::default(),
        x: axis,
        v: axis,
        identify: identify_periods(60, 8),
    };
    let clean = basins(&sys, &opts, &HashMap::new(), |_, _| {});
    let mut done = HashMap::new();
    for c in [0usize, 5, 77, 143] {
        done.insert(
            c,
            Outcome::Captured {
                id: 999,
                periods: 3,
            },
        );
    }
    let damaged = basins(&sys, &opts, &done, |_, _| {});
    assert_eq!(clean.cells, damaged.cells);
    assert_eq!(clean.attractors.len(), damaged.attractors.len());
}
