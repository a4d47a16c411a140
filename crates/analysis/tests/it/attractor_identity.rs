//! One motion, one attractor: basins and continuation report each attractor once, with a
//! decided class, and the list does not depend on the grid or on the transient length.

use geardyn_analysis::attractor::{Descriptor, IdentifyOptions};
use geardyn_analysis::basins::{basins, Axis, BasinOptions, BasinResult};
use geardyn_analysis::classify::Motion;
use geardyn_analysis::simulate::{Method, SimOptions};
use geardyn_model::{ContactLaw, MeshModel};
use geardyn_scenario::ScenarioSpec;
use std::collections::HashMap;

/// Seed B's Table 5.2 point (omega = 1.4, xi = 0.09, F = 0.16) on the internal preset.
fn internal_table_5_2(linear: bool) -> MeshModel {
    let mut spec = ScenarioSpec::preset("internal").unwrap();
    for (k, v) in [("omega", 1.4), ("xi", 0.09), ("F", 0.16)] {
        spec.set(k, v).unwrap();
    }
    if linear {
        spec.model.contact = ContactLaw::Linear;
    }
    spec.resolve().unwrap().model().clone()
}

fn classic(omega: f64) -> MeshModel {
    let mut spec = ScenarioSpec::preset("classic").unwrap();
    spec.set("omega", omega).unwrap();
    spec.resolve().unwrap().model().clone()
}

/// The command's default box (x0 in +-2 D_s, x0' in +-1.5) and identification settings.
fn run(model: &MeshModel, n: usize, transient: u64) -> BasinResult {
    let d = model.backlash_levels().1;
    let opts = BasinOptions {
        slice: Default::default(),
        x: Axis {
            min: -2.0 * d,
            max: 2.0 * d,
            n,
        },
        v: Axis {
            min: -1.5,
            max: 1.5,
            n,
        },
        identify: IdentifyOptions {
            sim: SimOptions {
                method: Method::Dopri {
                    rtol: 1e-7,
                    atol: 1e-10,
                },
                transient_periods: transient,
                record_periods: 64,
                ..Default::default()
            },
            ..Default::default()
        },
    };
    basins(model, &opts, &HashMap::new(), |_, _| {})
}

fn labels(r: &BasinResult) -> Vec<String> {
    let mut l: Vec<String> = r
        .attractors
        .iter()
        .map(|a| match &a.descriptor.motion {
            Motion::Periodic { .. } => a.descriptor.label.clone(),
            m => m.word().to_string(),
        })
        .collect();
    l.sort();
    l
}

/// No attractor is a copy of another: no two descriptors match, and none below 1 % of the cells
/// carries the label of a larger one.
fn assert_no_fragments(r: &BasinResult) {
    let tol = IdentifyOptions::default().match_tol;
    for (i, a) in r.attractors.iter().enumerate() {
        for b in &r.attractors[i + 1..] {
            assert!(
                !a.descriptor.matches(&b.descriptor, tol),
                "{} and {} are one attractor",
                a.descriptor.label,
                b.descriptor.label
            );
            let (small, big) = if a.fraction < b.fraction {
                (a, b)
            } else {
                (b, a)
            };
            assert!(
                small.fraction >= 0.01 || small.descriptor.label != big.descriptor.label,
                "fragment {} ({}) of {}",
                small.descriptor.label,
                small.fraction,
                big.descriptor.label
            );
        }
        assert!(
            !matches!(a.descriptor.motion, Motion::Unsettled { tle: None, .. }),
            "undecided attractor {}",
            a.descriptor.label
        );
    }
}

#[test]
fn internal_table_5_2_point_has_a_handful_of_attractors() {
    // The reproducer: with contact-law damping that remembered the initial condition this
    // basin held 46 look-alike "1-0-0-0-0" attractors.
    for linear in [false, true] {
        let r = run(&internal_table_5_2(linear), 30, 300);
        assert!(
            (1..=4).contains(&r.attractors.len()),
            "linear law {linear}: {:?}",
            labels(&r)
        );
        assert_no_fragments(&r);
        assert_eq!(r.failed, 0.0);
    }
}

#[test]
fn a_chaotic_attractor_reached_from_many_states_is_one_attractor() {
    // C1 at omega = 1.3: one chaotic attractor (TLE ~0.08 per unit time) whose short records
    // differ in how often they touch the back side; they must not become several attractors.
    let r = run(&classic(1.3), 24, 300);
    assert_eq!(r.attractors.len(), 1, "{:?}", labels(&r));
    let a = &r.attractors[0];
    assert!(
        matches!(a.descriptor.motion, Motion::Chaotic { tle, .. } if tle > 0.01),
        "{:?}",
        a.descriptor.motion
    );
    // the label is the class alone (no rates: runs and attractors group by it)
    assert_eq!(a.descriptor.label, "chaotic");
    assert_eq!(a.fraction, 1.0);
}

#[test]
fn attractor_list_is_stable_under_refinement_and_longer_transients() {
    // a periodic + chaotic coexistence (C1, omega = 1.5) and two periodic orbits (internal pair,
    // linear law, Table 5.2 point)
    for model in [classic(1.5), internal_table_5_2(true)] {
        let base = run(&model, 20, 300);
        assert!(base.attractors.len() >= 2, "{:?}", labels(&base));
        let finer = run(&model, 40, 300);
        let longer = run(&model, 20, 600);
        assert_eq!(labels(&base), labels(&finer), "grid refinement");
        assert_eq!(labels(&base), labels(&longer), "doubled transient");
        for r in [&finer, &longer] {
            assert_no_fragments(r);
            for (a, b) in base.attractors.iter().zip(&r.attractors) {
                assert!(
                    (a.fraction - b.fraction).abs() < 0.1,
                    "{}: {} vs {}",
                    a.descriptor.label,
                    a.fraction,
                    b.fraction
                );
            }
        }
    }
}

#[test]
fn chaotic_records_of_one_cloud_match_and_separate_clouds_do_not() {
    // Henon-map cloud: two records of the same orbit match, whatever they contain; the same cloud
    // moved by ten times its size does not
    let mut p = [0.1f64, 0.1];
    let mut pts = Vec::new();
    for i in 0..1300 {
        p = [1.0 - 1.4 * p[0] * p[0] + p[1], 0.3 * p[0]];
        if i >= 100 {
            pts.push(p);
        }
    }
    let first = Descriptor::new(0, "chaotic".into(), false, &pts[..64], 0.0, 0.0);
    let second = Descriptor::new(0, "chaotic".into(), false, &pts[600..1200], 0.0, 0.0);
    assert!(first.matches(&second, 1e-3) && second.matches(&first, 1e-3));
    let moved: Vec<[f64; 2]> = pts[600..1200].iter().map(|q| [q[0] + 30.0, q[1]]).collect();
    let far = Descriptor::new(0, "chaotic".into(), false, &moved, 0.0, 0.0);
    assert!(!first.matches(&far, 1e-3));
    // a record still approaching a period-2 orbit matches it once its tail is within tolerance
    let orbit = Descriptor::new(
        2,
        "2-1-1".into(),
        false,
        &[[0.5, 0.1], [0.7, -0.1]],
        0.0,
        0.0,
    );
    let approach: Vec<[f64; 2]> = (0..40)
        .map(|j| {
            let e = 0.5f64.powi(j);
            if j % 2 == 0 {
                [0.5 + e, 0.1]
            } else {
                [0.7 - e, -0.1]
            }
        })
        .collect();
    let cloud = Descriptor::new(0, "unsettled".into(), false, &approach, 0.0, 0.0);
    assert!(cloud.matches(&orbit, 1e-3));
    let early = Descriptor::new(0, "unsettled".into(), false, &approach[..6], 0.0, 0.0);
    assert!(!early.matches(&orbit, 1e-3));
}

#[test]
fn transient_chaos_is_not_an_attractor() {
    // internal preset at its operating point (omega = 1.4, F = 0.07, xi = 0.23): some initial
    // states wander chaotically for several hundred periods (TLE ~0.09) before settling on the
    // period-3 orbit; with a 2000-period transient every cell ends there. The chaotic record is
    // followed until it lands, so it is not listed as an attractor.
    let model = ScenarioSpec::preset("internal")
        .unwrap()
        .resolve()
        .unwrap()
        .model()
        .clone();
    let r = run(&model, 40, 300);
    assert_eq!(
        labels(&r),
        vec!["3-1-1-1-1".to_string()],
        "{:?}",
        labels(&r)
    );
    assert_eq!(r.attractors[0].fraction, 1.0);
}
