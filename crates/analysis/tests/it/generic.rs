//! The analyses on a system other than the gear model.

use geardyn_analysis::generic::{strobe_bifurcation, Family};
use geardyn_analysis::lyapunov::{tle_variational, LyapunovOptions};
use geardyn_model::reference::Duffing;
use geardyn_solvers::Scheme;

struct Forcing;
impl Family<2> for Forcing {
    type System = Duffing;
    fn at(&self, gamma: f64) -> Duffing {
        Duffing {
            delta: 0.3,
            alpha: -1.0,
            beta: 1.0,
            gamma,
            omega: 1.2,
        }
    }
    fn period(&self, _g: f64) -> f64 {
        2.0 * std::f64::consts::PI / 1.2
    }
}

#[test]
fn duffing_period_doubling_cascade() {
    // Double-well Duffing, delta = 0.3, omega = 1.2 (Guckenheimer & Holmes, Nonlinear Oscillations,
    // 1983, sec. 2.2): period 1 at gamma = 0.20, period doubling before gamma = 0.30, where the
    // motion is chaotic (the classic strange attractor), with a positive TLE there.
    let values = [0.20, 0.25, 0.27, 0.28, 0.29, 0.30];
    let d = strobe_bifurcation(
        &Forcing,
        &values,
        Scheme::dopri_default(),
        [1.0, 0.0],
        300,
        64,
        true,
    );
    let periods: Vec<usize> = d.iter().map(|b| b.period).collect();
    assert_eq!(periods[0], 1);
    assert_eq!(periods[1], 1);
    assert!(
        periods[2..5].contains(&2) && periods[2..5].contains(&4),
        "{periods:?}"
    );
    assert_eq!(periods[5], 0, "{periods:?}");
    let opts = LyapunovOptions {
        period: Forcing.period(0.3),
        transient_periods: 200,
        periods: 800,
        d0: 1e-6,
    };
    let r = tle_variational::<_, 2, 5>(
        Forcing.at(0.3),
        Scheme::dopri_default(),
        0.0,
        [1.0, 0.0],
        &opts,
    )
    .unwrap();
    assert!(r.tle > 0.05, "{}", r.tle);
    // parallel and sequential runs agree value by value
    let par = strobe_bifurcation(
        &Forcing,
        &values,
        Scheme::dopri_default(),
        [1.0, 0.0],
        100,
        8,
        false,
    );
    for (b, &v) in par.iter().zip(&values) {
        assert_eq!(b.value, v);
        assert_eq!(b.points.len(), 8);
    }
}
