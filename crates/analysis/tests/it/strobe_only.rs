//! Records of the stroboscopic points alone (`SimOptions::strobe_only`, the persistence blocks of
//! a decision): the same trajectory and the same points as a full record, scalar and in the
//! lanes, and nothing else recorded.

use crate::common::lane;
use geardyn_analysis::lanes::simulate_lanes;
use geardyn_analysis::simulate::{simulate, Method, SimOptions};
use geardyn_model::{presets, MeshModel};

fn opts(method: Method, strobe_only: bool) -> SimOptions {
    SimOptions {
        method,
        transient_periods: 50,
        record_periods: 40,
        strobe_only,
        ..Default::default()
    }
}

#[test]
fn a_strobe_only_record_has_the_full_records_points_and_nothing_else() {
    let mut p = presets::classic();
    p.omega = 1.3; // chaotic: any change of the path shows
    let m = MeshModel::new(&p).unwrap();
    for method in [
        Method::Rk4 {
            steps_per_cycle: 256,
        },
        Method::default(),
    ] {
        let full = simulate(&m, [0.1, 0.0], &opts(method, false)).unwrap();
        let cheap = simulate(&m, [0.1, 0.0], &opts(method, true)).unwrap();
        assert_eq!(full.strobe, cheap.strobe, "{method:?}");
        assert_eq!(full.final_state, cheap.final_state);
        assert!(cheap.mesh().events.is_empty() && cheap.mesh_strobe.is_empty());
        assert_eq!(cheap.mesh().durations, [0.0; 3]);
        // x_range from the points: inside the full record's range
        let (lo, hi) = cheap.mesh().x_range;
        assert!(lo <= hi && lo >= full.mesh().x_range.0 && hi <= full.mesh().x_range.1);
        assert!(full.mesh().events.len() > 10 && full.mesh().max_force > 0.0);
    }
    // the lanes: the same points as their full record, and as the scalar path's
    let rk4 = Method::Rk4 {
        steps_per_cycle: 256,
    };
    let runs: Vec<(&MeshModel, [f64; 2])> = (0..5).map(|i| (&m, [0.1 * i as f64, 0.0])).collect();
    let full = simulate_lanes(&runs, &lane(&opts(rk4, false)));
    let cheap = simulate_lanes(&runs, &lane(&opts(rk4, true)));
    for (a, b) in full.iter().zip(&cheap) {
        let (a, b) = (a.as_ref().unwrap(), b.as_ref().unwrap());
        assert_eq!(a.strobe, b.strobe);
        assert_eq!(a.final_state, b.final_state);
        assert!(
            b.mesh().events.is_empty() && b.mesh().max_force == 0.0 && a.mesh().max_force > 0.0
        );
    }
}
