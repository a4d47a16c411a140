//! Periodic orbits of a gear system other than the pair (`geardyn_analysis::orbits` generic over
//! [`GearSystem`]): the two-mass, two-clearance toy ([`TwoMassClearance`], four states, two
//! meshes), each result against an independent value: the closed-form forced response and the
//! modal eigenvalues in the linear regime, a long simulation and the top Lyapunov exponent
//! across contact changes.

use crate::common;
use geardyn_analysis::classify::{simulate_decided, Decide};
use geardyn_analysis::engine::Engine;
use geardyn_analysis::orbits::{describe_orbit, find_orbit, stroboscopic_map, OrbitOptions};
use geardyn_analysis::simulate::{simulate, SimOptions};
use geardyn_model::reference::TwoMassClearance;
use geardyn_model::GearSystem;
use std::f64::consts::PI;

/// Complex numbers as `(re, im)`.
type C = (f64, f64);

fn mul(a: C, b: C) -> C {
    (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0)
}

fn div(a: C, b: C) -> C {
    let d = b.0 * b.0 + b.1 * b.1;
    ((a.0 * b.0 + a.1 * b.1) / d, (a.1 * b.0 - a.0 * b.1) / d)
}

/// The steady state of the toy in permanent drive contact at `t = 0`: the static deflection plus
/// `Re[X e^{i Omega t}]`, `(K - Omega^2 M + i Omega C) X = [A, 0]` solved by Cramer's rule, and
/// its derivative `Re[i Omega X]` (state `[x1, x1', x2, x2']`).
fn closed_form_orbit(s: &TwoMassClearance) -> [f64; 4] {
    let w = s.omega;
    let [m1, m2] = s.mass;
    let [k0, k1] = s.k;
    let [c0, c1] = s.c;
    // static: k1 (x1 - x2 - D1) = F1, k0 (x1 - D0) = F0 - F1
    let x1s = s.d[0] + (s.load[0] - s.load[1]) / k0;
    let x2s = x1s - (s.d[1] + s.load[1] / k1);
    let a11 = (k0 + k1 - w * w * m1, w * (c0 + c1));
    let a12 = (-k1, -w * c1);
    let a22 = (k1 - w * w * m2, w * c1);
    let det = {
        let p = mul(a11, a22);
        let q = mul(a12, a12);
        (p.0 - q.0, p.1 - q.1)
    };
    let x1 = div((s.amplitude * a22.0, s.amplitude * a22.1), det);
    let x2 = div((-s.amplitude * a12.0, -s.amplitude * a12.1), det);
    [x1s + x1.0, -w * x1.1, x2s + x2.0, -w * x2.1]
}

#[test]
fn orbits_of_the_linear_toy_are_the_forced_response_with_multipliers_exp_lambda_t() {
    // both meshes in drive contact throughout: a linear system, its orbit the forced response and
    // its monodromy exp(A T), whose eigenvalues are exp(lambda_i T) for the modal eigenvalues
    let sys = TwoMassClearance {
        load: [2.0, 1.0],
        ..Default::default()
    };
    let exact = closed_form_orbit(&sys);
    let start = [
        exact[0] + 0.1,
        exact[1] - 0.05,
        exact[2] - 0.08,
        exact[3] + 0.03,
    ];
    let o = find_orbit(&sys, start, &OrbitOptions::default()).unwrap();
    assert!(o.events.is_empty(), "permanent contact: {:?}", o.events);
    assert_eq!(o.period, 1);
    for (i, (y, e)) in o.y.iter().zip(exact).enumerate() {
        // Newton stops at |P(y) - y| <= 1e-9 (1 + |y|) (~4e-9 here; the map is linear, so it
        // lands far below); the point's error is (I - M)^-1 times that (|1 / (1 - mu)| <= 1.5
        // for these multipliers) plus the integration's (rtol 1e-11)
        assert!(
            (y - e).abs() < 1e-8,
            "component {i}: shooting {y} vs closed form {e}"
        );
    }
    // proportional damping C = 0.1 K, unit masses and stiffnesses: lambda = -0.05 w^2 +-
    // i w sqrt(1 - (0.05 w)^2) for w^2 = (3 -+ sqrt 5) / 2
    let t = 2.0 * PI / sys.omega;
    let mut want = Vec::new();
    for w2 in [(3.0 - 5f64.sqrt()) / 2.0, (3.0 + 5f64.sqrt()) / 2.0] {
        let w: f64 = w2.sqrt();
        let (re, im) = (-0.05 * w2, w * (1.0 - (0.05 * w).powi(2)).sqrt());
        for s in [1.0, -1.0] {
            let m = (re * t).exp();
            want.push((m * (s * im * t).cos(), m * (s * im * t).sin()));
        }
    }
    // the slow mode's pair first (modulus exp(-0.05 w1^2 T) = 0.84 > 0.31), each pair with its
    // positive imaginary part first
    let mu = o.multipliers;
    assert!(mu[1].abs() > mu[2].abs(), "{mu:?}");
    for pair in [&mu[..2], &mu[2..]] {
        assert!(pair[0].im > 0.0 && pair[0].re == pair[1].re && pair[1].im == -pair[0].im);
    }
    // each exp(lambda T) is a multiplier: the monodromy exp(A T) is integrated to rtol 1e-11
    // (its entries, of size <= 1, to ~1e-10), and the eigenvalues of this diagonalisable,
    // well-separated spectrum are as accurate
    for (wr, wi) in want {
        let near = mu
            .iter()
            .map(|m| (m.re - wr).hypot(m.im - wi))
            .fold(f64::INFINITY, f64::min);
        assert!(
            near < 1e-8,
            "exp(lambda T) = ({wr}, {wi}) vs {mu:?}: {near:e}"
        );
    }
    assert!(o.stable);
    // the monodromy is the map's Jacobian there, and the orbit's record is a period-1 motion in
    // contact throughout
    let (_, jac) = stroboscopic_map(&sys, o.y, &OrbitOptions::default()).unwrap();
    assert_eq!(jac, o.monodromy);
    let d = describe_orbit(&sys, &o, 0.0).unwrap();
    assert_eq!(d.label, "1-0-0 1-0-0");
}

/// The toy with its clearances where both meshes separate and re-enter twice in a period-2
/// motion (at amplitude 0.4 it is chaotic: the decision says so).
fn rattling() -> TwoMassClearance {
    crate::common::rattling(0.6)
}

#[test]
fn an_orbit_of_the_toy_with_contact_changes_is_the_simulated_attractor_and_its_multiplier_the_exponent(
) {
    let sys = rattling();
    let t = sys.excitation_period();
    // a periodic motion, as the simulation decides it
    let opts = SimOptions::default();
    let (res, s, _) = simulate_decided(&sys, [0.0; 4], &opts, Decide::default()).unwrap();
    assert!(s.motion.is_periodic(), "{}", s.label);
    assert_eq!(s.period, 2, "{}", s.label);
    // shooting for two periods from the decided run's end
    let o = find_orbit(
        &sys,
        res.final_state.1,
        &OrbitOptions {
            period: 2,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(o.period, 2, "the least period");
    assert!(o.residual < 1e-9);
    // both meshes leave and re-enter contact on the orbit (saltation at every event)
    for k in [0, 1] {
        let n = o.event_meshes.iter().filter(|&&m| m == k).count();
        assert!(n >= 4, "mesh {k}: {:?} {:?}", o.events, o.event_meshes);
    }
    assert!(o.stable);
    // its record is the decided motion
    assert_eq!(describe_orbit(&sys, &o, 0.0).unwrap().label, s.label);
    // a long plain simulation from rest (DP5 at the default tolerance, 2001 periods) reaches the
    // orbit: its strobe point is one of the orbit's two points on the section, to the
    // integration's accuracy (the transient has decayed as 0.64^1000)
    let long = common::periods(2000, 1);
    let end = simulate(&sys, [0.0; 4], &long).unwrap().final_state.1;
    let one = OrbitOptions::default();
    let (second, _) = stroboscopic_map(&sys, o.y, &one).unwrap();
    let gap = [o.y, second]
        .iter()
        .map(|p| (0..4).map(|i| (p[i] - end[i]).abs()).fold(0.0, f64::max))
        .fold(f64::INFINITY, f64::min);
    assert!(
        gap < 1e-6,
        "simulated strobe point {end:?} vs the orbit's {:?}, {second:?}: {gap:e}",
        o.y
    );
    // the top Lyapunov exponent of a stable periodic orbit is ln |mu_max| / (n T): the exponent
    // by Benettin's renormalised tangent over 3200 periods (Engine::tle: no eigenvalues, no
    // monodromy), started on the orbit
    let expected = o.multipliers[0].abs().ln() / (2.0 * t);
    let (tle, spread) = sys.tle(&opts, 0.0, o.y, o.memory, 3200).unwrap();
    // the estimate's error is bounded, not random: ln of the tangent's norm oscillates (the
    // dominant multipliers are a complex pair, |mu| 0.64) and carries the decay of the
    // subdominant one (0.58 / 0.64 = 0.9 per orbit), both O(1) in total, so the error falls as
    // 1 / (n T) (3.5e-4 after 200 periods, 3e-5 after 3200); the estimator's own standard error
    // (ten block means) is of that size: three of it, and 0.5 %
    assert!(
        (tle - expected).abs() < 3.0 * spread && (tle - expected).abs() < 5e-3 * expected.abs(),
        "TLE {tle} (+- {spread}) vs ln |mu_1| / 2T = {expected}, multipliers {:?}",
        o.multipliers
    );
}
