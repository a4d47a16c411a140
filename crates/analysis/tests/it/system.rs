//! The analyses on a gear system other than the single pair: the two-mass, two-clearance toy
//! ([`TwoMassClearance`], four states, two meshes) through the same public functions the pair
//! uses (simulate, the summary per mesh, the decision, the exponent, the decided sweep).

use crate::common;
use geardyn_analysis::classify::{simulate_decided, Decide};
use geardyn_analysis::engine::Engine;
use geardyn_analysis::generic::{decided_sweep, Family};
use geardyn_analysis::lyapunov::{tle_two_trajectory, LyapunovOptions};
use geardyn_analysis::simulate::{simulate, summarize, SimOptions};
use geardyn_model::reference::TwoMassClearance;
use geardyn_model::{ContactState, GearSystem};
use geardyn_solvers::Scheme;

/// The toy loaded so heavily that both meshes stay in drive contact: a linear
/// two-degree-of-freedom system about the static deflection, with stiffness and damping matrices
/// `K = [[k0 + k1, -k1], [-k1, k1]]`, `C = 0.1 K` (proportional damping).
fn linear() -> TwoMassClearance {
    TwoMassClearance {
        load: [2.0, 1.0],
        ..Default::default()
    }
}

/// Complex amplitude `X1` of mass 1 under `A e^{i Omega t}` on mass 1: `(K - Omega^2 M + i
/// Omega C) X = [A, 0]`, solved by Cramer's rule (2x2 complex).
fn closed_form_amplitude(s: &TwoMassClearance) -> f64 {
    let w = s.omega;
    let [m1, m2] = s.mass;
    let [k0, k1] = s.k;
    let [c0, c1] = s.c;
    // entries as (re, im)
    let a11 = (k0 + k1 - w * w * m1, w * (c0 + c1));
    let a12 = (-k1, -w * c1);
    let a22 = (k1 - w * w * m2, w * c1);
    let mul = |a: (f64, f64), b: (f64, f64)| (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0);
    let det = {
        let p = mul(a11, a22);
        let q = mul(a12, a12);
        (p.0 - q.0, p.1 - q.1)
    };
    // X1 = A a22 / det
    let num = (s.amplitude * a22.0, s.amplitude * a22.1);
    (num.0 * num.0 + num.1 * num.1).sqrt() / (det.0 * det.0 + det.1 * det.1).sqrt()
}

#[test]
fn the_linear_limit_matches_the_closed_form_response() {
    let sys = linear();
    // static deflection in drive contact: k1 (u1 - D1) = F1, k0 (x1 - D0) + k1 (u1 - D1) = F0
    let x1_static = sys.d[0] + (sys.load[0] - sys.load[1]) / sys.k[0];
    let u1_static = sys.d[1] + sys.load[1] / sys.k[1];
    let opts = common::periods(300, 20);
    let res = simulate(&sys, [x1_static, 0.0, x1_static - u1_static, 0.0], &opts).unwrap();
    assert!(
        res.meshes.iter().all(|m| m.events.is_empty()),
        "stays in contact"
    );
    assert_eq!(res.meshes.len(), 2);
    let amp = res.meshes[0].amplitudes();
    let x1 = closed_form_amplitude(&sys);
    assert!(
        (amp.mean_x - x1_static).abs() < 1e-6,
        "mean {} vs static {x1_static}",
        amp.mean_x
    );
    assert!(
        (amp.p2p_x / 2.0 - x1).abs() < 1e-5 * x1,
        "half peak-to-peak {} vs closed form {x1}",
        amp.p2p_x / 2.0
    );
    // the second mesh's mean is the static share of the load
    assert!((res.meshes[1].amplitudes().mean_x - u1_static).abs() < 1e-6);
    let s = summarize(&sys, &res, &opts);
    assert_eq!(s.period, 1);
    // in contact throughout: no crossing, no separation
    assert_eq!(s.label, "1-0-0 1-0-0");
    assert_eq!(s.p_id, 0.0);
    assert!(s.healthy);
}

#[test]
fn the_exponent_of_the_linear_limit_is_the_modal_decay_rate() {
    // proportional damping C = alpha K: eigenvalues -alpha w_i^2 / 2 +- i w_i sqrt(..); the top
    // exponent is the real part of the slower mode, -alpha w_1^2 / 2 (closed form)
    let sys = linear();
    let alpha = sys.c[0] / sys.k[0];
    let w1 = sys.natural_frequencies()[0];
    // w_1^2 = (3 - sqrt 5) / 2 for unit masses and stiffnesses
    assert!((w1 * w1 - (3.0 - 5f64.sqrt()) / 2.0).abs() < 1e-12);
    let expected = -alpha * w1 * w1 / 2.0;
    let opts = SimOptions::default();
    let (tle, _) = sys
        .tle(&opts, 0.0, [2.0, 0.0, 0.0, 0.0], 0.0, 400)
        .expect("an exponent");
    assert!(
        (tle - expected).abs() < 0.05 * expected.abs(),
        "TLE {tle} vs -alpha w1^2 / 2 = {expected}"
    );
}

/// The toy with its clearances at a load where both meshes separate and re-enter every period.
fn rattling() -> TwoMassClearance {
    crate::common::rattling(0.4)
}

#[test]
fn the_variational_exponent_agrees_with_two_trajectories_across_contact_changes() {
    // contact damping makes the field jump at every contact change: without the saltation
    // matrix the variational estimate would be off; the two-trajectory estimate needs none
    let sys = rattling();
    let opts = SimOptions::default();
    let res = simulate(&sys, [0.0; 4], &opts).unwrap();
    let events: usize = res.meshes.iter().map(|m| m.events.len()).sum();
    assert!(events > 0, "the motion changes contact");
    let (t, y) = res.final_state;
    let (var, _) = sys
        .tle(&opts, t, y, 0.0, 300)
        .expect("variational exponent");
    let lo = LyapunovOptions {
        period: sys.excitation_period(),
        transient_periods: 0,
        periods: 300,
        d0: 1e-7,
    };
    let two = tle_two_trajectory(sys, Scheme::dopri_default(), t, y, &lo).unwrap();
    assert!(
        (var - two.tle).abs() < 0.1 * var.abs().max(1e-3),
        "variational {var} vs two-trajectory {}",
        two.tle
    );
}

#[test]
fn each_mesh_has_its_own_label_and_the_system_joins_them() {
    let sys = rattling();
    let opts = SimOptions::default();
    let (res, s, _) = simulate_decided(&sys, [0.0; 4], &opts, Decide::default()).unwrap();
    assert_eq!(s.meshes.len(), 2);
    assert_eq!(s.meshes[0].name, "mesh 1");
    if s.motion.is_periodic() {
        let joined: Vec<&str> = s.meshes.iter().map(|m| m.label.as_str()).collect();
        assert_eq!(s.label, joined.join(" "));
        for m in &s.meshes {
            assert!(m.label.starts_with(&format!("{}-", s.period)));
        }
    } else {
        // the class word of the decided motion, on the system and on every mesh
        for m in &s.meshes {
            assert_eq!(m.label, s.motion.word(), "{s:?}");
        }
    }
    // the aggregate is the extremes, totals and mean over the meshes
    let max = s
        .meshes
        .iter()
        .map(|m| m.max_force)
        .fold(f64::MIN, f64::max);
    assert_eq!(s.max_force, max);
    let pid = (s.meshes[0].p_id + s.meshes[1].p_id) / 2.0;
    assert!((s.p_id - pid).abs() < 1e-15);
    assert_eq!(s.healthy, s.meshes.iter().all(|m| m.healthy));
    // durations of each mesh add up to the recorded time
    let t_rec = opts.record_periods as f64 * sys.excitation_period();
    for m in &res.meshes {
        let total: f64 = m.durations.iter().sum();
        assert!((total - t_rec).abs() < 1e-9 * t_rec);
    }
    // the trajectories of the meshes are aligned sample by sample
    let opts = SimOptions {
        trajectory: true,
        record_periods: 3,
        ..opts
    };
    let r = simulate(&sys, [0.0; 4], &opts).unwrap();
    assert_eq!(r.meshes[0].trajectory.len(), r.meshes[1].trajectory.len());
    for (a, b) in r.meshes[0].trajectory.iter().zip(&r.meshes[1].trajectory) {
        assert_eq!(a.tau, b.tau);
    }
    // a separated mesh carries no force
    for p in &r.meshes[1].trajectory {
        if p.state == ContactState::Separated.code() {
            assert_eq!(p.mesh_force, 0.0);
        }
    }
}

/// The toy `self.0()` with the forcing amplitude as the parameter.
struct Amplitude(fn() -> TwoMassClearance);
impl Family<4> for Amplitude {
    type System = TwoMassClearance;
    fn at(&self, a: f64) -> TwoMassClearance {
        TwoMassClearance {
            amplitude: a,
            ..self.0()
        }
    }
    fn period(&self, _a: f64) -> f64 {
        self.0().excitation_period()
    }
}

#[test]
fn a_decided_sweep_of_the_toy_is_the_same_on_any_thread_count() {
    let values: Vec<f64> = (0..6).map(|i| 0.05 + 0.1 * i as f64).collect();
    let opts = SimOptions::rk4(256, 100, 32);
    let run = |threads: usize| {
        crate::common::on_threads(threads, || {
            decided_sweep(
                &Amplitude(rattling),
                &values,
                [0.0; 4],
                &opts,
                Decide::default(),
                false,
            )
        })
    };
    let (a, b) = (run(1), run(2));
    for (p, q) in a.iter().zip(&b) {
        assert_eq!(p.summary, q.summary);
        assert_eq!(p.strobe, q.strobe);
    }
    // the weakest forcing: a period-1 motion whose label is its two meshes' labels
    let s = a[0].summary.as_ref().unwrap();
    assert_eq!(s.period, 1, "{s:?}");
    let labels: Vec<&str> = s.label.split(' ').collect();
    assert_eq!(labels.len(), 2);
    for (l, m) in labels.iter().zip(&s.meshes) {
        assert_eq!(*l, m.label);
        let c: Vec<u32> = l.split('-').skip(1).map(|v| v.parse().unwrap()).collect();
        assert_eq!(c[..], m.counts[..2]);
    }
}

/// Identification of the toy with tolerances for a four-state system.
fn identify_opts() -> geardyn_analysis::attractor::IdentifyOptions {
    geardyn_analysis::attractor::IdentifyOptions {
        sim: common::periods(150, 32),
        ..Default::default()
    }
}

#[test]
fn basins_on_a_slice_of_the_linear_toy_are_one_basin() {
    use geardyn_analysis::basins::{basins, Axis, BasinOptions, Slice};
    // a linear system has one attractor, which attracts every initial state: the grid in the
    // (x1, x2) plane (velocities zero) is one basin of a period-1, impact-free orbit
    let sys = linear();
    let opts = BasinOptions {
        x: Axis {
            min: 1.5,
            max: 2.5,
            n: 6,
        },
        v: Axis {
            min: -0.5,
            max: 0.5,
            n: 5,
        },
        identify: identify_opts(),
        slice: Slice::new((0, 2), [0.0; 4]).unwrap(),
    };
    let r = basins(&sys, &opts, &Default::default(), |_, _| {});
    assert_eq!(r.attractors.len(), 1, "{:?}", r.attractors);
    let a = &r.attractors[0];
    assert_eq!(a.fraction, 1.0);
    assert_eq!(a.descriptor.period, 1);
    assert_eq!(a.descriptor.label, "1-0-0 1-0-0");
    assert_eq!(a.descriptor.points[0].len(), 4);
    assert_eq!(r.boundary_fraction, 0.0);
}

#[test]
fn continuation_of_the_toy_follows_one_branch_where_it_is_linear() {
    use geardyn_analysis::basins::Slice;
    use geardyn_analysis::continuation::{continuation_of, ContinuationOptions};
    let opts = ContinuationOptions {
        param: "amplitude".into(),
        values: vec![0.1, 0.2, 0.3],
        ics: 4,
        seed: 7,
        x0_range: (1.8, 2.2),
        v0_range: (-0.2, 0.2),
        phase: 0.0,
        identify: identify_opts(),
    };
    let r = continuation_of(&Amplitude(linear), &opts, &Slice::default()).unwrap();
    let bad = ContinuationOptions {
        x0_range: (f64::NAN, 2.0),
        ..opts.clone()
    };
    let e = continuation_of(&Amplitude(linear), &bad, &Slice::default()).unwrap_err();
    assert!(e.to_string().contains("x0_range"), "{e}");
    // one attractor per value, all on branch 0, no event between them
    assert_eq!(r.points.len(), 3, "{:?}", r.points);
    assert!(r.points.iter().all(|p| p.branch == 0 && p.period == 1));
    assert!(r.events.is_empty(), "{:?}", r.events);
    // the orbit's displacement grows with the forcing about the static deflection x1 = 2:
    // the strobe point's offset from it scales linearly with the amplitude
    let d: Vec<f64> = r.points.iter().map(|p| p.x - 2.0).collect();
    assert!(
        (d[1] / d[0] - 2.0).abs() < 1e-4 && (d[2] / d[0] - 3.0).abs() < 1e-4,
        "{d:?}"
    );
}

#[test]
fn a_decision_needs_a_record_and_a_run_needs_a_mesh() {
    use geardyn_model::{EventKind, GearSystem};
    use geardyn_solvers::Variational;
    // an empty record is refused (it would read as a motion at infinity)
    let opts = SimOptions {
        record_periods: 0,
        ..Default::default()
    };
    let e =
        simulate_decided(&linear(), [2.0, 0.0, 0.0, 0.0], &opts, Decide::default()).unwrap_err();
    assert!(e.to_string().contains("record_periods"), "{e}");
    /// `x' = -x` that claims no mesh.
    #[derive(Clone)]
    struct NoMesh;
    geardyn_solvers::one_mode_system!(NoMesh, 1, |_, _t, y, dy| {
        dy[0] = -y[0];
    });
    impl Variational<1> for NoMesh {
        fn jacobian(&self, _t: f64, _tt: &(), _y: &[f64; 1], _m: &(), j: &mut [[f64; 1]; 1]) {
            j[0][0] = -1.0;
        }
        fn guard_gradient(&self, _t: f64, _y: &[f64; 1], _m: &(), _i: usize) -> ([f64; 1], f64) {
            ([0.0], 0.0)
        }
    }
    impl GearSystem<1> for NoMesh {
        fn mesh_count(&self) -> usize {
            0
        }
        fn excitation_period(&self) -> f64 {
            1.0
        }
        fn natural_period(&self) -> f64 {
            f64::INFINITY
        }
        fn mesh_state(&self, _t: f64, y: &[f64; 1], _k: usize) -> [f64; 2] {
            [y[0], 0.0]
        }
        fn mesh_force(&self, _t: f64, _y: &[f64; 1], _m: &(), _k: usize) -> f64 {
            0.0
        }
        fn contact(&self, _m: &(), _k: usize) -> ContactState {
            ContactState::Separated
        }
        fn backlash_levels(&self, _k: usize) -> (f64, f64) {
            (1.0, 1.0)
        }
        fn event(&self, _b: &(), _a: &(), _i: usize) -> (usize, EventKind) {
            (0, EventKind::DriveEnter)
        }
    }
    let e = simulate(&NoMesh, [1.0], &SimOptions::default()).unwrap_err();
    assert!(e.to_string().contains("mesh_count"), "{e}");
    let o = geardyn_analysis::orbits::OrbitOptions::default();
    let e = geardyn_analysis::orbits::find_orbit(&NoMesh, [0.0], &o).unwrap_err();
    assert!(e.to_string().contains("mesh_count"), "{e}");
}

#[test]
fn a_start_at_rest_on_both_contact_surfaces_enters_contact() {
    // x1 = D0 and x1 - x2 = D1 at rest, the loads pressing both meshes in: contact at once (a
    // start "separated" there saw no crossing and flew off under the load)
    let sys = TwoMassClearance {
        amplitude: 0.05,
        ..Default::default()
    };
    let opts = common::periods(200, 20);
    let (res, s, _) =
        simulate_decided(&sys, [1.0, 0.0, 0.0, 0.0], &opts, Decide::default()).unwrap();
    assert!(s.motion.is_periodic(), "{s:?}");
    // about the static deflection x1 = D0 + (F0 - F1) / k0 = 1.1
    let a = res.meshes[0].amplitudes();
    assert!((a.mean_x - 1.1).abs() < 0.05, "mean x1 {}", a.mean_x);
}
