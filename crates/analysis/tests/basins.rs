//! Basins of attraction: symmetry, sums, refinement, determinism, early termination.

use geardyn_analysis::attractor::{IdentifyOptions, StrobeOnly};
use geardyn_analysis::basins::{basins, Axis, BasinOptions};
use geardyn_analysis::simulate::SimOptions;
use geardyn_model::reference::Duffing;
use geardyn_model::{presets, MeshModel};
use geardyn_solvers::Scheme;
use std::collections::HashMap;

fn in_pool<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f)
}

#[test]
fn symmetric_pair_of_attractors_has_equal_basins() {
    // unforced damped double-well Duffing: x'' + 0.25 x' - x + x^3 = 0, attractors (+-1, 0),
    // symmetric under (x, v) -> (-x, -v); the grid is symmetric too
    let sys = StrobeOnly {
        sys: Duffing {
            delta: 0.25,
            alpha: -1.0,
            beta: 1.0,
            gamma: 0.0,
            omega: 1.0,
        },
        period: 2.0,
        scheme: Scheme::dopri_default(),
    };
    let opts = BasinOptions {
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
        identify: IdentifyOptions {
            sim: SimOptions {
                transient_periods: 60,
                record_periods: 8,
                ..Default::default()
            },
            ..Default::default()
        },
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
        identify: IdentifyOptions {
            sim: SimOptions {
                transient_periods: 200,
                record_periods: 32,
                ..Default::default()
            },
            ..Default::default()
        },
    };
    let coarse = in_pool(1, || basins(&m, &opts(16), &HashMap::new(), |_, _| {}));
    let coarse2 = in_pool(2, || basins(&m, &opts(16), &HashMap::new(), |_, _| {}));
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
