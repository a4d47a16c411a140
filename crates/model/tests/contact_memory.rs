//! The hysteresis damping of the dissipative contact laws belongs to one impact (issue 11), and the
//! model keeps its physical invariants (issue 13): see `geardyn_model::contact_law` and
//! `geardyn_model::mesh_model`.

use geardyn_model::contact_law::V_IN_FLOOR;
use geardyn_model::mesh_model::SURFACE_TOL;
use geardyn_model::{
    presets, ContactLaw, ContactState, EventKind, ImpactLaw, MeshMode, MeshModel, ModelError,
    ModelParams, StiffnessForm,
};
use geardyn_solvers::{HybridSystem, Integrator, Scheme, SolverError, Stop};

/// Unit constant stiffness, `D = 1`, no excitation: the free contact of one tooth pair.
fn free_contact(law: ContactLaw, load: f64, c: f64) -> ModelParams {
    let mut p = presets::classic();
    p.stiffness = StiffnessForm::Constant { k: 1.0 };
    p.xi = 0.0;
    p.load = load;
    p.c = c;
    p.contact = law;
    p
}

/// An event seen by a test: kind, time, state before the reset, mode after.
type Seen = (EventKind, f64, [f64; 2], MeshMode);

/// Integrates from `y0` (mode from the model) until `t_end` or `stop_at` events.
fn events(m: &MeshModel, y0: [f64; 2], t_end: f64, stop_at: usize) -> Vec<Seen> {
    let mut it = Integrator::new(m, Scheme::dopri_default(), 0.0, y0).unwrap();
    let mut out = Vec::new();
    while out.len() < stop_at {
        let before = *it.mode();
        match it.step(t_end).unwrap() {
            Stop::Tstop => break,
            Stop::Event { index } => {
                let kind = m.event_kind(&before, it.mode(), index);
                out.push((kind, it.t(), it.last_step().y1(), *it.mode()));
            }
            _ => {}
        }
    }
    out
}

/// Restitution of one free impact through the mesh model: approach at `v0` from inside the
/// backlash, exit speed over entry speed.
fn model_restitution(law: ContactLaw, v0: f64) -> f64 {
    let m = MeshModel::new(&free_contact(law, 0.0, 0.0)).unwrap();
    let ev = events(&m, [0.0, v0], 1e3, 2);
    assert_eq!(ev[0].0, EventKind::DriveEnter, "{ev:?}");
    assert!(ev[0].3.chi > 0.0);
    assert_eq!(ev[1].0, EventKind::DriveExit, "{ev:?}");
    -ev[1].2[1] / v0
}

#[test]
fn isolated_impact_restitution_matches_the_law_coefficient() {
    // the same first-order energy balance as the law's own unit test, now through the model
    // (entry at v0 >> v_q = V_IN_FLOOR with no load: the free-impact factor applies)
    for e in [0.95, 0.9, 0.8] {
        let q = (1.0 - e) * (1.0 - e);
        let ln = ContactLaw::LankaraniNikravesh {
            exponent: 1.5,
            restitution: e,
        };
        let hc = ContactLaw::HuntCrossley {
            exponent: 1.5,
            restitution: e,
        };
        for v0 in [0.05, 0.5, 2.0] {
            let got = model_restitution(ln, v0);
            assert!(got > e && got - e < 1.5 * q, "LN e={e} v0={v0}: {got}");
            let got = model_restitution(hc, v0);
            assert!(got > e && got - e < 1.0 * q, "HC e={e} v0={v0}: {got}");
        }
        // independent of the entry speed, as the law is built to be
        let (a, b) = (model_restitution(ln, 0.05), model_restitution(ln, 2.0));
        assert!((a - b).abs() < 1e-4, "{a} vs {b}");
    }
}

#[test]
fn grazing_entries_fade_to_the_viscous_law() {
    let ln = ContactLaw::LankaraniNikravesh {
        exponent: 1.2,
        restitution: 0.8,
    };
    let a = ln.hysteresis_coefficient();
    let vq = ln.quasi_static_speed(0.16);
    assert!(vq > 0.1 && vq < 0.25, "{vq}");
    // bounded, vanishing at rest, continuous, and the free-impact factor well above v_q
    let mut last = 0.0;
    for i in 0..=4000 {
        let v = i as f64 * 1e-3 * vq;
        let chi = ln.entry_hysteresis(v, vq);
        assert!(chi <= 0.571 * a / vq, "v = {v}: {chi}");
        assert!((chi - last).abs() < 0.01 * a / vq, "jump at {v}");
        last = chi;
    }
    assert_eq!(ln.entry_hysteresis(0.0, vq), 0.0);
    let free = ln.hysteresis(3.0 * vq);
    assert!((ln.entry_hysteresis(3.0 * vq, vq) - free).abs() < 0.013 * free);
    // unloaded: the fade sits at the old floor only
    assert_eq!(ln.quasi_static_speed(0.0), V_IN_FLOOR);
    // through the model: a slow entry under load gets (almost) no hysteresis
    let m = MeshModel::new(&free_contact(ln, 0.16, 0.14)).unwrap();
    assert_eq!(m.quasi_static_speed(), vq);
    let ev = events(&m, [0.9999, 0.001], 10.0, 1);
    assert_eq!(ev[0].0, EventKind::DriveEnter);
    let v_in = ev[0].2[1];
    assert!(v_in < 0.1 * vq);
    assert!(ev[0].3.chi < 1e-4 * ln.hysteresis(v_in), "{}", ev[0].3.chi);
}

#[test]
fn an_impact_that_does_not_separate_settles_without_memory() {
    // a loaded contact entered fast: compression, restitution, then the load turns the velocity
    // back into the contact before the teeth separate: the impact is over, chi = 0 from then on
    let ln = ContactLaw::LankaraniNikravesh {
        exponent: 1.5,
        restitution: 0.8,
    };
    let m = MeshModel::new(&free_contact(ln, 0.5, 0.05)).unwrap();
    let ev = events(&m, [0.5, 0.6], 200.0, 20);
    assert_eq!(ev[0].0, EventKind::DriveEnter, "{ev:?}");
    assert!(ev[0].3.chi > 0.0);
    let s = ev
        .iter()
        .position(|e| e.0 == EventKind::Settle)
        .unwrap_or_else(|| panic!("no settling: {ev:?}"));
    // the impact that settles: entered with hysteresis, no separation before the reversal
    assert_eq!(ev[s - 1].0, EventKind::DriveEnter, "{ev:?}");
    assert!(ev[s - 1].3.chi > 0.0);
    assert_eq!(ev[s].3.contact, ContactState::Drive);
    assert_eq!(ev[s].3.chi, 0.0);
    assert!(
        ev[s].2[1].abs() < 1e-9,
        "settles where x' = 0: {:?}",
        ev[s].2
    );
    // the mesh force does not jump there (the hysteresis term vanishes with x')
    let (t, y) = (ev[s].1, ev[s].2);
    let mut with = ev[s].3;
    with.chi = ev[s - 1].3.chi;
    let (f0, f1) = (m.mesh_force(t, &y, &with), m.mesh_force(t, &y, &ev[s].3));
    assert!((f0 - f1).abs() < 1e-9, "{f0} vs {f1}");
    // nothing else happens: it stays in contact (damped by c alone)
    assert_eq!(ev.len(), s + 1, "{ev:?}");
}

#[test]
fn initial_contact_and_backlash_jumps_carry_no_hysteresis() {
    let mut p = presets::internal();
    p.omega = 1.4;
    let m = MeshModel::new(&p).unwrap();
    for v in [0.0, 1e-4, 0.3, -0.3] {
        let mut y = [1.3, v];
        let mode = m.initial_mode(0.0, &mut y);
        assert_eq!(mode.contact, ContactState::Drive);
        assert_eq!(mode.chi, 0.0, "v = {v}");
    }
}

#[test]
fn impacts_never_pass_through_the_back_stop() {
    // issue 13: R = 1, no sticking, xi = 50 pumps the motion without bound; once the teeth cross
    // the backlash faster than the time resolution, the run must stop with an error instead of
    // continuing beyond the stop
    let mut p = presets::breakage();
    p.set("R", 1.0).unwrap();
    p.set("v_stick", 0.0).unwrap();
    p.set("xi", 50.0).unwrap();
    let m = MeshModel::new(&p).unwrap();
    let d = 1.0;
    let t_end = 6.0 * m.excitation_period();
    let mut it = Integrator::new(&m, Scheme::dopri_default(), 0.0, [0.0, 0.0]).unwrap();
    let err = loop {
        let before = *it.mode();
        match it.step(t_end) {
            Ok(Stop::Tstop) => panic!("the divergent run should have stopped"),
            Ok(stop) => {
                let y = *it.y();
                assert!(y[0] >= -d, "state beyond the stop: {y:?}");
                if let Stop::Event { index } = stop {
                    let x = it.last_step().y1()[0];
                    assert!(
                        (x.abs() - d).abs() <= SURFACE_TOL,
                        "event off its surface: {x}"
                    );
                    if m.event_kind(&before, it.mode(), index) == EventKind::Impact {
                        assert!(y[0] == -d && y[1] >= 0.0, "{y:?}");
                    }
                }
            }
            Err(e) => break e,
        }
    };
    assert!(matches!(err, SolverError::NonFinite { .. }), "{err}");

    // the preset itself runs fine and keeps every impact on the stop
    let m = MeshModel::new(&presets::breakage()).unwrap();
    let mut it = Integrator::new(&m, Scheme::dopri_default(), 0.0, [0.0, 0.0]).unwrap();
    let mut impacts = 0;
    loop {
        let before = *it.mode();
        match it.step(20.0 * m.excitation_period()).unwrap() {
            Stop::Tstop => break,
            Stop::Event { index } => {
                assert!(it.y()[0] >= -d);
                if m.event_kind(&before, it.mode(), index) == EventKind::Impact {
                    impacts += 1;
                    assert!((it.last_step().y1()[0] + d).abs() < 1e-9);
                }
            }
            _ => assert!(it.y()[0] >= -d),
        }
    }
    assert!(impacts > 0);
}

#[test]
fn back_stop_stiffness_is_validated_and_peak_forces_stay_finite() {
    let mut p = presets::breakage();
    p.set("k_c", 5e-324).unwrap();
    match MeshModel::new(&p).unwrap_err() {
        ModelError::Invalid {
            field,
            value,
            allowed,
        } => {
            assert_eq!(field, "back_side.k_c");
            assert_eq!(value, 5e-324);
            assert_eq!(allowed, "[1e-6, 1e6]");
        }
        e => panic!("{e}"),
    }
    for bad in [0.0, -1.0, 2e6, f64::INFINITY, f64::NAN] {
        p.set("k_c", bad).unwrap();
        assert!(MeshModel::new(&p).is_err(), "k_c = {bad}");
    }
    for k_c in [1e-6, 1.0, 1e6] {
        p.set("k_c", k_c).unwrap();
        let m = MeshModel::new(&p).unwrap();
        for v in [0.0, 1e-300, 1.0, 1e100, 1e300, f64::MAX] {
            let f = m.impact_peak_force(v);
            assert!(f.is_finite() && f >= 0.0, "k_c = {k_c}, v = {v}: {f}");
        }
        // the overflow-safe form is the Hertz closed form
        let law = ImpactLaw {
            restitution: 1.0,
            v_stick: 0.0,
            k_c,
        };
        let v = 0.7f64;
        let closed = k_c * (1.25 * v * v / k_c).powf(0.6);
        assert!((law.hertz_peak(v) - closed).abs() < 1e-12 * closed);
    }
}

#[test]
fn period_arithmetic_does_not_wrap_at_huge_times() {
    // 40 mesh cycles per excitation period: at tau = 1e20 the cycle count exceeds i64::MAX / 40
    let m = MeshModel::new(&presets::breakage()).unwrap();
    for t in [1e3, 1e12, 1e20] {
        let mut y = [0.0, 0.0];
        let mode = m.initial_mode(t, &mut y);
        let bp = m.next_breakpoint(t, &mode);
        assert!(bp.is_finite() && bp > 0.0, "t = {t}: {bp}");
        assert!(
            (bp - t).abs() <= 1e-9 * t + m.excitation_period(),
            "t = {t}: breakpoint {bp}"
        );
        let mut mode = mode;
        m.on_breakpoint(bp, &mut y, &mut mode);
    }
    // beyond 2^62 periods the mode cannot represent the time: an error state, not a wrap
    let mut y = [0.0, 0.0];
    m.initial_mode(1e25, &mut y);
    assert!(y[0].is_nan());
    assert!(matches!(
        Integrator::new(&m, Scheme::dopri_default(), 1e25, [0.0, 0.0]),
        Err(SolverError::NonFinite { .. })
    ));
    // the last period index saturates instead of wrapping
    let mut mode = MeshMode {
        period: i64::MAX,
        seg: m.segments().len() as u32 - 1,
        contact: ContactState::Separated,
        chi: 0.0,
    };
    let mut y = [0.0, 0.0];
    m.on_breakpoint(1e30, &mut y, &mut mode);
    assert_eq!(mode.period, i64::MAX);
    assert_eq!(mode.seg, 0);
}
