//! Issue 13: physical invariants of the back-side impact model through the simulation API.

use crate::common;
use geardyn_analysis::simulate::{simulate, SimError};
use geardyn_model::{presets, EventKind, MeshModel};
use geardyn_solvers::SolverError;

#[test]
fn divergent_impacting_run_stops_with_an_error_instead_of_crossing_the_stop() {
    // `simulate --preset breakage --set R=1 --set v_stick=0 --set xi=50 --periods 6
    // --transient 0` used to exit 0 with impacts at x = -1.4e28 (stop at -1)
    let m = common::model(
        presets::breakage(),
        &[("R", 1.0), ("v_stick", 0.0), ("xi", 50.0)],
    );
    let opts = common::periods(0, 6);
    match simulate(&m, [0.0, 0.0], &opts) {
        Err(SimError::Solver(SolverError::NonFinite { .. })) => {}
        other => panic!("expected a non-finite (divergent) error, got {other:?}"),
    }
}

#[test]
fn impacts_stay_on_the_stop_and_outputs_stay_finite() {
    let m = MeshModel::new(&presets::breakage()).unwrap();
    let opts = common::periods(2, 4);
    let res = simulate(&m, [0.0, 0.0], &opts).unwrap();
    let d = 1.0;
    assert!(
        res.mesh().x_range.0 >= -d - 1e-9,
        "{:?}",
        res.mesh().x_range
    );
    assert!(res.mesh().max_force.is_finite() && res.mesh().min_force.is_finite());
    let mut impacts = 0;
    for e in &res.mesh().events {
        assert!(e.peak_force.is_finite());
        if e.kind == EventKind::Impact {
            impacts += 1;
            assert!((e.x + d).abs() < 1e-9, "{e:?}");
            assert!(e.v_before < 0.0 && e.v_after >= 0.0, "{e:?}");
        }
    }
    assert!(impacts > 0);
}
