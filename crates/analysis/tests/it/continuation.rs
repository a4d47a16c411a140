//! Attractor continuation and 2-parameter maps.

use crate::common;
use crate::common::identify_periods;
use crate::common::on_threads;
use geardyn_analysis::attractor::Descriptor;
use geardyn_analysis::bifurcation::{linspace, run_sweep, SweepMode, SweepOptions, Task};
use geardyn_analysis::continuation::{
    continuation, link, ContinuationOptions, ContinuationResult, ValueAttractors,
};
use geardyn_analysis::map2d::{map2d, MapOptions};
use geardyn_analysis::simulate::SimOptions;
use geardyn_model::presets;
use std::collections::HashMap;

fn copts(values: Vec<f64>) -> ContinuationOptions {
    ContinuationOptions {
        param: "omega".into(),
        values,
        ics: 24,
        seed: 3,
        x0_range: (-3.0, 3.0),
        v0_range: (-2.0, 2.0),
        phase: 0.0,
        identify: identify_periods(300, 40),
    }
}

#[test]
fn continuation_finds_both_attractors_of_the_hysteresis_window() {
    let base = geardyn_scenario::Scenario::dimensionless(presets::classic()).unwrap();
    // forward and backward sweeps over [1.4, 1.9] land on different attractors at omega = 1.8
    let so = SweepOptions {
        param: "omega".into(),
        values: linspace(1.4, 1.9, 11),
        mode: SweepMode::Sweep,
        sim: common::periods(300, 40),
        y0: [0.0, 0.0],
        sections: vec![],
        lyapunov: false,
    };
    let sweep = run_sweep(&base, &so, &HashMap::new(), |_| {}).unwrap();
    let label = |b: u8| {
        sweep
            .iter()
            .find(|r| {
                r.task
                    == Task {
                        index: 8,
                        branch: b,
                    }
            })
            .unwrap()
            .runs[0]
            .label
            .clone()
    };
    let (up, down) = (label(1), label(2));
    let o = copts(vec![1.75, 1.8, 1.85]);
    let one = on_threads(1, || {
        continuation(&base, &o, &HashMap::new(), |_| {}).unwrap()
    });
    let two = on_threads(2, || {
        continuation(&base, &o, &HashMap::new(), |_| {}).unwrap()
    });
    assert_eq!(
        serde_json::to_string(&one).unwrap(),
        serde_json::to_string(&two).unwrap()
    );
    let at: Vec<_> = one.points.iter().filter(|p| p.value == 1.8).collect();
    let labels: Vec<&String> = at.iter().map(|p| &p.label).collect();
    assert!(
        labels.contains(&&up) && labels.contains(&&down),
        "sweeps {up} / {down}, continuation {labels:?}"
    );
    let total: f64 = at.iter().map(|p| p.fraction).sum::<f64>()
        + one.lost.iter().find(|l| l.0 == 1.8).unwrap().1;
    assert!((total - 1.0).abs() < 1e-12);
    // branches persist across the window: no spurious appearance/disappearance
    assert!(
        one.events.iter().all(|e| e.kind != "disappearance"),
        "{:?}",
        one.events
    );
    assert!(!one.intervals.is_empty());
}

#[test]
fn continuation_reports_period_doubling_of_c1() {
    // C1 doubles its period between omega = 0.85 and 0.9
    let base = geardyn_scenario::Scenario::dimensionless(presets::classic()).unwrap();
    let mut o = copts(vec![0.84, 0.92]);
    o.ics = 8;
    o.x0_range = (-0.5, 0.5);
    o.v0_range = (-0.1, 0.1);
    let r = continuation(&base, &o, &HashMap::new(), |_| {}).unwrap();
    assert!(
        r.events.iter().any(|e| e.kind == "period_doubling"),
        "{:?}\n{:?}",
        r.events,
        r.points
    );
}

#[test]
fn map_of_max_force_is_deterministic() {
    let base = geardyn_scenario::Scenario::dimensionless(presets::classic()).unwrap();
    let o = MapOptions {
        x_param: "xi".into(),
        x_values: linspace(0.05, 0.3, 4),
        y_param: "F".into(),
        y_values: linspace(0.02, 0.2, 3),
        sim: common::periods(200, 20),
        y0: [0.0, 0.0],
        lyapunov: false,
    };
    let a = on_threads(1, || map2d(&base, &o, &HashMap::new(), |_| {}).unwrap());
    let b = on_threads(2, || map2d(&base, &o, &HashMap::new(), |_| {}).unwrap());
    assert_eq!(
        serde_json::to_string(&a).unwrap(),
        serde_json::to_string(&b).unwrap()
    );
    assert_eq!(a.len(), 12);
    // at fixed error amplitude the static load raises the maximum mesh force
    assert!(a[0].max_force < a[8].max_force);
    let mut bad = o.clone();
    bad.y_values = vec![0.1, -0.5];
    assert!(map2d(&base, &bad, &HashMap::new(), |_| {})
        .unwrap_err()
        .to_string()
        .contains("F"));
}

#[test]
fn continuation_phase_moves_the_section() {
    // C1 at omega = 0.7 has one period-1 orbit; with phase 0.5 its section point is the orbit's
    // state half an excitation period after the phase-0 section, found here by a plain run
    let base = geardyn_scenario::Scenario::dimensionless(presets::classic()).unwrap();
    let mut o = copts(vec![0.7]);
    o.ics = 4;
    o.x0_range = (-0.5, 0.5);
    o.v0_range = (-0.1, 0.1);
    let at = |phase: f64| {
        let mut o = o.clone();
        o.phase = phase;
        let r = continuation(&base, &o, &HashMap::new(), |_| {}).unwrap();
        assert_eq!(r.points.len(), 1, "{:?}", r.points);
        (r.points[0].x, r.points[0].v)
    };
    let (x0, v0) = at(0.0);
    let (xh, vh) = at(0.5);
    let m = base.with("omega", 0.7).unwrap();
    let t = m.model().excitation_period();
    let sim = SimOptions {
        tau0: 0.5 * t,
        transient_periods: 300,
        record_periods: 2,
        ..Default::default()
    };
    let r = geardyn_analysis::simulate::simulate(m.model(), [x0, v0], &sim).unwrap();
    let last = r.strobe.last().unwrap();
    assert!(
        (last[1] - xh).abs() < 1e-5 && (last[2] - vh).abs() < 1e-5,
        "{last:?} vs {xh} {vh}"
    );
    assert!(
        (xh - x0).abs() + (vh - v0).abs() > 1e-2,
        "phase changed nothing"
    );
    assert!(geardyn_analysis::attractor::check_phase(1.0).is_err());
}

/// A healthy period-1 orbit `1-1-0` through `(x, -0.025)`.
fn p1(x: f64) -> Descriptor {
    Descriptor::new(1, "1-1-0".into(), true, &[[x, -0.025]], 0.3, 0.4)
}

/// A period-3 orbit `3-1-1` through `pts`.
fn p3(pts: &[[f64; 2]]) -> Descriptor {
    Descriptor::new(3, "3-1-1".into(), false, pts, 0.7, 0.6)
}

/// The branch of the point of `label` at `value`.
fn branch_of(r: &ContinuationResult, value: f64, label: &str) -> usize {
    r.points
        .iter()
        .find(|p| p.value == value && p.label == label)
        .unwrap()
        .branch
}

#[test]
fn an_orbit_described_at_both_values_keeps_its_branch() {
    // C1 near omega = 1.8 (the audit's case): the period-1 orbit moves by 0.003 between the
    // values while its initial states all go to the period-3 one and vice versa; by basin
    // overlap alone the branches swapped labels (3-1-1 -> 1-1-0 "period change", and an
    // "appearance" and a "disappearance")
    let a = ValueAttractors {
        index: 0,
        value: 1.8,
        attractors: vec![p3(&[[1.32, -1.0], [0.5, 1.2], [-1.0, 0.3]]), p1(1.3164)],
        assignment: vec![0, 0, 0, 1, 1],
    };
    // at 1.9 the period-3 orbit is recorded from another of its points (and moved a little);
    // the initial states of each orbit now reach the other
    let b = ValueAttractors {
        index: 1,
        value: 1.9,
        attractors: vec![
            p1(1.3137),
            p3(&[[0.502, 1.203], [-1.001, 0.302], [1.318, -1.0]]),
        ],
        assignment: vec![0, 0, 0, 1, 1],
    };
    let r = link("omega", &[a, b], 1e-3);
    assert_eq!(branch_of(&r, 1.8, "1-1-0"), branch_of(&r, 1.9, "1-1-0"));
    assert_eq!(branch_of(&r, 1.8, "3-1-1"), branch_of(&r, 1.9, "3-1-1"));
    assert!(r.events.is_empty(), "{:?}", r.events);
}

#[test]
fn an_orbit_that_moved_far_over_a_coarse_step_keeps_its_branch() {
    // C1, omega 1.8 -> 2.0 with 8 initial states (audit): the 3-1-1 orbit moves by ~0.3 between
    // the values, no initial state reaches it at both, and it had been reported as one branch
    // disappearing and another appearing; the 1-1-0 orbit keeps its basin
    let a = ValueAttractors {
        index: 0,
        value: 1.8,
        attractors: vec![
            p1(1.3164),
            p3(&[[1.93, 0.19], [-1.36, 0.92], [-0.75, -0.87]]),
        ],
        assignment: vec![0, 0, 0, 0, 0, 1, 0, 0],
    };
    let b = ValueAttractors {
        index: 1,
        value: 2.0,
        attractors: vec![p1(1.25), p3(&[[2.13, 0.52], [-1.81, 1.06], [-0.51, -1.15]])],
        assignment: vec![0, 1, 0, 0, 0, 0, 0, 0],
    };
    let r = link("omega", &[a.clone(), b.clone()], 1e-3);
    assert_eq!(branch_of(&r, 1.8, "3-1-1"), branch_of(&r, 2.0, "3-1-1"));
    assert!(r.events.is_empty(), "{:?}", r.events);
    // two new orbits of that label: which one continues is not decided by the label alone
    let mut c = b;
    c.attractors.push(p3(&[[0.1, 0.1], [0.2, 0.2], [0.3, 0.3]]));
    c.assignment[2] = 2;
    let r = link("omega", &[a, c], 1e-3);
    assert!(!r.events.is_empty());
}
