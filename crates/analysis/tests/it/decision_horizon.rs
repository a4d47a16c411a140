//! The chaos verdict at the decision horizon (docs/analyses.md, classification rule 2): a positive
//! exponent is followed to `decision_periods` before the motion is called chaotic, a chaotic
//! transient that ends before it is periodic, and a budget that cuts the horizon short leaves the
//! run unsettled. Each case was chaotic under the former rule (one 500-cycle persistence run).

use crate::common;

use geardyn_analysis::classify::{DecidedBy, Motion, DECISION_PERIODS};
use geardyn_analysis::simulate::{Method, SimOptions, Summary};
use geardyn_model::{presets, MeshModel};
use geardyn_scenario::ScenarioSpec;

/// The defaults with the escape test off: these tests are about the follow of the run's own
/// trajectory to the horizon, the rule where the escape test does not apply (tests/it/escape.rs
/// holds the test's own cases).
fn follow_only() -> SimOptions {
    SimOptions {
        escape: geardyn_analysis::escape::EscapeSettings {
            copies: 0,
            ..Default::default()
        },
        ..Default::default()
    }
}

fn c1(omega: f64) -> MeshModel {
    common::model(presets::classic(), &[("omega", omega)])
}

const RK4: Method = Method::Rk4 {
    steps_per_cycle: 512,
};

/// C1 at `omega` from rest, fixed-step RK4 512, decided with `opts` over the defaults. The
/// record reported is a full one, whatever the persistence blocks recorded on the way (their
/// records hold the stroboscopic points alone): forces, contact time and its rates.
fn decide_c1(omega: f64, opts: SimOptions) -> Summary {
    let opts = SimOptions {
        method: RK4,
        ..opts
    };
    let (res, s, _) = common::decided(&c1(omega), &opts);
    assert!(
        res.mesh().max_force > 0.0 && s.max_force > 0.0,
        "{}",
        s.label
    );
    assert!(res.mesh().durations.iter().sum::<f64>() > 0.0);
    assert!(s.p_id > 0.0 && s.p_id < 1.0, "{}", s.p_id);
    s
}

#[test]
fn a_chaotic_transient_of_thousands_of_revolutions_is_periodic() {
    // the broken pair at omega = 1.2, F = 0.065 (seed A's load sweep): transient chaos (exponent
    // positive over the first record) for ~5 300 revolutions from rest, then the 1-20-0 orbit;
    // the former rule called it chaotic
    let sc = ScenarioSpec::preset("breakage").unwrap().resolve().unwrap();
    let sc = sc.with_all(&[("omega", 1.2), ("F", 0.065)]).unwrap();
    let (res, s, _) = common::decided_from_rest(sc.model());
    // the escape test sees the copies leak to the orbit (lifetime ~4 700 revolutions)
    let lifetime = common::transient_lifetime(&s, 1, "1-20-0");
    assert!((1_000.0..30_000.0).contains(&lifetime), "{lifetime}");
    // (decided in a fraction of the single trajectory's lifetime: the copies leak 64 times as
    // fast)
    assert!(s.periods_integrated < 2_000, "{}", s.periods_integrated);
    // the same orbit when the transient is followed with DP5 itself (the follow, coarse RK4
    // with impacts and friction, is a faithful pseudo-orbit here)
    let exact = SimOptions {
        follow_steps: 0,
        ..follow_only()
    };
    let (res_dp5, s_dp5, _) = common::decided(sc.model(), &exact);
    assert_eq!(s_dp5.label, s.label);
    assert!(
        s_dp5.periods_integrated > 4_000,
        "{}",
        s_dp5.periods_integrated
    );
    // (the work differs in kind: 64 copies in lanes against one trajectory; measured 230 M
    // evaluations for the escape test's decision against 87 M for DP5's follow, 2026-11-29)
    assert!(res.rhs_evals > 0 && res_dp5.rhs_evals > 0);
}

#[test]
fn a_transient_of_eight_thousand_periods_is_periodic() {
    // C1 at omega = 1.19346733668 (a value of W1), fixed-step RK4 512 from rest, decided as
    // `geardyn simulate --integrator rk4` decides it: chaotic (positive exponent after the first
    // record) for about 8 300 periods, then a period-16 orbit (followed with RK4 512 itself; the
    // decision's coarser follow leaves the chaos after ~4 400 periods)
    let exact = SimOptions {
        follow_steps: 0,
        ..follow_only()
    };
    let s = decide_c1(1.19346733668, exact);
    assert_eq!(s.motion, Motion::Periodic { period: 16 }, "{}", s.label);
    assert!(s.periods_integrated > 8_000, "{}", s.periods_integrated);
    let s = decide_c1(1.19346733668, follow_only());
    assert_eq!(s.motion, Motion::Periodic { period: 16 }, "{}", s.label);
    assert!(s.periods_integrated > 1_000, "{}", s.periods_integrated);
    // the escape test: transient chaos, then the same period-16 orbit, at a lifetime of the
    // order of the single trajectory's 8 000 periods
    let s = decide_c1(1.19346733668, SimOptions::default());
    let lifetime = common::transient_lifetime(&s, 16, &s.label);
    assert!((1_000.0..50_000.0).contains(&lifetime), "{lifetime}");
    // a horizon below the transient reports it chaotic: the verdict is about the time integrated
    let short = SimOptions {
        decision_periods: 3_000,
        ..follow_only()
    };
    let s = decide_c1(1.19346733668, short);
    assert!(s.motion.is_chaotic(), "{}", s.label);
    assert_eq!(s.decided_by, DecidedBy::PersistentChaos);
    assert!((3_000..3_200).contains(&s.periods_integrated));
}

#[test]
fn persistent_chaos_is_chaotic_at_the_horizon() {
    let s = decide_c1(1.3, follow_only());
    match s.motion {
        Motion::Chaotic { tle, stderr } => assert!(tle > 0.02 && tle > 3.0 * stderr),
        other => panic!("{other:?}"),
    }
    assert_eq!(s.decided_by, DecidedBy::PersistentChaos);
    assert!(s.periods_integrated >= DECISION_PERIODS);
    assert!(s.periods_integrated < DECISION_PERIODS + 200);
}

#[test]
fn a_horizon_within_the_first_record_is_no_persistence_check() {
    // nothing is followed beyond the first record: the evidence is the first exponents
    let s = decide_c1(
        1.3,
        SimOptions {
            decision_periods: 0,
            ..follow_only()
        },
    );
    assert!(s.motion.is_chaotic(), "{}", s.label);
    assert_eq!(s.decided_by, DecidedBy::FirstExponent);
    assert_eq!(s.periods_integrated, 400);
}

#[test]
fn a_budget_short_of_the_horizon_leaves_chaos_unsettled() {
    // RK4 at 512 steps per cycle, followed so too: 2 048 right-hand sides per period of C1 (and a
    // few for event location), so a budget of 4 096 000 ends the decision near 2 000 periods
    let s = decide_c1(
        1.3,
        SimOptions {
            decision_budget: 4_096_000,
            follow_steps: 0,
            ..follow_only()
        },
    );
    assert!(
        matches!(s.motion, Motion::Unsettled { tle: Some(t), .. } if t > 0.0),
        "{:?}",
        s.motion
    );
    assert_eq!(s.decided_by, DecidedBy::Budget);
    assert!(
        (1_500..=2_000).contains(&s.periods_integrated),
        "{}",
        s.periods_integrated
    );
    assert!(s.label.starts_with("unsettled"), "{}", s.label);
    assert!(s.describe().contains("work budget"), "{}", s.describe());
}

#[test]
fn horizon_verdicts_in_the_lanes_do_not_depend_on_the_thread_count() {
    // persistent chaos, a long transient, a periodic orbit and a weakly chaotic value, decided
    // together in the lanes on one and on two threads
    let models: Vec<MeshModel> = [1.3, 1.42713567839, 0.8, 1.40452261307, 1.19346733668]
        .iter()
        .map(|&w| c1(w))
        .collect();
    let runs: Vec<(&MeshModel, [f64; 2])> = models.iter().map(|m| (m, [0.0, 0.0])).collect();
    let opts = SimOptions {
        method: RK4,
        ..follow_only()
    };
    let on = |threads: usize| {
        common::decided_lanes_on(threads, &runs, &opts, |r, s, _| {
            (s.motion, s.decided_by, s.periods_integrated, r.final_state)
        })
    };
    let one = on(1);
    assert_eq!(one, on(2));
    assert!(one[0].0.is_chaotic());
    assert_eq!(one[2].1, DecidedBy::PeriodTest);
}

#[test]
fn the_attractor_region_holds_the_impacting_orbit_of_the_broken_pair() {
    use geardyn_analysis::bifurcation::{attractor_region, run_sweep, SweepMode, SweepOptions};
    use geardyn_analysis::simulate::simulate;
    use std::collections::HashMap;
    // omega = 1.2, F = 0.07: the healthy 1-20-0 orbit (from rest) coexists with an impacting
    // 1-40-40 orbit whose basin lies at x0 > 1.7, outside the former +-1.5 x +-1 box
    let sc = ScenarioSpec::preset("breakage").unwrap().resolve().unwrap();
    let sc = sc.with_all(&[("omega", 1.2), ("F", 0.07)]).unwrap();
    let m = sc.model();
    let (xr, vr) = attractor_region(m.backlash_levels().1);
    let opts = SimOptions {
        transient_periods: 20,
        record_periods: 5,
        trajectory: true,
        ..follow_only()
    };
    let res = simulate(m, [2.88, 0.14], &opts).unwrap();
    assert_eq!(
        res.mesh().impacts,
        200,
        "the impacting orbit: 40 impacts per revolution"
    );
    for p in &res.mesh().trajectory {
        assert!(xr.0 <= p.x && p.x <= xr.1, "x {} outside {xr:?}", p.x);
        assert!(vr.0 <= p.v && p.v <= vr.1, "v {} outside {vr:?}", p.v);
    }
    let x_max = res.mesh().trajectory.iter().fold(0.0f64, |a, p| a.max(p.x));
    assert!(x_max > 1.5, "beyond the former box: {x_max}");
    // a multi-initial sweep over the region finds both orbits; over the former box only one
    let labels = |x0_range, v0_range| {
        let o = SweepOptions {
            param: "F".into(),
            values: vec![0.07],
            mode: SweepMode::Multi {
                ics: 8,
                seed: 1,
                x0_range,
                v0_range,
            },
            sim: SimOptions {
                decision_periods: 1_000,
                ..follow_only()
            },
            y0: [0.0, 0.0],
            sections: vec![],
            lyapunov: false,
        };
        let base = sc.with("omega", 1.2).unwrap();
        let r = run_sweep(&base, &o, &HashMap::new(), |_| {}).unwrap();
        r[0].runs
            .iter()
            .map(|run| run.label.clone())
            .collect::<Vec<_>>()
    };
    let wide = labels(xr, vr);
    assert!(wide.iter().any(|l| l == "1-40-40"), "{wide:?}");
    assert!(wide.iter().any(|l| l == "1-20-0"), "{wide:?}");
    let old = labels((-1.5, 1.5), (-1.0, 1.0));
    assert!(!old.iter().any(|l| l == "1-40-40"), "{old:?}");
}

#[test]
fn the_follow_decides_chaos_in_a_fraction_of_the_work() {
    // C1 at omega = 1.3 (persistent chaos), RK4 512: followed by the default RK4 follow (64 steps
    // per mesh cycle here) and by RK4 512 itself, the same verdict at the same horizon; the follow
    // integrates the ~9 600 periods beyond the first record at an eighth of the steps
    let exact = decide_c1(
        1.3,
        SimOptions {
            follow_steps: 0,
            ..follow_only()
        },
    );
    let opts = SimOptions {
        method: RK4,
        ..follow_only()
    };
    let (res, s, _) = common::decided(&c1(1.3), &opts);
    assert!(s.motion.is_chaotic() && exact.motion.is_chaotic());
    assert_eq!(s.decided_by, DecidedBy::PersistentChaos);
    assert_eq!(s.periods_integrated, exact.periods_integrated);
    // (the exact run's work: 2 048 right-hand sides per period)
    let exact_work = 2048 * exact.periods_integrated;
    assert!(
        res.rhs_evals * 3 < exact_work,
        "follow {} against {exact_work}",
        res.rhs_evals
    );
    // the record the verdict reports is the requested integrator's: 100 periods of 512 steps
    assert_eq!(res.strobe.len(), 100);
    assert!(res.steps >= 100 * 512);
}

#[test]
fn an_adaptive_run_decides_alike_alone_and_in_a_sweep() {
    use geardyn_analysis::bifurcation::{run_sweep, SweepMode, SweepOptions};
    use std::collections::HashMap;
    // the default adaptive integrator, C1 at omega = 1.3 (chaotic) and 1.25: the follows of a
    // sweep run together in the lanes, those of a lone run on a one-lane engine with the same
    // phase tables, so the two decide alike to the bit
    let base = geardyn_scenario::ScenarioSpec::preset("classic")
        .unwrap()
        .resolve()
        .unwrap();
    let o = SweepOptions {
        param: "omega".into(),
        values: vec![1.25, 1.3],
        mode: SweepMode::Fixed,
        sim: SimOptions::default(),
        y0: [0.0, 0.0],
        sections: vec![],
        lyapunov: false,
    };
    let swept = run_sweep(&base, &o, &HashMap::new(), |_| {}).unwrap();
    for (r, &w) in swept.iter().zip(&o.values) {
        let sc = base.with("omega", w).unwrap();
        let (res, s, _) = common::decided(sc.model(), &o.sim);
        assert_eq!(r.runs[0].label, s.label, "omega {w}");
        assert_eq!(r.runs[0].final_state, res.final_state.1, "omega {w}");
    }
    assert!(
        swept[1].runs[0].label == "chaotic",
        "{}",
        swept[1].runs[0].label
    );
}

#[test]
fn the_follow_is_coarse_only_where_the_lanes_step_the_contact_law() {
    use geardyn_analysis::pair_engine::follow_method;
    // C1, and the broken pair (impacts with restitution, friction): the linear contact law
    let sc = ScenarioSpec::preset("breakage").unwrap().resolve().unwrap();
    let sc = sc.with_all(&[("omega", 1.18), ("F", 0.05)]).unwrap();
    assert!(sc.model().impact_law().is_some());
    assert!(follow_method(sc.model(), &SimOptions::default()).is_some());
    assert!(follow_method(&c1(1.3), &SimOptions::default()).is_some());
    // the internal pair with its nonlinear contact law: not checked, the requested integrator
    let mut p = presets::internal();
    p.omega = 1.8;
    let m = MeshModel::new(&p).unwrap();
    assert!(!geardyn_analysis::lanes::lanes_cover_contact(&m));
    assert_eq!(follow_method(&m, &SimOptions::default()), None);
    // with the linear law (the report's studies): friction and a time-varying backlash, followed
    p.contact = geardyn_model::contact_law::ContactLaw::Linear;
    let lin = MeshModel::new(&p).unwrap();
    assert!(follow_method(&lin, &SimOptions::default()).is_some());
    // nor a unilateral contact
    p.unilateral = true;
    let uni = MeshModel::new(&p).unwrap();
    assert_eq!(follow_method(&uni, &SimOptions::default()), None);
}

#[test]
fn a_follow_finer_than_the_run_keeps_the_budget() {
    // C1 with the adaptive integrator (~2 000 right-hand sides per period) and a follow of 200 000
    // RK4 steps per natural period (~800 000 per period): the follow would overrun the budget that
    // reckons blocks at the run's mean work, so the blocks run with the requested integrator
    let opts = SimOptions {
        follow_steps: 200_000,
        decision_budget: 50_000_000,
        ..follow_only()
    };
    let (res, s, _) = common::decided(&c1(1.38), &opts);
    assert!(
        res.rhs_evals <= opts.decision_budget + opts.decision_budget / 20,
        "{} evaluations for a budget of {}",
        res.rhs_evals,
        opts.decision_budget
    );
    assert!(s.periods_integrated > 1_000, "{}", s.periods_integrated);
}
