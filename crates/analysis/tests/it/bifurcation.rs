//! Sweeps: determinism across thread counts, resumption, hysteresis versus coexistence.

use crate::common;
use crate::common::on_threads;
use geardyn_analysis::bifurcation::{
    detect_jumps, linspace, run_sweep, Section, SweepMode, SweepOptions, Task, TaskResult,
};
use geardyn_model::presets;
use std::collections::HashMap;

fn opts(values: Vec<f64>, mode: SweepMode) -> SweepOptions {
    SweepOptions {
        param: "omega".into(),
        values,
        mode,
        sim: common::periods(300, 40),
        y0: [0.0, 0.0],
        sections: vec![Section::Strobe, Section::DsUp, Section::DsDown],
        lyapunov: false,
    }
}

fn multi(ics: usize) -> SweepMode {
    SweepMode::Multi {
        ics,
        seed: 7,
        x0_range: (-1.5, 1.5),
        v0_range: (-1.0, 1.0),
    }
}

#[test]
fn identical_results_for_any_thread_count() {
    let base = geardyn_scenario::Scenario::dimensionless(presets::classic()).unwrap();
    for mode in [SweepMode::Fixed, SweepMode::Sweep, multi(4)] {
        let o = opts(linspace(0.8, 1.4, 7), mode);
        let one = on_threads(1, || run_sweep(&base, &o, &HashMap::new(), |_| {}).unwrap());
        let two = on_threads(2, || run_sweep(&base, &o, &HashMap::new(), |_| {}).unwrap());
        let four = on_threads(4, || run_sweep(&base, &o, &HashMap::new(), |_| {}).unwrap());
        let js = |r: &Vec<TaskResult>| serde_json::to_string(r).unwrap();
        assert_eq!(js(&one), js(&two));
        assert_eq!(js(&one), js(&four));
    }
}

#[test]
fn resumed_sweep_equals_uninterrupted_one() {
    let base = geardyn_scenario::Scenario::dimensionless(presets::classic()).unwrap();
    for mode in [SweepMode::Sweep, multi(3)] {
        let o = opts(linspace(0.9, 1.3, 6), mode);
        let full = run_sweep(&base, &o, &HashMap::new(), |_| {}).unwrap();
        // an interrupted run finished every other task; they go through JSON as in a checkpoint
        let done: HashMap<Task, TaskResult> = full
            .iter()
            .enumerate()
            .filter(|(i, _)| i % 2 == 0 || *i < 2)
            .map(|(_, r)| {
                let back: TaskResult =
                    serde_json::from_str(&serde_json::to_string(r).unwrap()).unwrap();
                (r.task, back)
            })
            .collect();
        let recomputed = std::sync::atomic::AtomicUsize::new(0);
        let resumed = run_sweep(&base, &o, &done, |r| {
            assert!(!done.contains_key(&r.task), "finished task recomputed");
            recomputed.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        })
        .unwrap();
        assert_eq!(
            serde_json::to_string(&full).unwrap(),
            serde_json::to_string(&resumed).unwrap()
        );
        assert!(recomputed.into_inner() > 0);
    }
}

#[test]
fn continuation_hysteresis_where_multi_initial_shows_coexistence() {
    // C1 for omega in [1.75, 1.85]: the sweep coming down from chaos and the sweep going up from
    // the resonance settle on different attractors at the same omega.
    let base = geardyn_scenario::Scenario::dimensionless(presets::classic()).unwrap();
    let values = linspace(1.4, 1.9, 11);
    let sweep = run_sweep(
        &base,
        &opts(values.clone(), SweepMode::Sweep),
        &HashMap::new(),
        |_| {},
    )
    .unwrap();
    let at = |branch: u8, i: usize| {
        sweep
            .iter()
            .find(|r| r.task == Task { index: i, branch })
            .unwrap()
    };
    let i = 8; // omega = 1.8
    assert!((values[i] - 1.8).abs() < 1e-12);
    let (up, down) = (&at(1, i).runs[0], &at(2, i).runs[0]);
    let (ru, rd) = (up.amplitudes.unwrap().rms_x, down.amplitudes.unwrap().rms_x);
    assert!(
        (ru - rd).abs() > 0.3,
        "no hysteresis at omega = 1.8: {} {} / {} {}",
        up.label,
        ru,
        down.label,
        rd
    );
    // the multi-initial diagram at the same value finds both
    let m = run_sweep(&base, &opts(vec![1.8], multi(24)), &HashMap::new(), |_| {}).unwrap();
    let near = |rms: f64| {
        m[0].runs
            .iter()
            .any(|r| (r.amplitudes.unwrap().rms_x - rms).abs() < 0.02)
    };
    assert!(
        near(ru) && near(rd),
        "multi-initial misses an attractor: {:?}",
        m[0].runs.iter().map(|r| &r.label).collect::<Vec<_>>()
    );
    // and the frequency-response jump of the down sweep lies inside the coexistence range
    let resp = run_sweep(
        &base,
        &opts(linspace(0.7, 1.2, 26), SweepMode::Sweep),
        &HashMap::new(),
        |_| {},
    )
    .unwrap();
    let jumps = detect_jumps(&resp);
    assert!(
        jumps
            .iter()
            .any(|j| j.branch == "down" && j.from > 0.75 && j.from < 0.85),
        "{jumps:?}"
    );
}

#[test]
fn invalid_values_are_rejected_before_work_starts() {
    let base = geardyn_scenario::Scenario::dimensionless(presets::classic()).unwrap();
    let mut o = opts(vec![0.5, -1.0], SweepMode::Fixed);
    let e = run_sweep(&base, &o, &HashMap::new(), |_| panic!("no work expected")).unwrap_err();
    assert!(e.to_string().contains("omega"), "{e}");
    o.param = "nonsense".into();
    assert!(run_sweep(&base, &o, &HashMap::new(), |_| {}).is_err());
}

#[test]
fn a_mode_from_its_name_is_checked_once_for_every_face() {
    use geardyn_analysis::bifurcation::{attractor_region, ModeError, MAX_ICS};
    assert_eq!(
        SweepMode::from_name("fixed", 0, 0, None, None, 1.0),
        Ok(SweepMode::Fixed)
    );
    // multi: the attractor region of the largest half backlash by default
    let region = attractor_region(1.2);
    assert_eq!(
        SweepMode::from_name("multi", 8, 3, None, None, 1.2),
        Ok(SweepMode::Multi {
            ics: 8,
            seed: 3,
            x0_range: region.0,
            v0_range: region.1
        })
    );
    assert_eq!(region.0, (-(1.2 + 3.6), 1.2 + 3.6));
    assert_eq!(
        SweepMode::from_name("multi", 0, 3, None, None, 1.0),
        Err(ModeError::Ics(0))
    );
    assert_eq!(
        SweepMode::from_name("multi", MAX_ICS + 1, 3, None, None, 1.0),
        Err(ModeError::Ics(MAX_ICS + 1))
    );
    assert!(SweepMode::from_name("multi", MAX_ICS, 3, None, None, 1.0).is_ok());
    assert!(matches!(
        SweepMode::from_name("multi", 4, 3, Some((1.0, f64::NAN)), None, 1.0),
        Err(ModeError::Range {
            name: "x0_range",
            ..
        })
    ));
    assert_eq!(
        SweepMode::from_name("both", 4, 3, None, None, 1.0),
        Err(ModeError::Name("both".into()))
    );
}
