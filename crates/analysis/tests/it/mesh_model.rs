//! The gear mesh model against closed forms and limit cases (docs/model.md §2–4).

use crate::common;
use geardyn_analysis::simulate::{simulate, summarize, Method, SimOptions};
use geardyn_model::{
    presets, BackSide, ContactLaw, ContactState, ImpactLaw, MeshModel, ModelError, ModelParams,
    StiffnessForm,
};
use geardyn_solvers::{HybridSystem, Integrator, Scheme, Stop};

fn base() -> ModelParams {
    let mut p = presets::classic();
    p.stiffness = StiffnessForm::Constant { k: 1.0 };
    p.xi = 0.0;
    p
}

fn schemes(m: &MeshModel) -> [Scheme; 2] {
    [
        Scheme::dopri_default(),
        Scheme::Rk4 {
            h: m.mesh_cycle_time() / 2048.0,
        },
    ]
}

/// An event as seen by a test: time, contact state after it, state before any reset.
type EventSeen = (f64, ContactState, [f64; 2]);

/// Runs to `t_end`, returning the state and the list of (time, mode-after) of events.
fn run(m: &MeshModel, scheme: Scheme, y0: [f64; 2], t_end: f64) -> ([f64; 2], Vec<EventSeen>) {
    let mut it = Integrator::new(m.clone(), scheme, 0.0, y0).unwrap();
    let mut ev = Vec::new();
    loop {
        match it.step(t_end).unwrap() {
            Stop::Tstop => return (*it.y(), ev),
            Stop::Event { .. } => ev.push((it.t(), it.mode().contact, it.last_step().y1())),
            _ => {}
        }
    }
}

#[test]
fn free_vibration_in_permanent_contact_matches_closed_form() {
    // delta = x - D obeys delta'' + c delta' + k delta = F: underdamped step response about F/k
    let mut p = base();
    p.load = 1.0;
    p.c = 0.1;
    let m = MeshModel::new(&p).unwrap();
    let (k, c, f, d0) = (1.0f64, 0.1f64, 1.0f64, 0.5f64); // starts at delta = 0.5, at rest
    let z = c / (2.0 * k.sqrt());
    let wd = k.sqrt() * (1.0 - z * z).sqrt();
    let exact = |t: f64| {
        let a = d0 - f / k;
        let e = (-z * k.sqrt() * t).exp();
        let delta = f / k + a * e * ((wd * t).cos() + z * k.sqrt() / wd * (wd * t).sin());
        let v = -a * e * (k / wd) * (wd * t).sin();
        (delta, v)
    };
    for s in schemes(&m) {
        let (y, ev) = run(&m, s, [1.0 + d0, 0.0], 30.0);
        assert!(ev.is_empty(), "contact never lost");
        let (d, v) = exact(30.0);
        assert!(
            (y[0] - 1.0 - d).abs() < 1e-8 && (y[1] - v).abs() < 1e-8,
            "{s:?}: {y:?} vs {d} {v}"
        );
    }
}

#[test]
fn separation_is_an_exact_parabola() {
    // separated: x'' = F, from x = 0, v = 0.3; drive contact begins at the root of
    // F t^2/2 + 0.3 t = D
    let mut p = base();
    p.load = 0.1;
    let m = MeshModel::new(&p).unwrap();
    let t_hit = (-0.3 + (0.09f64 + 2.0 * 0.1 * 1.0).sqrt()) / 0.1;
    for s in schemes(&m) {
        let (_, ev) = run(&m, s, [0.0, 0.3], t_hit + 0.01);
        assert_eq!(ev.len(), 1);
        let (t, state, y) = ev[0];
        assert_eq!(state, ContactState::Drive);
        assert!(
            (t - t_hit).abs() < 1e-12,
            "{s:?}: event at {t}, exact {t_hit}"
        );
        assert!(
            (y[0] - 1.0).abs() < 1e-12 && y[0] >= 1.0,
            "state on the new side: {}",
            y[0]
        );
        assert!((y[1] - (0.3 + 0.1 * t_hit)).abs() < 1e-12);
    }
}

#[test]
fn impact_reverses_velocity_by_restitution() {
    let mut p = base();
    p.load = 0.0;
    p.back_side = BackSide::Impact(ImpactLaw {
        restitution: 0.85,
        v_stick: 1e-6,
        k_c: 1.0,
    });
    let m = MeshModel::new(&p).unwrap();
    for s in schemes(&m) {
        // free flight at -0.5 from x = 0: hits x = -1 at t = 2, leaves at 0.425
        let mut it = Integrator::new(m.clone(), s, 0.0, [0.0, -0.5]).unwrap();
        let stop = loop {
            let st = it.step(3.0).unwrap();
            if st != Stop::Step {
                break st;
            }
        };
        assert!(matches!(stop, Stop::Event { .. }));
        assert!((it.t() - 2.0).abs() < 1e-12);
        assert_eq!(it.y()[0], -1.0);
        assert!((it.y()[1] - 0.425).abs() < 1e-13);
        // kinetic energy ratio R^2 (the only loss); position exactly on the stop
        let ke_ratio = it.y()[1].powi(2) / 0.25;
        assert!((ke_ratio - 0.85f64.powi(2)).abs() < 1e-12);
    }
    // R = 1 conserves energy over many bounces between the two flanks (c = 0, F = 0)
    let mut p2 = p.clone();
    p2.c = 0.0;
    if let BackSide::Impact(l) = &mut p2.back_side {
        l.restitution = 1.0;
    }
    let m = MeshModel::new(&p2).unwrap();
    let (y, ev) = run(&m, Scheme::dopri_default(), [0.0, -0.5], 200.0);
    assert!(ev.len() > 40);
    // energy in drive contact: v^2/2 + k (x-D)^2/2; separated: v^2/2
    let e = 0.5 * y[1] * y[1]
        + if y[0] > 1.0 {
            0.5 * (y[0] - 1.0).powi(2)
        } else {
            0.0
        };
    assert!((e - 0.125).abs() < 1e-8, "energy {e}");
}

#[test]
fn chattering_ends_in_sticking_and_release_follows_the_excitation() {
    // F = 0, xi > 0: the free acceleration xi w^2 cos(w tau) pushes into the back stop for half a
    // cycle; a bouncing tooth must come to rest (finite number of impacts) and leave exactly when
    // the acceleration turns positive (cos crosses 0 upward: w tau = 3 pi/2 mod 2 pi).
    let mut p = base();
    p.load = 0.0;
    p.xi = 0.05;
    p.omega = 0.5;
    p.back_side = BackSide::Impact(ImpactLaw {
        restitution: 0.5,
        v_stick: 1e-5,
        k_c: 1.0,
    });
    let m = MeshModel::new(&p).unwrap();
    let w = 0.5;
    // start at the stop, falling slowly, at w tau = pi/2 (acceleration turning negative)
    let t0 = std::f64::consts::FRAC_PI_2 / w;
    let mut it = Integrator::new(m.clone(), Scheme::dopri_default(), t0, [-0.999, -0.01]).unwrap();
    let mut stuck_at = None;
    let mut released_at = None;
    let mut impacts = 0;
    for _ in 0..100_000 {
        let before = it.mode().contact;
        let st = it.step(t0 + 4.0 * std::f64::consts::PI / w).unwrap();
        if let Stop::Event { .. } = st {
            match (before, it.mode().contact) {
                (ContactState::Separated, ContactState::Stuck) => stuck_at = Some(it.t()),
                (ContactState::Stuck, ContactState::Separated) => {
                    released_at = Some(it.t());
                    break;
                }
                (ContactState::Separated, ContactState::Separated) => impacts += 1,
                _ => {}
            }
        }
    }
    assert!(impacts > 3 && impacts < 200, "{impacts} impacts");
    let ts = stuck_at.expect("never stuck");
    let tr = released_at.expect("never released");
    assert!(ts < tr);
    let expect = 1.5 * std::f64::consts::PI / w;
    assert!(
        (tr - expect).abs() < 1e-9,
        "release at {tr}, expected {expect}"
    );
}

#[test]
fn grazing_contact_is_detected_and_tangency_does_not_hang() {
    // separated flight x = x0 + v0 t + F t^2/2 with its lowest point at -D - depth; the start
    // position moves the apex across the integrator's steps (fixed RK4 grid and adaptive steps)
    let mut p = base();
    p.load = 0.1;
    p.c = 0.0;
    let m = MeshModel::new(&p).unwrap();
    for scheme in [Scheme::dopri_default(), Scheme::Rk4 { h: 0.05 }] {
        for k in 0..9 {
            let x0 = 0.0123 * k as f64;
            let flight = |depth: f64| {
                let v0 = -(2.0 * 0.1 * (1.0 + depth + x0)).sqrt();
                run(&m, scheme, [x0, v0], 2.0 * v0.abs() / 0.1 + 1.0).1
            };
            let deep = flight(1e-9);
            assert_eq!(
                deep.len(),
                2,
                "{scheme:?} x0={x0}: a 1e-9 graze must enter and exit: {deep:?}"
            );
            assert_eq!(deep[0].1, ContactState::Back);
            assert_eq!(deep[1].1, ContactState::Separated);
            // time in contact: 2 sqrt(2 depth / F) (the stiffness acts for a negligible time)
            let dt = deep[1].0 - deep[0].0;
            assert!(
                (dt - 2.0 * (2.0 * 1e-9 / 0.1f64).sqrt()).abs() < 2e-6,
                "{dt}"
            );
            assert!(flight(-1e-7).is_empty(), "a miss is not a contact");
            assert!(flight(0.0).len() <= 2, "tangency");
        }
    }
}

#[test]
fn backlash_jump_at_a_zone_border_starts_a_separation() {
    // D_d = 0.9 < D_s = 1.1; in drive contact at x = 1.0 near the end of the double zone, the
    // jump to D_s at the border must switch to separation at once (no crossing of x = D happens).
    let mut p = base();
    p.d_double = 0.9;
    p.d_single = 1.1;
    p.eps = 1.5;
    p.load = 0.0;
    p.c = 0.0;
    p.omega = 2.0 * std::f64::consts::PI; // mesh cycle = 1 time unit; border at tau = 0.5
    let m = MeshModel::new(&p).unwrap();
    let mut it = Integrator::new(m, Scheme::dopri_default(), 0.49, [1.0, 0.0]).unwrap();
    assert_eq!(it.mode().contact, ContactState::Drive);
    let st = loop {
        let st = it.step(0.6).unwrap();
        if st != Stop::Step {
            break st;
        }
    };
    assert_eq!(st, Stop::Breakpoint);
    assert!((it.t() - 0.5).abs() < 1e-13);
    assert_eq!(it.mode().contact, ContactState::Separated);
    // x obeyed x'' = -(x - 0.9) for 0.01: closed form
    let x = 0.9 + 0.1 * (0.01f64).cos();
    assert!((it.y()[0] - x).abs() < 1e-11);
}

#[test]
fn frictionless_limit_and_bad_inputs() {
    let mut p = presets::breakage();
    p.friction.mu = 0.0;
    let m = MeshModel::new(&p).unwrap();
    assert!(m
        .segments()
        .iter()
        .all(|s| s.h_drive == 1.0 && s.h_back == 1.0));

    let field = |p: &ModelParams| match MeshModel::new(p).unwrap_err() {
        ModelError::Invalid { field, .. } | ModelError::Inconsistent { field, .. } => field,
        e => panic!("{e}"),
    };
    let mut q = presets::classic();
    q.d_double = -1.0;
    assert_eq!(field(&q), "D_d");
    let mut q = presets::classic();
    q.omega = f64::NAN;
    assert_eq!(field(&q), "omega");
    let mut q = presets::internal();
    q.d_single = 0.5;
    assert_eq!(field(&q), "D_s");
    let mut q = presets::breakage();
    q.friction.mu = 20.0; // h = 1 - mu*arm < 0 somewhere
    assert!(field(&q).starts_with("friction"));
    let mut q = presets::classic();
    q.contact = ContactLaw::Power { exponent: 0.2 };
    assert_eq!(field(&q), "contact.exponent");
    let mut q = presets::breakage();
    q.breakage.as_mut().unwrap().eps_b = 1.9;
    assert_eq!(field(&q), "breakage.eps_b");
    assert!(presets::classic().set("nonsense", 1.0).is_err());
}

#[test]
fn c1_integrators_agree_and_periods_are_detected() {
    let mut p = presets::classic();
    let strobe = |p: &ModelParams, method: Method| {
        let m = MeshModel::new(p).unwrap();
        let opts = SimOptions {
            method,
            transient_periods: 300,
            record_periods: 32,
            ..Default::default()
        };
        let r = simulate(&m, [0.0, 0.0], &opts).unwrap();
        (summarize(&m, &r, &opts), r.strobe)
    };
    let (s_dp, a) = strobe(&p, Method::default());
    let (s_rk, b) = strobe(
        &p,
        Method::Rk4 {
            steps_per_cycle: 512,
        },
    );
    for (u, w) in a.iter().zip(&b) {
        assert!(
            (u[1] - w[1]).abs() < 1e-7 && (u[2] - w[2]).abs() < 1e-7,
            "{u:?} vs {w:?}"
        );
    }
    assert_eq!(s_dp.period, 1);
    assert_eq!(s_rk.period, 1);
    assert!(s_dp.label.starts_with("1-"));
    p.omega = 0.95;
    let (s, _) = strobe(&p, Method::default());
    assert_eq!(s.period, 2, "{}", s.label);
    p.omega = 1.3;
    let (s, _) = strobe(&p, Method::default());
    assert_eq!(s.period, 0, "chaos at 1.3: {}", s.label);
    assert!(!s.healthy);
}

#[test]
fn broken_model_is_zp_cycles_periodic_with_zone_ii() {
    let m = MeshModel::new(&presets::breakage()).unwrap();
    assert_eq!(m.cycles_per_period(), 40);
    let segs = m.segments();
    assert_eq!(segs.first().unwrap().start, 0.0);
    assert_eq!(segs.last().unwrap().end, 40.0);
    let zone2: Vec<_> = segs
        .iter()
        .filter(|s| s.zone == geardyn_model::Zone::SingleII)
        .collect();
    assert_eq!(zone2.len(), 1);
    // zone II starts where the chipped tooth leaves mesh (eps_b - 1); it carries the single-pair
    // stiffness, below the double-pair value the healthy cycles have at the same phase
    assert!((zone2[0].start - 0.45).abs() < 1e-12);
    assert!(m.stiffness_at(0.5) < m.stiffness_at(1.5));
    assert_eq!(m.stiffness_at(0.5), m.stiffness_at(0.9));
    // excitation period = 40 mesh cycles; a strobe every 40 cycles
    assert!((m.excitation_period() - 40.0 * m.mesh_cycle_time()).abs() < 1e-12);
    // the next breakpoint from inside zone II is its end
    let mut y = [1.2, 0.0];
    let t = 0.5 * m.mesh_cycle_time();
    let mode = m.initial_mode(t, &mut y);
    assert!((m.next_breakpoint(t, &mode) - zone2[0].end * m.mesh_cycle_time()).abs() < 1e-12);
}

#[test]
fn forced_linear_response_amplitudes_match_closed_form() {
    // permanent contact (large F): delta'' + c delta' + k delta = F + xi w^2 cos(w tau), steady
    // state delta = F/k + A cos(w tau - phase), A = xi w^2 / sqrt((k - w^2)^2 + (c w)^2)
    let mut p = base();
    p.load = 2.0;
    p.xi = 0.2;
    p.c = 0.1;
    p.omega = 0.5;
    let m = MeshModel::new(&p).unwrap();
    let (k, c, w, xi) = (1.0f64, 0.1f64, 0.5f64, 0.2f64);
    let a = xi * w * w / ((k - w * w).powi(2) + (c * w).powi(2)).sqrt();
    for method in [
        Method::default(),
        Method::Rk4 {
            steps_per_cycle: 256,
        },
    ] {
        let opts = SimOptions {
            method,
            transient_periods: 150,
            record_periods: 20,
            ..Default::default()
        };
        let r = simulate(&m, [3.0, 0.0], &opts).unwrap();
        let amp = r.amplitudes();
        assert!((amp.mean_x - 3.0).abs() < 1e-7, "{amp:?}");
        assert!((amp.rms_x - a / 2f64.sqrt()).abs() < 1e-7, "{amp:?} vs {a}");
        assert!((amp.p2p_x - 2.0 * a).abs() < 1e-6);
        let af = a * (k * k + (c * w).powi(2)).sqrt();
        assert!((amp.mean_force - 2.0).abs() < 1e-7);
        assert!(
            (amp.rms_force - af / 2f64.sqrt()).abs() < 1e-7,
            "{amp:?} vs {af}"
        );
        let s = summarize(&m, &r, &opts);
        assert_eq!((s.period, s.p_id), (1, 0.0));
    }
}

#[test]
fn unilateral_option_forbids_tensile_mesh_force() {
    // drive-side contact only (large static load), damping c = 0.4: leaving the contact with
    // x' < 0 makes k(x - D) + c x' negative just before x = D unless the force is unilateral
    let mut p = presets::classic();
    p.load = 0.3;
    p.xi = 0.5;
    p.c = 0.4;
    p.omega = 0.9;
    let opts = common::periods(200, 20);
    let m = MeshModel::new(&p).unwrap();
    let bilateral = summarize(&m, &simulate(&m, [1.3, 0.0], &opts).unwrap(), &opts);
    p.unilateral = true;
    let m = MeshModel::new(&p).unwrap();
    let r = simulate(&m, [1.3, 0.0], &opts).unwrap();
    let unilateral = summarize(&m, &r, &opts);
    assert!(
        bilateral.min_force < -1e-3,
        "setup must produce a tensile force: {}",
        bilateral.min_force
    );
    assert!(unilateral.min_force >= 0.0, "{}", unilateral.min_force);
    assert_eq!(r.mesh().impacts, 0);
}

#[test]
fn trajectory_window_keeps_the_last_periods_on_the_same_uniform_grid() {
    let m = MeshModel::new(&presets::classic()).unwrap();
    let full = SimOptions {
        transient_periods: 50,
        record_periods: 10,
        trajectory: true,
        ..Default::default()
    };
    let last = SimOptions {
        trajectory_periods: 3,
        ..full
    };
    let (a, b) = (
        simulate(&m, [0.0, 0.0], &full).unwrap(),
        simulate(&m, [0.0, 0.0], &last).unwrap(),
    );
    // everything but the trajectory is identical
    assert_eq!(a.strobe, b.strobe);
    assert_eq!(a.mesh().max_force, b.mesh().max_force);
    let t_from = a.strobe[6][0];
    let tail: Vec<_> = a
        .mesh()
        .trajectory
        .iter()
        .filter(|p| p.tau >= t_from - 1e-9)
        .collect();
    assert!(
        !b.mesh().trajectory.is_empty()
            && b.mesh().trajectory.iter().all(|p| p.tau >= t_from - 1e-9)
    );
    // same samples (times on the same uniform grid, up to round-off of its origin)
    assert!(
        (tail.len() as i64 - b.mesh().trajectory.len() as i64).abs() <= 2,
        "{} vs {}",
        tail.len(),
        b.mesh().trajectory.len()
    );
}

/// A kept trajectory resolves the natural oscillation at low meshing frequency: C1 (k = 1 +- 0.2,
/// natural period 2 pi / sqrt(1.2) = 5.74) at omega = 0.1 spans eleven natural periods per mesh
/// cycle, so 24 samples per cycle (2.2 per natural period) would draw a star of chords; the
/// sampler takes at least 32 per natural period there, and exactly `samples_per_cycle` per mesh
/// cycle where that is finer (omega = 1 with 128 per cycle).
#[test]
fn trajectory_sampling_follows_the_natural_period_at_low_frequency() {
    let m = MeshModel::new(&presets::classic()).unwrap();
    assert!(
        (m.peak_stiffness() - 1.2).abs() < 1e-9,
        "{}",
        m.peak_stiffness()
    );
    let spacing = |omega: f64, samples_per_cycle: u32| {
        let mut p = presets::classic();
        p.omega = omega;
        let m = MeshModel::new(&p).unwrap();
        let r = simulate(
            &m,
            [0.0, 0.0],
            &SimOptions {
                transient_periods: 2,
                record_periods: 1,
                trajectory: true,
                samples_per_cycle,
                ..Default::default()
            },
        )
        .unwrap();
        // the widest gap (events only add points between uniform samples)
        let mut gaps: Vec<f64> = r
            .mesh()
            .trajectory
            .windows(2)
            .map(|w| w[1].tau - w[0].tau)
            .collect();
        gaps.sort_by(f64::total_cmp);
        (gaps[gaps.len() - 1], m.mesh_cycle_time())
    };
    let natural = 2.0 * std::f64::consts::PI / 1.2f64.sqrt();
    let (gap, _) = spacing(0.1, 24);
    assert!(
        gap <= natural / 32.0 * (1.0 + 1e-9),
        "{gap} vs {}",
        natural / 32.0
    );
    let (gap, cycle) = spacing(1.0, 128);
    assert!(
        (gap - cycle / 128.0).abs() < 1e-9 * cycle,
        "{gap} vs {}",
        cycle / 128.0
    );
}

/// Fixed-step RK4 on the broken pair (friction mu = 0.15) over one revolution of an impacting
/// motion (omega 1.18, F 0.05: 45 contact events and 12 impacts), against Dormand–Prince at rtol
/// 1e-13 (a second method). With the pitch point a time breakpoint RK4 at 256 steps per mesh
/// cycle errs by ~1e-6; with the friction jump sampled across a table interval it erred by
/// 1.3e-3 (first order: the step that straddles the jump).
#[test]
fn rk4_converges_on_the_broken_pair_with_friction() {
    let sc = geardyn_scenario::ScenarioSpec::preset("breakage")
        .unwrap()
        .resolve()
        .unwrap()
        .with_all(&[("omega", 1.18), ("F", 0.05)])
        .unwrap();
    let run = |method| {
        let o = SimOptions {
            method,
            transient_periods: 0,
            record_periods: 1,
            tau0: 2151618.2363772267,
            ..Default::default()
        };
        let r = simulate(sc.model(), [1.0551878960979093, -0.38787661149898606], &o).unwrap();
        (r.final_state.1, r.mesh().impacts)
    };
    let (exact, impacts) = run(Method::Dopri {
        rtol: 1e-13,
        atol: 1e-15,
    });
    assert_eq!(impacts, 12);
    for n in [128, 256] {
        let (y, i) = run(Method::Rk4 { steps_per_cycle: n });
        assert_eq!(i, impacts);
        let err = (y[0] - exact[0]).abs().max((y[1] - exact[1]).abs());
        assert!(err < 2e-5, "RK4 {n} steps per cycle: error {err:e}");
    }
}
