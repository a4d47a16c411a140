//! Periodic orbits by shooting (`geardyn_analysis::orbits`): the monodromy matrix against closed
//! forms and a finite-difference Jacobian of the same map, and the bifurcations of a branch
//! against the linear response and the brute-force diagram of case C1.

use crate::common;
use geardyn_analysis::orbit_branches::{
    continue_orbits, Bifurcation, BifurcationKind, Continuation, ContinuationOptions,
};
use geardyn_analysis::orbits::{eigenvalues, find_orbit, stroboscopic_map, OrbitOptions};
use geardyn_analysis::simulate::simulate;
use geardyn_model::{presets, MeshModel, ModelParams};
use geardyn_scenario::Scenario;
use std::f64::consts::PI;

/// The bifurcations of `kind` of a continuation, in order.
fn of_kind(c: &Continuation, kind: BifurcationKind) -> Vec<&Bifurcation> {
    c.bifurcations.iter().filter(|b| b.kind == kind).collect()
}

/// The state of `m` after 300 periods from rest (near its attractor).
fn settled(m: &MeshModel) -> [f64; 2] {
    let opts = common::periods(300, 1);
    simulate(m, [0.0, 0.0], &opts).unwrap().final_state.1
}

/// C1 with constant stiffness (kappa = 0) and load `f`.
fn linear(omega: f64, f: f64) -> ModelParams {
    common::set(
        presets::classic(),
        &[("kappa", 0.0), ("F", f), ("omega", omega)],
    )
}

/// Steady state of `x'' + c x' + (x - D) = F + xi w^2 cos(w t)` at `t = 0` (permanent drive
/// contact): `D + F + Re[xi w^2 / (1 - w^2 + i c w)]` and its derivative.
fn linear_response(p: &ModelParams) -> [f64; 2] {
    let (w, c, xi, d, f) = (p.omega, p.c, p.xi, 1.0, p.load);
    let (re, im) = (1.0 - w * w, c * w);
    let den = re * re + im * im;
    let a = xi * w * w;
    // a / (re + i im) = a (re - i im) / den
    let (zr, zi) = (a * re / den, -a * im / den);
    // x = D + F + Re[z e^{i w t}], x' = Re[i w z e^{i w t}] at t = 0
    [d + f + zr, -w * zi]
}

#[test]
fn multipliers_of_a_linear_orbit_in_permanent_contact_have_modulus_exp_minus_c_pi_over_omega() {
    for omega in [0.6, 0.8, 1.3] {
        let p = linear(omega, 1.0);
        let m = MeshModel::new(&p).unwrap();
        let exact = linear_response(&p);
        let o = find_orbit(
            &m,
            [exact[0] + 0.05, exact[1] - 0.02],
            &OrbitOptions::default(),
        )
        .unwrap();
        assert!(o.events.is_empty(), "permanent contact: {:?}", o.events);
        assert!((o.y[0] - exact[0]).abs() < 1e-8 && (o.y[1] - exact[1]).abs() < 1e-8);
        let want = (-p.c * PI / omega).exp();
        for mu in o.multipliers {
            assert!(
                (mu.abs() - want).abs() < 1e-8,
                "{omega}: {} vs {want}",
                mu.abs()
            );
        }
        // the pair's argument: the damped natural frequency times the period
        let wd = (1.0 - 0.25 * p.c * p.c).sqrt();
        let arg = o.multipliers[0].im.atan2(o.multipliers[0].re).abs();
        let t = 2.0 * PI / omega;
        let want_arg = (wd * t).rem_euclid(2.0 * PI);
        let want_arg = want_arg.min(2.0 * PI - want_arg);
        assert!(
            (arg - want_arg).abs() < 1e-7,
            "{omega}: {arg} vs {want_arg}"
        );
        assert!(o.stable);
    }
}

#[test]
fn the_monodromy_matrix_equals_a_finite_difference_jacobian_of_the_map() {
    // C1 at omega = 0.8: a period-1 orbit with contact loss and re-entry (saltation at both)
    let m = common::model(presets::classic(), &[("omega", 0.8)]);
    let o = find_orbit(&m, settled(&m), &OrbitOptions::default()).unwrap();
    assert!(o.events.len() >= 2, "{:?}", o.events);
    let opts = OrbitOptions::default();
    let (_, jac) = stroboscopic_map(&m, o.y, &opts).unwrap();
    let h = 1e-6;
    for k in 0..2 {
        let mut a = o.y;
        let mut b = o.y;
        a[k] += h;
        b[k] -= h;
        let (fa, _) = stroboscopic_map(&m, a, &opts).unwrap();
        let (fb, _) = stroboscopic_map(&m, b, &opts).unwrap();
        for i in 0..2 {
            let fd = (fa[i] - fb[i]) / (2.0 * h);
            assert!(
                (fd - jac[i][k]).abs() < 1e-5 * (1.0 + fd.abs()),
                "d{i}/d{k}: variational {} vs differences {fd}",
                jac[i][k]
            );
        }
    }
    // and the multipliers from the same matrix
    let mu = eigenvalues(&jac);
    assert_eq!(mu, o.multipliers);
}

#[test]
fn a_branch_finds_the_grazing_of_the_linear_orbit_where_its_amplitude_equals_the_load() {
    // permanent contact while the response amplitude A(omega) stays below the load F: the orbit
    // grazes x = D where A = F (then it separates once per period)
    let f = 0.3;
    let amp = |w: f64| {
        let p = linear(w, f);
        p.xi * w * w / ((1.0 - w * w).powi(2) + (p.c * w).powi(2)).sqrt()
    };
    let (mut a, mut b) = (0.6, 0.8);
    for _ in 0..100 {
        let m = 0.5 * (a + b);
        if amp(m) < f {
            a = m;
        } else {
            b = m;
        }
    }
    let w_graze = 0.5 * (a + b);
    let sc = Scenario::dimensionless(linear(0.6, f)).unwrap();
    let y0 = linear_response(&linear(0.6, f));
    let opts = ContinuationOptions {
        param: "omega".into(),
        start: 0.6,
        stop: 0.8,
        ..Default::default()
    };
    let c = continue_orbits(&sc, y0, &opts, &|_| {}).unwrap();
    let g = of_kind(&c, BifurcationKind::Grazing);
    assert_eq!(g.len(), 1, "{:?}", c.bifurcations);
    assert!(
        (g[0].param - w_graze).abs() < 1e-6,
        "{} vs {w_graze}",
        g[0].param
    );
    // along the branch: contact only before it, a separation per period after it
    let k = c
        .points
        .iter()
        .position(|p| !p.orbit.events.is_empty())
        .unwrap();
    assert!(c.points[..k].iter().all(|p| p.param < w_graze));
    assert!(c.points[k..].iter().all(|p| p.orbit.events.len() == 2));
    // past the grazing the separations soften the pair: the branch turns back (a fold) just
    // above the grazing frequency, towards lower frequencies (the bent resonance of a pair with
    // backlash)
    let folds: Vec<f64> = c
        .bifurcations
        .iter()
        .filter(|b| b.kind == BifurcationKind::Fold)
        .map(|b| b.param)
        .collect();
    assert_eq!(folds.len(), 1, "{folds:?}");
    assert!(folds[0] > w_graze && folds[0] < 0.8, "{folds:?}");
    // refined to the turning point: a multiplier is +1 there (the smooth fold's test, which the
    // refinement does not use: it bisects on the tangent)
    let fold = c
        .bifurcations
        .iter()
        .find(|b| b.kind == BifurcationKind::Fold)
        .unwrap();
    let near_one = fold
        .orbit
        .multipliers
        .iter()
        .map(|m| (m.re - 1.0).hypot(m.im))
        .fold(f64::INFINITY, f64::min);
    assert!(near_one < 1e-3, "{:?}", fold.orbit.multipliers);
    // the last step is clipped to end at the end of the range
    let last = c.points.last().unwrap().param;
    assert!((last - 0.6).abs() <= 2e-4, "{last}");
    assert!(c.ends[0].contains("left [0.6, 0.8]"), "{:?}", c.ends);
}

#[test]
fn the_period_one_branch_of_c1_doubles_where_the_diagram_does_and_goes_on_unstable() {
    // the brute-force diagram (W1: 200 values of omega, RK4) shows period 1 up to 0.8769 and
    // period 2 from 0.8844
    let sc = Scenario::dimensionless(presets::classic()).unwrap();
    let opts = ContinuationOptions {
        param: "omega".into(),
        start: 0.8,
        stop: 0.95,
        ..Default::default()
    };
    let y0 = settled(
        &MeshModel::new(&{
            let mut p = presets::classic();
            p.set("omega", 0.8).unwrap();
            p
        })
        .unwrap(),
    );
    let c = continue_orbits(&sc, y0, &opts, &|_| {}).unwrap();
    let pd = of_kind(&c, BifurcationKind::PeriodDoubling);
    assert_eq!(pd.len(), 1, "{:?}", c.bifurcations);
    let w = pd[0].param;
    assert!(w > 0.8769 && w < 0.8844, "{w}");
    // a multiplier at -1 there
    let mu = pd[0].orbit.multipliers;
    assert!(
        mu.iter().any(|m| (m.re + 1.0).abs() < 1e-4 && m.im == 0.0),
        "{mu:?}"
    );
    for pt in &c.points {
        assert_eq!(
            pt.orbit.stable,
            pt.param < w,
            "{} {:?}",
            pt.param,
            pt.orbit.multipliers
        );
    }
    assert!(c.points.iter().any(|p| p.param > 0.93));
    assert!(c.ends[0].contains("left"), "{:?}", c.ends);
}

#[test]
fn an_orbit_of_a_law_with_memory_is_the_simulated_attractor() {
    // the internal pair's contact law keeps the hysteresis of an impact in progress: the orbit
    // carries it across the stroboscopic instant (shooting from a fresh start each time found
    // another orbit: P_ID 0.6800 instead of 0.6834)
    let sc = geardyn_scenario::ScenarioSpec::preset("internal")
        .unwrap()
        .resolve()
        .unwrap();
    let m = sc.model();
    let long = common::periods(600, 96);
    let res = simulate(m, [0.0, 0.0], &long).unwrap();
    let s = geardyn_analysis::simulate::summarize(m, &res, &long);
    assert_eq!(s.period, 3, "{}", s.label);
    let o = find_orbit(
        m,
        res.final_state.1,
        &OrbitOptions {
            period: 3,
            ..Default::default()
        },
    )
    .unwrap();
    let d = geardyn_analysis::orbits::describe_orbit(m, &o, 0.0).unwrap();
    assert_eq!(d.label, s.label);
    assert!((d.p_id - s.p_id).abs() < 1e-5, "{} vs {}", d.p_id, s.p_id);
    assert!(
        (d.max_force - s.max_force).abs() < 1e-4 * s.max_force.abs(),
        "{} vs {}",
        d.max_force,
        s.max_force
    );
}

/// A change of stability is never silent. On the broken pair at omega = 1.2 the `1-20-0` orbit
/// of the high loads loses stability near F = 0.07808: a real multiplier crosses +1 with the
/// branch going on in F (no fold, no change of the contact events), so neither the smooth tests
/// nor the grazing test fire; the continuation must still locate and report the change, with
/// the multiplier at the located point near +1 and bracketed by the branch's stable and
/// unstable points.
#[test]
fn a_multiplier_through_plus_one_without_a_fold_is_a_pitchfork_with_its_two_orbits() {
    let sc = geardyn_scenario::ScenarioSpec::preset("breakage")
        .unwrap()
        .resolve()
        .unwrap()
        .with("omega", 1.2)
        .unwrap();
    let opts = ContinuationOptions {
        param: "F".into(),
        start: 0.0785,
        stop: 0.0772,
        ds_max: 0.005,
        max_points: 60,
        ..Default::default()
    };
    let c = continue_orbits(&sc, [0.6618, -0.19207], &opts, &|_| {}).unwrap();
    let pts = &c.points;
    // the branch changes stability between two of its points ...
    let k = (1..pts.len())
        .find(|&i| pts[i].orbit.stable != pts[i - 1].orbit.stable)
        .expect("the orbit loses stability on this range");
    let (a, b) = (pts[k - 1].param, pts[k].param);
    // ... and a bifurcation is reported between them
    let found = c
        .bifurcations
        .iter()
        .find(|x| x.param <= a.max(b) && x.param >= a.min(b))
        .unwrap_or_else(|| {
            panic!(
                "no bifurcation reported in [{b}, {a}]: {:?}",
                c.bifurcations
            )
        });
    let mu = found.orbit.multipliers[0];
    assert!(mu.im == 0.0 && (mu.re - 1.0).abs() < 0.05, "{mu:?}");
    assert!((found.param - 0.07808).abs() < 5e-4, "{}", found.param);
    // a real multiplier through +1 with no fold: two new stable orbits branch off on the
    // unstable side, one on each side of the old orbit, with equal multipliers (images of each
    // other under a symmetry of the map): a pitchfork
    assert_eq!(found.kind, BifurcationKind::Pitchfork, "{found:?}");
    let [a, b] = &found.branches[..] else {
        panic!("{:?}", found.branches)
    };
    assert!(a.param < found.param && a.orbit.stable && b.orbit.stable);
    let old = c
        .points
        .iter()
        .find(|p| p.param == a.param)
        .expect("the new orbits are sought at a branch point");
    let (xa, xb, x0) = (a.orbit.y[0], b.orbit.y[0], old.orbit.y[0]);
    assert!((xa - x0) * (xb - x0) < 0.0, "{xa} {xb} {x0}");
    let (ma, mb) = (a.orbit.multipliers[0], b.orbit.multipliers[0]);
    assert!((ma.re - mb.re).abs() < 1e-3 && (ma.im.abs() - mb.im.abs()).abs() < 1e-3);
}
