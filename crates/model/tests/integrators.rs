//! Convergence orders and event semantics of the integrators, measured against closed forms.

use geardyn_model::reference::{Duffing, ImpactOscillator};
use geardyn_solvers::{Direction, EventAction, Guards, HybridSystem, Integrator, Scheme, Stop};

/// Caps the adaptive step so that Dormand–Prince runs with a fixed step `h` (loose tolerances).
struct Capped<S>(S, f64);
impl<S: HybridSystem<2>> HybridSystem<2> for Capped<S> {
    type Mode = S::Mode;
    type TimeTerms = S::TimeTerms;
    geardyn_solvers::forward_methods! { to field 0;
        fn initial_mode(&self, t: f64, y: &mut [f64; 2]) -> S::Mode;
        fn time_terms(&self, t: f64) -> S::TimeTerms;
        fn rhs(&self, t: f64, tt: &S::TimeTerms, y: &[f64; 2], m: &S::Mode, dy: &mut [f64; 2]);
        fn guards(&self, t: f64, y: &[f64; 2], m: &S::Mode, g: &mut Guards);
        fn on_event(&self, t: f64, y: &mut [f64; 2], m: &mut S::Mode, i: usize) -> EventAction;
    }
    fn max_step(&self) -> f64 {
        self.1
    }
}

fn run<S: HybridSystem<2>>(sys: S, scheme: Scheme, y0: [f64; 2], t_end: f64) -> ([f64; 2], usize) {
    let mut it = Integrator::new(sys, scheme, 0.0, y0).unwrap();
    let mut events = 0;
    loop {
        match it.step(t_end).unwrap() {
            Stop::Tstop => return (*it.y(), events),
            Stop::Event { .. } => events += 1,
            _ => {}
        }
    }
}

fn fixed_dopri(h: f64) -> Scheme {
    let _ = h;
    Scheme::DormandPrince {
        rtol: 0.9,
        atol: 1.0,
    }
}

/// Least-squares slope of log(err) against log(h).
fn slope(h: &[f64], e: &[f64]) -> f64 {
    let n = h.len() as f64;
    let (lx, ly): (Vec<f64>, Vec<f64>) = h.iter().zip(e).map(|(h, e)| (h.ln(), e.ln())).unzip();
    let (mx, my) = (lx.iter().sum::<f64>() / n, ly.iter().sum::<f64>() / n);
    let sxy: f64 = lx.iter().zip(&ly).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = lx.iter().map(|x| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

/// Observed order from errors at h and h/2.
fn order(e1: f64, e2: f64) -> f64 {
    (e1 / e2).log2()
}

/// Undamped, unforced oscillator with a stop at -gap: closed-form state after impacts.
/// Between impacts x = A cos(s - phi); each arc from the stop returns to it after 2*phi'
/// where the arc is symmetric; the velocity after each impact is R times the arrival speed.
fn impact_oscillator_exact(gap: f64, r: f64, x0: f64, t_end: f64) -> [f64; 2] {
    // first arc: x = x0 cos t, reaches -gap at t1 = acos(-gap/x0)
    let mut t = (-gap / x0).acos();
    let mut v_plus = r * x0 * t.sin(); // arrival speed x0 sin t1, reflected
    if t > t_end {
        return [x0 * t_end.cos(), -x0 * t_end.sin()];
    }
    loop {
        // arc from the stop: x = -gap cos s + v sin s; back at the stop after s = 2*atan2(v, -gap)...
        // x(s) = A cos(s - p), A = hypot(gap, v), p = atan2(v, -gap); returns at s = 2p
        let p = v_plus.atan2(-gap);
        let arc = 2.0 * p;
        if t + arc > t_end {
            let s = t_end - t;
            let x = -gap * s.cos() + v_plus * s.sin();
            let v = gap * s.sin() + v_plus * s.cos();
            return [x, v];
        }
        t += arc;
        v_plus *= r; // arrival speed equals departure speed by symmetry
    }
}

#[test]
fn rk4_and_dopri_orders_on_a_smooth_case() {
    // Duffing with an exact reference from a tight adaptive run cross-checked by a second scheme
    let sys = Duffing {
        delta: 0.1,
        alpha: 1.0,
        beta: 0.5,
        gamma: 0.3,
        omega: 1.2,
    };
    let t_end = 10.0;
    let reference = run(
        sys,
        Scheme::DormandPrince {
            rtol: 1e-13,
            atol: 1e-15,
        },
        [0.5, 0.0],
        t_end,
    )
    .0;
    let check = run(sys, Scheme::Rk4 { h: 1e-3 }, [0.5, 0.0], t_end).0;
    assert!(
        (reference[0] - check[0]).abs() < 1e-11,
        "reference not converged"
    );
    let err = |scheme: Scheme, h: f64| {
        let y = run(Capped(sys, h), scheme, [0.5, 0.0], t_end).0;
        (y[0] - reference[0]).abs() + (y[1] - reference[1]).abs()
    };
    let (h1, h2) = (0.2, 0.1);
    let p_rk4 = order(
        err(Scheme::Rk4 { h: h1 }, h1),
        err(Scheme::Rk4 { h: h2 }, h2),
    );
    assert!((p_rk4 - 4.0).abs() < 0.3, "RK4 order {p_rk4}");
    // least-squares slope over four halvings (single ratios are noisy pre-asymptotically)
    let hs = [0.4, 0.2, 0.1, 0.05];
    let ed: Vec<f64> = hs.iter().map(|&h| err(fixed_dopri(h), h)).collect();
    let p_dp = slope(&hs, &ed);
    assert!((p_dp - 5.0).abs() < 0.4, "DP5 order {p_dp} ({ed:?})");
}

#[test]
fn orders_survive_events() {
    // Impacts every half cycle: if events were stepped over, order would drop to 1.
    let (gap, r, x0) = (0.5, 0.8, 1.0);
    let sys = ImpactOscillator {
        zeta: 0.0,
        a: 0.0,
        omega: 1.0,
        gap,
        r,
    };
    let t_end = 20.0;
    let exact = impact_oscillator_exact(gap, r, x0, t_end);
    let err = |scheme: Scheme, h: f64| {
        let (y, events) = run(Capped(sys, h), scheme, [x0, 0.0], t_end);
        assert!(events >= 4, "only {events} impacts");
        (y[0] - exact[0]).abs() + (y[1] - exact[1]).abs()
    };
    let e = [
        err(Scheme::Rk4 { h: 0.1 }, 0.1),
        err(Scheme::Rk4 { h: 0.05 }, 0.05),
        err(Scheme::Rk4 { h: 0.025 }, 0.025),
    ];
    let p = order(e[1], e[2]);
    assert!((p - 4.0).abs() < 0.4, "RK4 order with events {p} ({e:?})");
    let e = [err(fixed_dopri(0.2), 0.2), err(fixed_dopri(0.1), 0.1)];
    let p = order(e[0], e[1]);
    assert!((p - 5.0).abs() < 0.6, "DP5 order with events {p} ({e:?})");
    // and the adaptive run meets its tolerance through all impacts
    let y = run(sys, Scheme::dopri_default(), [x0, 0.0], t_end).0;
    assert!((y[0] - exact[0]).abs() < 1e-8 && (y[1] - exact[1]).abs() < 1e-8);
}

/// x' = 1 with a guard at x = 1 (rising) and a time breakpoint at t = 1: both fall on the same
/// instant. The event must be reported, the breakpoint handled, and nothing fire twice.
struct Coincident;
impl HybridSystem<2> for Coincident {
    type Mode = (u8, u8); // (zone, crossed)
    type TimeTerms = ();
    fn initial_mode(&self, _t: f64, _y: &mut [f64; 2]) -> (u8, u8) {
        (0, 0)
    }
    fn time_terms(&self, _t: f64) {}
    fn rhs(&self, _t: f64, _: &(), _y: &[f64; 2], m: &(u8, u8), dy: &mut [f64; 2]) {
        *dy = [1.0, if m.0 == 0 { 0.0 } else { 1.0 }];
    }
    fn guards(&self, _t: f64, y: &[f64; 2], m: &(u8, u8), g: &mut Guards) {
        if m.1 == 0 {
            g.push(y[0] - 1.0, Direction::Rising);
        } else {
            g.push(y[0] - 1.0, Direction::Falling);
        }
    }
    fn on_event(&self, _t: f64, _y: &mut [f64; 2], m: &mut (u8, u8), _i: usize) -> EventAction {
        m.1 += 1;
        EventAction::Continue
    }
    fn next_breakpoint(&self, _t: f64, m: &(u8, u8)) -> f64 {
        if m.0 == 0 {
            1.0
        } else {
            f64::INFINITY
        }
    }
    fn on_breakpoint(&self, _t: f64, _y: &mut [f64; 2], m: &mut (u8, u8)) {
        m.0 = 1;
    }
}

#[test]
fn event_and_breakpoint_at_the_same_instant() {
    for scheme in [Scheme::dopri_default(), Scheme::Rk4 { h: 0.3 }] {
        let mut it = Integrator::new(Coincident, scheme, 0.0, [0.0, 0.0]).unwrap();
        let mut events = 0;
        let mut bps = 0;
        loop {
            match it.step(3.0).unwrap() {
                Stop::Tstop => break,
                Stop::Event { .. } => {
                    events += 1;
                    assert!((it.t() - 1.0).abs() < 1e-12);
                }
                Stop::Breakpoint => {
                    bps += 1;
                    assert!((it.t() - 1.0).abs() < 1e-12);
                }
                _ => {}
            }
        }
        assert_eq!((events, bps), (1, 1), "{scheme:?}");
        // y[1] grows at rate 1 only after the breakpoint: exactly 2 at t = 3
        assert!((it.y()[1] - 2.0).abs() < 1e-12, "{scheme:?}: {:?}", it.y());
        assert_eq!(*it.mode(), (1, 1));
    }
}

#[test]
fn zeno_sequence_is_reported_not_hung() {
    // a bouncing ball with restitution 0.5 and no sticking rule: impacts accumulate at t = 3 g^-1 ...
    struct Ball;
    geardyn_solvers::one_mode_system! { Ball, 2, |_, _t, y, dy| {
            *dy = [y[1], -1.0];
        }
        fn guards(&self, _t: f64, y: &[f64; 2], _m: &(), g: &mut Guards) {
            g.push(y[0], Direction::Falling);
        }
        fn on_event(&self, _t: f64, y: &mut [f64; 2], _m: &mut (), _i: usize) -> EventAction {
            y[0] = 0.0;
            y[1] *= -0.5;
            EventAction::Continue
        }
    }
    let mut it = Integrator::new(Ball, Scheme::dopri_default(), 0.0, [0.5, 0.0]).unwrap();
    let mut n = 0;
    let res = loop {
        match it.step(10.0) {
            Ok(Stop::Tstop) => break Ok(()),
            Ok(_) => n += 1,
            Err(e) => break Err(e),
        }
        assert!(n < 1_000_000, "hung");
    };
    // Accumulation point: t* = t1 * (1 + 2 * 0.5/(1 - 0.5)) = 3 t1, t1 = 1: the run must either stop
    // with an error there or pass it; it must never hang.
    if let Err(e) = res {
        assert!(it.t() > 2.9 && it.t() < 3.0 + 1e-6, "{e} at {}", it.t());
    }
}
