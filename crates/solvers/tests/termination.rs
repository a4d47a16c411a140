//! Every integration terminates (issue 13): accumulations of impacts (Zeno), sub-ulp adaptive
//! steps, unresolvable fixed grids and runaway step counts end in a sticking mode or a clear error,
//! within a bounded number of steps.

use geardyn_solvers::{
    min_step, Direction, EventAction, Guards, HybridSystem, Integrator, Options, Scheme,
    SolverError, Stop,
};

const G: f64 = 9.81;

/// A ball falling onto a floor at `x = floor`: restitution `r`, no sticking threshold. With
/// `sticking`, it offers a resting mode through `zeno_fallback`; `broken_fallback` claims to end the
/// accumulation but does not.
#[derive(Clone, Copy)]
struct Ball {
    r: f64,
    floor: f64,
    sticking: bool,
    broken_fallback: bool,
}

impl Ball {
    fn new(r: f64, floor: f64) -> Self {
        Ball {
            r,
            floor,
            sticking: false,
            broken_fallback: false,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum BallMode {
    Flying,
    Resting,
}

impl HybridSystem<2> for Ball {
    type Mode = BallMode;
    type TimeTerms = ();
    fn initial_mode(&self, _t: f64, _y: &mut [f64; 2]) -> BallMode {
        BallMode::Flying
    }
    fn time_terms(&self, _t: f64) {}
    fn rhs(&self, _t: f64, _tt: &(), y: &[f64; 2], m: &BallMode, dy: &mut [f64; 2]) {
        *dy = match m {
            BallMode::Flying => [y[1], -G],
            BallMode::Resting => [0.0, 0.0],
        };
    }
    fn guards(&self, _t: f64, y: &[f64; 2], m: &BallMode, g: &mut Guards) {
        if *m == BallMode::Flying {
            g.push(y[0] - self.floor, Direction::Falling);
        }
    }
    fn on_event(&self, _t: f64, y: &mut [f64; 2], _m: &mut BallMode, _i: usize) -> EventAction {
        y[0] = self.floor;
        y[1] *= -self.r;
        EventAction::Continue
    }
    fn zeno_fallback(&self, _t: f64, y: &mut [f64; 2], m: &mut BallMode, _i: usize) -> bool {
        if self.broken_fallback {
            return true;
        }
        if !self.sticking {
            return false;
        }
        *y = [self.floor, 0.0];
        *m = BallMode::Resting;
        true
    }
}

/// Integrates to `tstop`; returns the outcome and the number of `step` calls.
fn drive<S: HybridSystem<2>>(
    it: &mut Integrator<S, 2>,
    tstop: f64,
    max_calls: u64,
) -> (Result<(), SolverError>, u64) {
    let mut calls = 0;
    loop {
        calls += 1;
        assert!(calls <= max_calls, "no termination after {max_calls} steps");
        match it.step(tstop) {
            Ok(Stop::Tstop) | Ok(Stop::Terminated { .. }) => return (Ok(()), calls),
            Ok(_) => {}
            Err(e) => return (Err(e), calls),
        }
    }
}

fn schemes() -> [Scheme; 2] {
    [Scheme::dopri_default(), Scheme::Rk4 { h: 1e-2 }]
}

#[test]
fn zeno_restitution_zero_without_sticking_is_an_error() {
    // R = 0: after the first impact the ball rests on the floor pushed into it by gravity and
    // re-impacts at every float step of the guard. A floor at x = 1 (guard resolution one ulp of
    // 1) and a late start make the micro-impacts ~1e-8 apart: far above the ulp of t.
    for scheme in schemes() {
        for (t0, floor) in [(0.0, 0.0), (0.0, 1.0), (1e6, 1.0)] {
            let mut it =
                Integrator::new(Ball::new(0.0, floor), scheme, t0, [floor + 1.0, 0.0]).unwrap();
            let (r, calls) = drive(&mut it, t0 + 10.0, 100_000);
            match r {
                Err(SolverError::Zeno { t, count, span }) => {
                    assert!(
                        (t0 + 0.4..t0 + 0.5).contains(&t),
                        "{scheme:?} t0={t0}: at {t}"
                    );
                    assert!(count > 64 && (0.0..1e-3).contains(&span), "{count} {span}");
                }
                other => panic!("{scheme:?} t0={t0} floor={floor}: {other:?}"),
            }
            assert!(calls < 5_000, "{scheme:?}: {calls} steps");
        }
    }
}

#[test]
fn zeno_ends_in_the_sticking_mode_the_system_offers() {
    for scheme in schemes() {
        for r in [0.0, 0.5] {
            let ball = Ball {
                sticking: true,
                ..Ball::new(r, 1.0)
            };
            let mut it = Integrator::new(ball, scheme, 0.0, [2.0, 0.0]).unwrap();
            let (res, calls) = drive(&mut it, 10.0, 100_000);
            assert_eq!(res, Ok(()), "{scheme:?} R={r}");
            assert_eq!(*it.mode(), BallMode::Resting);
            assert_eq!(*it.y(), [1.0, 0.0]);
            assert!((it.t() - 10.0).abs() < 1e-12);
            assert!(calls < 10_000, "{scheme:?} R={r}: {calls} steps");
        }
    }
}

#[test]
fn geometric_zeno_without_sticking_is_an_error() {
    // R = 0.5: the bounce times converge to sqrt(2h/g)(1 + 2R/(1-R)) = 3 sqrt(2/g)
    let t_acc = 3.0 * (2.0 / G).sqrt();
    let mut it = Integrator::new(
        Ball::new(0.5, 0.0),
        Scheme::dopri_default(),
        0.0,
        [1.0, 0.0],
    )
    .unwrap();
    let (r, calls) = drive(&mut it, 10.0, 100_000);
    match r {
        Err(SolverError::Zeno { t, .. }) => assert!((t - t_acc).abs() < 1e-3, "{t} vs {t_acc}"),
        other => panic!("{other:?}"),
    }
    assert!(calls < 5_000, "{calls}");
}

#[test]
fn a_fallback_that_does_not_end_the_accumulation_is_an_error() {
    let ball = Ball {
        broken_fallback: true,
        ..Ball::new(0.0, 1.0)
    };
    let mut it = Integrator::new(ball, Scheme::dopri_default(), 0.0, [2.0, 0.0]).unwrap();
    let (r, calls) = drive(&mut it, 10.0, 100_000);
    assert!(matches!(r, Err(SolverError::Zeno { .. })), "{r:?}");
    assert!(calls < 5_000, "{calls}");
}

#[test]
fn zeno_message_names_the_fallback() {
    let e = SolverError::Zeno {
        t: 1.5,
        count: 65,
        span: 2e-6,
    };
    let s = e.to_string();
    assert!(
        s.contains("65 events") && s.contains("zeno_fallback"),
        "{s}"
    );
}

/// Harmonic oscillator `x'' = -x` (smooth, no events), optionally with a largest step.
#[derive(Clone, Copy)]
struct Osc {
    max_step: f64,
}

geardyn_solvers::one_mode_system! { Osc, 2, |_, _t, y, dy| {
        *dy = [y[1], -y[0]];
    }
    fn max_step(&self) -> f64 {
        self.max_step
    }
}

const FREE: Osc = Osc {
    max_step: f64::INFINITY,
};

#[test]
fn late_start_time_advances_or_fails_cleanly() {
    // at t0 = 1e11 the first step guess (1e-6 for a state at rest) is below the float spacing of
    // t (1.5e-5): it used to be a zero step repeated forever
    let mut it = Integrator::new(FREE, Scheme::dopri_default(), 1e11, [0.0, 0.0]).unwrap();
    let (r, calls) = drive(&mut it, 1e11 + 10.0, 100_000);
    assert_eq!(r, Ok(()));
    assert!(calls < 1_000, "{calls}");
    // a moving state at 1e11: every step is at least min_step(t) long, the run ends
    let mut it = Integrator::new(FREE, Scheme::dopri_default(), 1e11, [1.0, 0.0]).unwrap();
    let (r, calls) = drive(&mut it, 1e11 + 10.0, 100_000);
    assert!(r.is_ok() || matches!(r, Err(SolverError::StepSizeTooSmall { .. })));
    assert!(calls < 100_000);
    // at 1e17 the shortest resolved step (36) is far too long for the tolerance
    let mut it = Integrator::new(FREE, Scheme::dopri_default(), 1e17, [1.0, 0.0]).unwrap();
    let (r, calls) = drive(&mut it, 1e17 + 1e4, 100_000);
    match r {
        Err(e @ SolverError::StepSizeTooSmall { .. }) => {
            assert!(e.to_string().contains("step size underflow"), "{e}")
        }
        other => panic!("{other:?}"),
    }
    assert!(calls < 10, "{calls}");
    assert!(min_step(1e17) > 30.0);
}

#[test]
fn max_step_below_time_resolution_is_an_error() {
    let sys = Osc { max_step: 1e-5 };
    let mut it = Integrator::new(sys, Scheme::dopri_default(), 1e11, [1.0, 0.0]).unwrap();
    match it.step(1e11 + 1.0) {
        Err(SolverError::TimeResolution { t, h, min }) => {
            assert_eq!(t, 1e11);
            assert_eq!(h, 1e-5);
            assert!(min > h);
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn huge_initial_velocity_does_not_loop() {
    // the tolerance-weighted norm of the field overflows: the step guess used to be 0
    for v in [1e150, 1e200, f64::MAX / 4.0] {
        let mut it = Integrator::new(FREE, Scheme::dopri_default(), 0.0, [0.0, v]).unwrap();
        let (_r, calls) = drive(&mut it, 1.0, 1_000_000);
        assert!(calls < 1_000_000);
        assert!(it.t() > 0.0 || calls == 1, "no progress at all");
    }
}

#[test]
fn rk4_grid_below_time_resolution_is_rejected() {
    // h = 0.05 at t = 1e15 (float spacing 0.125): the grid cannot be laid out
    match Integrator::new(FREE, Scheme::Rk4 { h: 0.05 }, 1e15, [1.0, 0.0]) {
        Err(e @ SolverError::TimeResolution { .. }) => {
            let s = e.to_string();
            assert!(s.contains("not resolved at t = 1e15"), "{s}");
        }
        Err(e) => panic!("{e}"),
        Ok(_) => panic!("accepted"),
    }
    // moved there later: the next step fails
    let mut it = Integrator::new(FREE, Scheme::Rk4 { h: 0.05 }, 0.0, [1.0, 0.0]).unwrap();
    it.reset(1e15, [1.0, 0.0]).unwrap();
    assert!(matches!(
        it.step(1e15 + 500.0),
        Err(SolverError::TimeResolution { .. })
    ));
    // or asked to step out that far
    let mut it = Integrator::new(FREE, Scheme::Rk4 { h: 0.05 }, 0.0, [1.0, 0.0]).unwrap();
    assert!(matches!(
        it.step(1e15),
        Err(SolverError::TimeResolution { .. })
    ));
    // a resolved grid still works far out
    let mut it = Integrator::new(FREE, Scheme::Rk4 { h: 0.05 }, 1e9, [1.0, 0.0]).unwrap();
    let (r, calls) = drive(&mut it, 1e9 + 1.0, 1_000);
    assert_eq!(r, Ok(()));
    assert_eq!(calls, 20);
}

#[test]
fn step_budget_per_request() {
    let mut it = Integrator::new(FREE, Scheme::Rk4 { h: 1e-2 }, 0.0, [1.0, 0.0])
        .unwrap()
        .with_options(Options {
            max_steps: Some(50),
            ..Default::default()
        });
    // 1.0 needs 100 steps
    let (r, calls) = drive(&mut it, 1.0, 1_000);
    match r {
        Err(
            ref e @ SolverError::StepBudget {
                t0,
                t,
                tstop,
                steps,
            },
        ) => {
            assert_eq!((t0, tstop, steps), (0.0, 1.0, 50));
            assert!((t - 0.5).abs() < 1e-12, "{t}");
            assert!(e.to_string().contains("step budget exhausted"), "{e}");
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(calls, 51);
    // a new request gets a new budget
    let (r, _) = drive(&mut it, 0.9, 1_000);
    assert_eq!(r, Ok(()));
    // the default budget leaves ordinary runs alone
    let mut it = Integrator::new(FREE, Scheme::Rk4 { h: 1e-3 }, 0.0, [1.0, 0.0]).unwrap();
    let (r, calls) = drive(&mut it, 100.0, 200_000);
    assert_eq!(r, Ok(()));
    assert_eq!(calls, 100_000);
}
