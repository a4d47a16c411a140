//! A token per run: cancelling one run stops it within moments and leaves a run beside it
//! untouched (its results are those of a run alone).

use geardyn_analysis::bifurcation::TaskResult;
use geardyn_exec::cancel::{run_under, Token};
use geardyn_exec::request::SweepSpec;
use geardyn_exec::{execute, Each, SweepJob};
use geardyn_io::Config;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

fn sweep(
    transient: u64,
) -> (
    geardyn_scenario::Scenario,
    geardyn_analysis::bifurcation::SweepOptions,
) {
    let mut cfg = Config::preset("classic").unwrap();
    cfg.simulation.transient_periods = transient;
    cfg.simulation.record_periods = 10;
    let scenario = cfg.resolve().unwrap();
    let spec = SweepSpec {
        values: vec![0.6, 0.7, 0.8, 0.9],
        ..SweepSpec::default()
    };
    let opts = spec.options(&cfg, &scenario).unwrap();
    (scenario, opts)
}

#[test]
fn cancelling_one_run_leaves_the_other_alone() {
    let (long_sc, long) = sweep(5_000_000);
    let (short_sc, short) = sweep(200);
    let alone = execute(&SweepJob::new("bifurcation", &short_sc, &short), None, &()).unwrap();
    let (a, b) = (Token::new(), Token::new());
    let finished_a = AtomicUsize::new(0);
    let t = Instant::now();
    let (cut, beside) = std::thread::scope(|s| {
        let cut = s.spawn(|| {
            let count = Each(|_: &TaskResult| {
                finished_a.fetch_add(1, Ordering::Relaxed);
            });
            run_under(&a, || {
                execute(&SweepJob::new("bifurcation", &long_sc, &long), None, &count).is_ok()
            })
        });
        let beside = s.spawn(|| {
            run_under(&b, || {
                execute(&SweepJob::new("bifurcation", &short_sc, &short), None, &())
            })
        });
        std::thread::sleep(Duration::from_millis(300));
        a.cancel();
        (cut.join().unwrap(), beside.join().unwrap().unwrap())
    });
    assert!(t.elapsed() < Duration::from_secs(60), "{:?}", t.elapsed());
    assert_eq!(finished_a.into_inner(), 0, "a cut run was handed on");
    let _ = cut;
    assert!(!b.is_cancelled());
    assert_eq!(beside.len(), alone.len());
    for (x, y) in beside.iter().zip(&alone) {
        assert_eq!(x.runs[0].label, y.runs[0].label);
        assert_eq!(x.runs[0].max_force.to_bits(), y.runs[0].max_force.to_bits());
    }
}
