//! The back-side impact model on its whole documented range: restitution R in [0, 1] and any
//! sticking speed v_stick in [0, 1). The broken pair at xi = 1, F = 0.1, omega = 1 with R = 0
//! ended "state became non-finite" (a plastic impact left the stop at zero speed straight back
//! into it, and a grazing approach was taken for a crossing); so did R >= 0.99 with
//! v_stick >= 0.5.

use geardyn_analysis::classify::{simulate_decided, Decide};
use geardyn_analysis::simulate::SimOptions;
use geardyn_scenario::ScenarioSpec;

#[test]
fn every_legal_restitution_and_sticking_speed_runs() {
    let base = ScenarioSpec::preset("breakage").unwrap().resolve().unwrap();
    let opts = SimOptions {
        transient_periods: 20,
        record_periods: 5,
        decision_periods: 100,
        ..Default::default()
    };
    for r in [0.0, 0.5, 0.99, 1.0] {
        for vs in [0.0, 0.5, 0.99] {
            let s = base
                .with_all(&[
                    ("xi", 1.0),
                    ("F", 0.1),
                    ("omega", 1.0),
                    ("R", r),
                    ("v_stick", vs),
                ])
                .unwrap();
            let out = simulate_decided(s.model(), [0.0, 0.0], &opts, Decide::default());
            let (_, summary, _) = out.unwrap_or_else(|e| panic!("R = {r}, v_stick = {vs}: {e}"));
            assert!(summary.max_force.is_finite(), "R = {r}, v_stick = {vs}");
        }
    }
}
