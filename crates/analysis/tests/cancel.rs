//! Stop requests (`geardyn_analysis::cancel`, Ctrl-C in Python): a requested stop ends scalar
//! and lane integrations at once, and a sweep hands on no run it cut short. One test in its own
//! binary: the request is process-wide and would stop the other tests of a shared binary.

use geardyn_analysis::bifurcation::{linspace, run_sweep, Section, SweepMode, SweepOptions};
use geardyn_analysis::cancel;
use geardyn_analysis::simulate::{simulate, Method, SimError, SimOptions};
use geardyn_model::presets;
use geardyn_solvers::SolverError;
use std::collections::HashMap;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

#[test]
fn a_requested_stop_ends_runs_and_hands_on_nothing_cut_short() {
    let m = geardyn_model::MeshModel::new(&presets::classic()).unwrap();
    // scalar (DP5) and lanes (RK4), each long enough to run for minutes
    let long = SimOptions {
        transient_periods: 50_000_000,
        record_periods: 10,
        ..Default::default()
    };
    let base = geardyn_scenario::Scenario::dimensionless(presets::classic()).unwrap();
    for method in [
        Method::default(),
        Method::Rk4 {
            steps_per_cycle: 128,
        },
    ] {
        let sim = SimOptions { method, ..long };
        // a plain run
        cancel::clear();
        let stopper = std::thread::spawn(|| {
            std::thread::sleep(Duration::from_millis(200));
            cancel::request();
        });
        let t = Instant::now();
        let r = simulate(&m, [0.0, 0.0], &sim);
        stopper.join().unwrap();
        assert!(
            matches!(r, Err(SimError::Solver(SolverError::Cancelled))),
            "{r:?}"
        );
        assert!(t.elapsed() < Duration::from_secs(5), "{:?}", t.elapsed());
        // a sweep of such runs: the stop cuts every run, and none of them reaches on_done
        cancel::clear();
        let opts = SweepOptions {
            param: "omega".into(),
            values: linspace(0.8, 1.4, 16),
            mode: SweepMode::Fixed,
            sim,
            y0: [0.0, 0.0],
            sections: vec![Section::Strobe],
            lyapunov: false,
        };
        let handed = AtomicUsize::new(0);
        let stopper = std::thread::spawn(|| {
            std::thread::sleep(Duration::from_millis(300));
            cancel::request();
        });
        let t = Instant::now();
        let _ = run_sweep(&base, &opts, &HashMap::new(), |_| {
            handed.fetch_add(1, Ordering::Relaxed);
        });
        stopper.join().unwrap();
        assert!(t.elapsed() < Duration::from_secs(5), "{:?}", t.elapsed());
        assert_eq!(handed.load(Ordering::Relaxed), 0, "a cut run was handed on");
        // re-armed: the next computation runs
        cancel::clear();
        let short = SimOptions {
            transient_periods: 20,
            record_periods: 5,
            ..sim
        };
        assert!(simulate(&m, [0.0, 0.0], &short).is_ok());
    }
}
