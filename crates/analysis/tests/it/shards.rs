//! The parts of a map or a sweep that a shard of a distributed plan computes
//! (`map2d_cells`, `run_sweep_tasks`) equal the whole computation's, whatever the grouping of the
//! points: a point's result depends on nothing but the point (also in the lockstep lanes).

use geardyn_analysis::bifurcation::{
    linspace, run_sweep, run_sweep_tasks, Section, SweepMode, SweepOptions, Task,
};
use geardyn_analysis::map2d::{map2d, map2d_cells, MapOptions};
use geardyn_analysis::simulate::{Method, SimOptions};
use geardyn_model::presets;
use geardyn_scenario::Scenario;
use std::collections::HashMap;

fn sim(rk4: bool) -> SimOptions {
    SimOptions {
        method: if rk4 {
            Method::Rk4 {
                steps_per_cycle: 256,
            }
        } else {
            Method::default()
        },
        transient_periods: 60,
        record_periods: 20,
        decision_periods: 300,
        ..Default::default()
    }
}

#[test]
fn map_cells_in_any_grouping_equal_the_whole_map() {
    let base = Scenario::dimensionless(presets::classic()).unwrap();
    for rk4 in [true, false] {
        let o = MapOptions {
            x_param: "omega".into(),
            x_values: linspace(0.6, 1.2, 5),
            y_param: "F".into(),
            y_values: linspace(0.05, 0.2, 3),
            sim: sim(rk4),
            y0: [0.0, 0.0],
            lyapunov: rk4,
        };
        let whole = map2d(&base, &o, &HashMap::new(), |_| {}).unwrap();
        for groups in [
            vec![vec![14, 0, 7], (1..7).collect(), (8..14).collect()],
            (0..15).map(|i| vec![i]).collect::<Vec<_>>(),
        ] {
            for g in groups {
                let part = map2d_cells(&base, &o, &g, |_| {}).unwrap();
                for (i, c) in g.iter().zip(&part) {
                    assert_eq!(c, &whole[*i], "cell {i}, rk4 {rk4}");
                }
            }
        }
        assert!(map2d_cells(&base, &o, &[15], |_| {}).is_err());
    }
}

#[test]
fn sweep_tasks_in_any_grouping_equal_the_whole_sweep() {
    let base = Scenario::dimensionless(presets::classic()).unwrap();
    let o = SweepOptions {
        param: "omega".into(),
        values: linspace(0.6, 1.4, 6),
        mode: SweepMode::Multi {
            ics: 3,
            seed: 7,
            x0_range: (-1.5, 1.5),
            v0_range: (-1.0, 1.0),
        },
        sim: sim(true),
        y0: [0.0, 0.0],
        sections: vec![Section::Strobe],
        lyapunov: true,
    };
    let whole = run_sweep(&base, &o, &HashMap::new(), |_| {}).unwrap();
    for g in [vec![5, 0], vec![1, 2, 3, 4]] {
        let tasks: Vec<Task> = g.iter().map(|&index| Task { index, branch: 0 }).collect();
        let part = run_sweep_tasks(&base, &o, &tasks, |_| {}).unwrap();
        for r in &part {
            assert_eq!(r, &whole[r.task.index]);
        }
        assert_eq!(part.len(), g.len());
    }
    let mut cont = o.clone();
    cont.mode = SweepMode::Sweep;
    assert!(run_sweep_tasks(
        &base,
        &cont,
        &[Task {
            index: 0,
            branch: 1
        }],
        |_| {}
    )
    .is_err());
}
