//! Basins of attraction: symmetry, sums, refinement, determinism, early termination.

use crate::common::double_well;
use crate::common::identify_periods;
use crate::common::on_threads;
use geardyn_analysis::attractor::{IdentifyOptions, Outcome};
use geardyn_analysis::basins::{basins, Axis, BasinOptions};
use geardyn_analysis::simulate::SimOptions;
use geardyn_model::{presets, MeshModel};
use std::collections::HashMap;

#[test]
fn symmetric_pair_of_attractors_has_equal_basins() {
    // unforced damped double-well Duffing: x'' + 0.25 x' - x + x^3 = 0, attractors (+-1, 0),
    // symmetric under (x, v) -> (-x, -v); the grid is symmetric too
    let sys = double_well();
    let opts = BasinOptions {
        slice: Default::default(),
        x: Axis {
            min: -2.0,
            max: 2.0,
            n: 40,
        },
        v: Axis {
            min: -2.0,
            max: 2.0,
            n: 40,
        },
        identify: identify_periods(60, 8),
    };
    let r = basins(&sys, &opts, &HashMap::new(), |_, _| {});
    assert_eq!(r.attractors.len(), 2, "{:?}", r.attractors);
    let (a, b) = (&r.attractors[0], &r.attractors[1]);
    assert!((a.descriptor.points[0][0].abs() - 1.0).abs() < 1e-4);
    assert!(
        (a.fraction - b.fraction).abs() < 1.0 / 1600.0 + 1e-12,
        "{} vs {}",
        a.fraction,
        b.fraction
    );
    let sum: f64 = r.attractors.iter().map(|a| a.fraction).sum::<f64>() + r.diverged + r.failed;
    assert!((sum - 1.0).abs() < 1e-12);
    // the symmetric image of each cell belongs to the other attractor
    let n = 40;
    for iv in 0..n {
        for ix in 0..n {
            let c = r.cells[iv * n + ix];
            let m = r.cells[(n - 1 - iv) * n + (n - 1 - ix)];
            assert_eq!(c + m, 1, "cell ({ix}, {iv})");
        }
    }
    assert!(
        r.captured_early > 1000,
        "early termination unused: {}",
        r.captured_early
    );
}

#[test]
fn gear_basins_are_deterministic_and_stable_under_refinement() {
    // C1 at omega = 1.8: the resonant period-1 orbit and the non-resonant one coexist
    let mut p = presets::classic();
    p.omega = 1.8;
    let m = MeshModel::new(&p).unwrap();
    let opts = |n: usize| BasinOptions {
        slice: Default::default(),
        x: Axis {
            min: -3.0,
            max: 3.0,
            n,
        },
        v: Axis {
            min: -2.0,
            max: 2.0,
            n,
        },
        identify: identify_periods(200, 32),
    };
    let coarse = on_threads(1, || basins(&m, &opts(16), &HashMap::new(), |_, _| {}));
    let coarse2 = on_threads(2, || basins(&m, &opts(16), &HashMap::new(), |_, _| {}));
    assert_eq!(coarse.cells, coarse2.cells);
    assert!(
        coarse.attractors.len() >= 2,
        "{:?}",
        coarse
            .attractors
            .iter()
            .map(|a| &a.descriptor.label)
            .collect::<Vec<_>>()
    );
    let fine = basins(&m, &opts(32), &HashMap::new(), |_, _| {});
    let labels = |r: &geardyn_analysis::basins::BasinResult| {
        r.attractors
            .iter()
            .map(|a| a.descriptor.label.clone())
            .collect::<Vec<_>>()
    };
    assert_eq!(labels(&coarse), labels(&fine));
    for (a, b) in coarse.attractors.iter().zip(&fine.attractors) {
        assert!(
            (a.fraction - b.fraction).abs() < 0.1,
            "{} vs {}",
            a.fraction,
            b.fraction
        );
    }
    // resuming from half the cells reproduces the result
    let outcomes = std::sync::Mutex::new(HashMap::new());
    let _ = basins(&m, &opts(16), &HashMap::new(), |c, o| {
        outcomes.lock().unwrap().insert(c, o.clone());
    });
    let all = outcomes.into_inner().unwrap();
    let half: HashMap<_, _> = all.into_iter().filter(|(c, _)| c % 2 == 0).collect();
    let resumed = basins(&m, &opts(16), &half, |c, _| assert!(!half.contains_key(&c)));
    assert_eq!(resumed.cells, coarse.cells);
}

#[test]
fn cell_labels_capture_only_inside_a_uniform_square() {
    use geardyn_analysis::identify::CellLabels;
    // 9 x 9 grid on [0, 9]^2 (centres at i + 0.5), lattice of every 2nd cell: nodes 0, 2, .., 8
    let axis = Axis {
        min: 0.0,
        max: 9.0,
        n: 9,
    };
    let mut labels = vec![i64::MIN; 81];
    for iv in (0..9).step_by(2) {
        for ix in (0..9).step_by(2) {
            labels[iv * 9 + ix] = 0;
        }
    }
    let mut cells = CellLabels {
        x: axis,
        v: axis,
        stride: 2,
        labels,
    };
    // the square of nodes 2..4 (centres 2.5..4.5) with its ring of nodes 0..6 is uniform
    assert_eq!(cells.lookup(&[3.0, 3.7]), Some(0));
    // too close to the edge for a ring of nodes, or outside
    assert_eq!(cells.lookup(&[1.0, 3.0]), None);
    assert_eq!(cells.lookup(&[8.8, 3.0]), None);
    assert_eq!(cells.lookup(&[-3.0, 3.0]), None);
    // one ring node of another attractor (or divergent) spoils the square
    cells.labels[6 * 9 + 6] = 1;
    assert_eq!(cells.lookup(&[3.0, 3.7]), None);
    cells.labels[6 * 9 + 6] = -1;
    assert_eq!(cells.lookup(&[3.0, 3.7]), None);
    cells.labels[6 * 9 + 6] = 0;
    assert_eq!(cells.lookup(&[3.0, 3.7]), Some(0));
}

#[test]
fn cell_capture_is_deterministic_and_equals_the_scalar_path() {
    // C1 at omega = 1.8, RK4 lanes: most cells of the later passes are captured by the labelled
    // cells; the result is the same for 1 and 2 threads and on the scalar path
    use geardyn_analysis::basins::basins_scalar;
    let mut p = presets::classic();
    p.omega = 1.8;
    let m = MeshModel::new(&p).unwrap();
    let axis = |n, r: f64| Axis { min: -r, max: r, n };
    let identify = crate::common::identify_rk4(128, 300, 16);
    let opts = BasinOptions {
        slice: Default::default(),
        x: axis(40, 2.0),
        v: axis(40, 1.5),
        identify,
    };
    let quick = std::sync::atomic::AtomicUsize::new(0);
    let one = on_threads(1, || {
        basins(&m, &opts, &HashMap::new(), |_, o| {
            // capture by an attractor needs tens of periods (from O(1) to 1e-4 of it); by the
            // labelled cells, a few
            if matches!(o, Outcome::Captured { periods, .. } if *periods <= 10) {
                quick.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            }
        })
    });
    let two = on_threads(2, || basins(&m, &opts, &HashMap::new(), |_, _| {}));
    assert_eq!(one.cells, two.cells);
    assert_eq!(one.periods, two.periods);
    // the scalar path: the same cells (a capture may come a period apart: the lanes' phase
    // tables differ from the scalar path by ulps)
    let scalar = basins_scalar(&m, &opts, &HashMap::new(), |_, _| {});
    assert_eq!(one.cells, scalar.cells);
    assert!(one.periods.abs_diff(scalar.periods) * 1000 < one.periods);
    let quick = quick.into_inner();
    assert!(
        quick > 800,
        "{quick} of 1600 cells captured within 10 periods"
    );
    assert!(one.attractors.len() >= 2);
}

#[test]
fn an_orbit_still_approaching_a_lower_period_is_not_a_second_attractor() {
    // internal preset at omega = 0.7: one healthy period-2 orbit (2-2-0-2-0, checked by a
    // 3000-period transient, classification.rs) with a slowly decaying mode; the cells that had
    // not settled when recorded had made a "period-4 attractor" of 99.94 % of the grid beside it
    let mut spec = geardyn_scenario::ScenarioSpec::preset("internal").unwrap();
    spec.set("omega", 0.7).unwrap();
    let m = spec.resolve().unwrap().model().clone();
    let opts = BasinOptions {
        slice: Default::default(),
        x: Axis {
            min: -2.0,
            max: 2.0,
            n: 16,
        },
        v: Axis {
            min: -1.5,
            max: 1.5,
            n: 16,
        },
        identify: IdentifyOptions {
            sim: SimOptions {
                method: geardyn_analysis::simulate::Method::Dopri {
                    rtol: 1e-7,
                    atol: 1e-10,
                },
                ..IdentifyOptions::default().sim
            },
            ..Default::default()
        },
    };
    let r = basins(&m, &opts, &HashMap::new(), |_, _| {});
    let labels: Vec<&str> = r
        .attractors
        .iter()
        .map(|a| a.descriptor.label.as_str())
        .collect();
    assert_eq!(labels, ["2-2-0-2-0"], "{:?}", r.attractors);
}

#[test]
fn cells_behind_the_rigid_back_stop_are_left_out_of_the_shares() {
    // the broken pair's back side is a rigid stop at x = -D = -1 (impact law): a start at
    // x0 < -1 is no state of the model; counted, it would start from its projection onto the
    // stop (referee of issue 48: 24 such cells of a box all went to the chaotic set)
    let mut p = presets::breakage();
    p.omega = 1.2;
    p.load = 0.1;
    let m = MeshModel::new(&p).unwrap();
    let opts = BasinOptions {
        slice: Default::default(),
        x: Axis {
            min: -2.0,
            max: 2.0,
            n: 9,
        },
        v: Axis {
            min: -1.0,
            max: 1.0,
            n: 3,
        },
        identify: identify_periods(60, 8),
    };
    let r = basins(&m, &opts, &HashMap::new(), |c, _| {
        assert!(
            opts.x.value(c % 9) >= -1.0,
            "cell {c} behind the stop was run"
        )
    });
    let behind = |c: usize| opts.x.value(c % 9) < -1.0;
    for (c, &id) in r.cells.iter().enumerate() {
        assert_eq!(
            id == geardyn_analysis::basins::INADMISSIBLE,
            behind(c),
            "cell {c}: {id}"
        );
    }
    // x = -2, -1.5 of 9 columns
    assert!(
        (r.inadmissible - 2.0 / 9.0).abs() < 1e-12,
        "{}",
        r.inadmissible
    );
    let sum: f64 = r.attractors.iter().map(|a| a.fraction).sum::<f64>() + r.diverged + r.failed;
    assert!(
        (sum - 1.0).abs() < 1e-12,
        "shares of the admissible cells sum to {sum}"
    );
    let cells: usize = r.attractors.iter().map(|a| a.cells).sum();
    assert_eq!(cells, 27 - 6);
    // a model without a rigid stop admits every state
    let c1 = MeshModel::new(&presets::classic()).unwrap();
    let opts_c1 = BasinOptions {
        identify: identify_periods(20, 4),
        ..opts
    };
    let r1 = basins(&c1, &opts_c1, &HashMap::new(), |_, _| {});
    assert_eq!(r1.inadmissible, 0.0);
    assert!(r1.cells.iter().all(|&c| c >= 0));
}

#[test]
fn random_initial_states_are_drawn_in_front_of_the_back_stop() {
    use geardyn_analysis::continuation::{initial_state, ContinuationOptions};
    use geardyn_solvers::HybridSystem;
    let m = MeshModel::new(&presets::breakage()).unwrap();
    let opts = ContinuationOptions {
        param: "F".into(),
        values: vec![0.1],
        ics: 400,
        seed: 7,
        x0_range: (-4.0, 4.0),
        v0_range: (-3.0, 3.0),
        phase: 0.0,
        identify: IdentifyOptions::default(),
    };
    let ys: Vec<[f64; 2]> = (0..400)
        .map(|ic| initial_state(&opts, ic, |y| m.admissible(0.0, y)))
        .collect();
    assert!(ys.iter().all(|y| y[0] >= -1.0 && y[0] <= 4.0));
    // uniform over the admissible part [-1, 4]: mean 1.5 (s.e. 5/sqrt(12 * 400) = 0.072)
    let mean = ys.iter().map(|y| y[0]).sum::<f64>() / ys.len() as f64;
    assert!((mean - 1.5).abs() < 0.3, "{mean}");
    // the same draws without a stop: some lie behind it
    let free: Vec<[f64; 2]> = (0..400)
        .map(|ic| initial_state(&opts, ic, |_| true))
        .collect();
    assert!(free.iter().filter(|y| y[0] < -1.0).count() > 100);
}
