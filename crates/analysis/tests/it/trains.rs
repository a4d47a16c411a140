//! Gear trains through the analyses (issue 49): the single pair written as a train against the
//! pair model, energy conservation of the undamped train, the planetary stage's static load
//! sharing and cyclic symmetry, and its linearisation against its modes.

use geardyn_analysis::classify::{simulate_decided, Decide};
use geardyn_analysis::simulate::{simulate, Method, SimOptions};
use geardyn_model::{presets, GearSystem, MeshModel};
use geardyn_solvers::HybridSystem;
use geardyn_train::dynamics::{MeshStiffness, TrainModel, TrainOperating};
use geardyn_train::presets as trains;
use geardyn_train::{ModeKind, Modes};

/// Case C1 (the `classic` preset: harmonic stiffness 0.2, `xi = 0.2`, `c = 0.1`, `D = 1`,
/// `F = 0.1`) as the operating point of a one-mesh train.
fn c1(omega: f64) -> TrainOperating {
    TrainOperating {
        omega,
        load: 0.1,
        xi: 0.2,
        c: 0.1,
        d: 1.0,
        stiffness: MeshStiffness::Harmonic { kappa: 0.2 },
    }
}

/// The train's state whose mesh deflection is `[x, v]` at `t = 0` (one mesh: `b = +-1`).
fn train_state(m: &TrainModel<2>, x: f64, v: f64) -> [f64; 2] {
    let e = m.mesh_state(0.0, &[0.0, 0.0], 0);
    let b = m.mesh_state(0.0, &[1.0, 0.0], 0)[0] - e[0];
    [(x - e[0]) / b, (v - e[1]) / b]
}

/// The single pair written as a train (its own coordinates, its own mesh law in matrix form)
/// gives the pair model's stroboscopic points, mesh forces and labels at the same operating
/// point (the acceptance of issue 49), periodic and with back-side contacts.
#[test]
fn the_pair_as_a_train_reproduces_the_pair_model() {
    let spec = trains::single_pair().unwrap();
    let opts = SimOptions::default();
    for omega in [0.8, 1.0, 2.6] {
        let mut p = presets::classic();
        p.omega = omega;
        let pair = MeshModel::new(&p).unwrap();
        let train = TrainModel::<2>::new(&spec, &c1(omega)).unwrap();
        assert_eq!(train.excitation_period(), pair.excitation_period());
        let (rp, sp, _) = simulate_decided(&pair, [0.0, 0.0], &opts, Decide::default()).unwrap();
        let y0 = train_state(&train, 0.0, 0.0);
        let (rt, st, _) = simulate_decided(&train, y0, &opts, Decide::default()).unwrap();
        assert_eq!(st.label, sp.label, "omega {omega}");
        // (force extremes are located on samples of each step, and the pair limits its steps
        // where the train does not: to 1e-4; the stroboscopic points below to 1e-6)
        assert!(
            (st.max_force - sp.max_force).abs() < 1e-4 * sp.max_force,
            "omega {omega}: {} {} {} {}",
            st.max_force,
            sp.max_force,
            st.label,
            sp.motion.describe()
        );
        assert!((st.min_force - sp.min_force).abs() < 1e-4 * sp.max_force);
        let n = rp.strobe.len().min(rt.strobe.len());
        assert!(n > 10);
        for (a, b) in rp.strobe[rp.strobe.len() - n..]
            .iter()
            .zip(&rt.strobe[rt.strobe.len() - n..])
        {
            let d = train.mesh_state(b.tau, &b.y, 0);
            assert!((a.tau - b.tau).abs() < 1e-9 * a.tau.max(1.0));
            assert!(
                (a.y[0] - d[0]).abs() < 1e-6 && (a.y[1] - d[1]).abs() < 1e-6,
                "omega {omega}: {:?} {d:?}",
                a.y
            );
        }
    }
}

/// Without damping, stiffness variation, transmission error or load, the train's energy is
/// constant along a motion through contacts and separations of every mesh: to the integrator's
/// tolerance.
#[test]
fn an_undamped_constant_stiffness_train_conserves_energy() {
    let spec = trains::planetary(&trains::PlanetaryParams::default()).unwrap();
    let op = TrainOperating {
        omega: 1.0,
        load: 0.0,
        xi: 0.0,
        c: 0.0,
        d: 0.5,
        stiffness: MeshStiffness::Harmonic { kappa: 0.0 },
    };
    let m = TrainModel::<8>::new(&spec, &op).unwrap();
    let opts = SimOptions {
        method: Method::Dopri {
            rtol: 1e-11,
            atol: 1e-13,
        },
        transient_periods: 0,
        record_periods: 200,
        ..Default::default()
    };
    let mut y0 = [0.0; 8];
    y0[0] = 3.0;
    y0[1] = -2.0;
    y0[3] = 1.5;
    let r = simulate(&m, y0, &opts).unwrap();
    let energy = |t: f64, y: &[f64; 8]| {
        let mut y = *y;
        let mode = m.initial_mode(t, &mut y);
        m.energy(t, &y, &mode)
    };
    let e0 = energy(0.0, &y0);
    let events: usize = r.meshes.iter().map(|x| x.events.len()).sum();
    assert!(
        events > 100,
        "the meshes separate and close: {events} events"
    );
    for s in &r.strobe {
        let e = energy(s.tau, &s.y);
        assert!((e - e0).abs() < 1e-7 * e0, "{e} {e0}");
    }
}

/// Equal planets share the load equally at mean stiffness, every mesh on its drive flank; the
/// sun–planet and ring–planet meshes of one planet carry the same force (the planet's torque
/// balance, equal base radii).
#[test]
fn the_planets_share_the_static_load_equally() {
    let spec = trains::planetary(&trains::PlanetaryParams::default()).unwrap();
    let m = TrainModel::<8>::new(&spec, &TrainOperating::default()).unwrap();
    let f = m.static_forces();
    assert_eq!(f.len(), 6);
    for x in f {
        assert!((x - 0.1).abs() < 1e-9, "{f:?}");
    }
    assert!(m.input_rpm() > 0.0);
}

/// A tangential position error `e` of planet 1's pin (ahead in the carrier's sense): the sun and
/// carrier rotations are common to all planets, and each planet is a path of its sun and ring
/// meshes in series (its own rotation free, so both carry the same force `W_i`), which the error
/// shortens by `cos(alpha')` e at each mesh (`alpha'` the operating pressure angle: `cos(alpha')
/// = (r_bs + r_bp) / r_c`). With the total `sum W_i` fixed by the sun's torque,
/// `W_i = W_mean - 2 cos(alpha') k_path (e_i - e_mean)`, `k_path = k_sp k_rp / (k_sp + k_rp)`
/// (the torsional load-sharing model of Kahraman, "Load sharing characteristics of planetary
/// transmissions", Mech. Mach. Theory 29, 1994). The dynamic model, damped at constant stiffness,
/// settles on the same forces.
#[test]
fn a_planet_pin_error_shifts_its_load_to_the_other_planets() {
    let e = 0.04;
    let spec = trains::planetary(&trains::PlanetaryParams {
        pin_error: e,
        ..Default::default()
    })
    .unwrap();
    let op = TrainOperating {
        stiffness: MeshStiffness::Rectangular { ratio: 1.0 },
        ..Default::default()
    };
    let m = TrainModel::<8>::new(&spec, &op).unwrap();
    let f = m.static_forces();
    let at = |name: &str| spec.meshes.iter().position(|x| x.name == name).unwrap();
    let sun = spec.meshes[at("sun-planet 1")].clone();
    let ring = spec.meshes[at("ring-planet 1")].clone();
    let k_ref = spec.meshes[0].stiffness_n_per_m;
    let k_path = sun.stiffness_n_per_m * ring.stiffness_n_per_m
        / (sun.stiffness_n_per_m + ring.stiffness_n_per_m)
        / k_ref;
    let r_c = spec.bodies[spec.body_index("planet 1").unwrap()].orbit_radius_mm;
    let cos_a = (sun.base_radii_mm[0] + sun.base_radii_mm[1]) / r_c;
    assert!(cos_a > 0.85 && cos_a < 0.95, "{cos_a}");
    let w: Vec<f64> = (1..=3).map(|p| f[at(&format!("sun-planet {p}"))]).collect();
    for p in 1..=3 {
        let (s, r) = (
            f[at(&format!("sun-planet {p}"))],
            f[at(&format!("ring-planet {p}"))],
        );
        assert!((s - r).abs() < 1e-12, "planet {p}: {s} vs {r}");
    }
    let mean = 0.1;
    assert!((w.iter().sum::<f64>() - 3.0 * mean).abs() < 1e-12, "{w:?}");
    let expect = |ei: f64| mean - 2.0 * cos_a * k_path * (ei - e / 3.0);
    assert!((w[0] - expect(e)).abs() < 1e-12, "{w:?} vs {}", expect(e));
    assert!((w[1] - expect(0.0)).abs() < 1e-12, "{w:?}");
    assert!((w[2] - expect(0.0)).abs() < 1e-12, "{w:?}");
    assert!(w[0] < w[1], "a pin ahead takes less load: {w:?}");
    // the dynamics: damped, at constant stiffness and no transmission error, from the static
    // state of the error-free train the motion settles on the same forces
    let opts = SimOptions {
        transient_periods: 400,
        record_periods: 1,
        ..Default::default()
    };
    let r = simulate(&m, [0.0; 8], &opts).unwrap();
    let s = r.strobe.last().unwrap();
    let mut y = s.y;
    let mode = m.initial_mode(s.tau, &mut y);
    for (k, fk) in f.iter().enumerate() {
        let dynamic = m.mesh_force(s.tau, &y, &mode, k);
        assert!((dynamic - fk).abs() < 1e-6, "mesh {k}: {dynamic} vs {fk}");
    }
    // an error the closed form would give a negative load: planet 1 lets go (both its meshes
    // separate), the two others carry the sun's torque equally; the dynamics settle there too
    let unloaded = |e: f64| {
        let spec = trains::planetary(&trains::PlanetaryParams {
            pin_error: e,
            ..Default::default()
        })
        .unwrap();
        TrainModel::<8>::new(&spec, &op)
    };
    assert!(expect(0.3) < 0.0);
    let m = unloaded(0.3).unwrap();
    let f = m.static_forces();
    for p in 1..=3 {
        let want = if p == 1 { 0.0 } else { 0.15 };
        for mesh in ["sun", "ring"] {
            let k = at(&format!("{mesh}-planet {p}"));
            assert!((f[k] - want).abs() < 1e-12, "{mesh}-planet {p}: {f:?}");
        }
    }
    let r = simulate(&m, m.static_state(), &opts).unwrap();
    let s = r.strobe.last().unwrap();
    let mut y = s.y;
    let mode = m.initial_mode(s.tau, &mut y);
    for (k, fk) in f.iter().enumerate() {
        let dynamic = m.mesh_force(s.tau, &y, &mode, k);
        assert!((dynamic - fk).abs() < 1e-6, "mesh {k}: {dynamic} vs {fk}");
    }
    // the unloaded planet floats in the middle of its free play: both its meshes stay off their
    // back flanks while the sum of their deflections is above -2D (about e < 2.27 here), and
    // the meshes that let go carry exactly 0
    let m = unloaded(2.0).unwrap();
    assert_eq!(f.iter().filter(|x| **x == 0.0).count(), 2, "{f:?}");
    assert!(m.static_forces().iter().filter(|x| **x == 0.0).count() == 2);
    // an error the backlash cannot take up jams the planet on its back flanks: refused by name
    assert!(unloaded(2.4).is_err());
    let e = unloaded(50.0).err().unwrap().to_string();
    assert!(e.contains("pin_error") && e.contains("back flank"), "{e}");
}

/// The linearised train's natural frequencies are the modes' (a second computation: the dynamic
/// model's elastic coordinates against the modal analysis of the bodies' rotations).
#[test]
fn the_dynamic_model_linearises_to_the_modes() {
    for (spec, dof) in [
        (
            trains::planetary(&trains::PlanetaryParams::default()).unwrap(),
            4,
        ),
        (
            trains::two_stage(&trains::TwoStageParams::default()).unwrap(),
            3,
        ),
    ] {
        let modes = Modes::of(&spec);
        let hz: Vec<f64> = modes
            .modes
            .iter()
            .filter(|x| x.kind != ModeKind::RigidBody)
            .map(|x| x.frequency_hz)
            .collect();
        assert_eq!(hz.len(), dof);
        let w = if dof == 4 {
            let m = TrainModel::<8>::new(&spec, &TrainOperating::default()).unwrap();
            m.frequencies()
                .iter()
                .map(|f| f * m.omega_ref() / std::f64::consts::TAU)
                .collect::<Vec<_>>()
        } else {
            let m = TrainModel::<6>::new(&spec, &TrainOperating::default()).unwrap();
            m.frequencies()
                .iter()
                .map(|f| f * m.omega_ref() / std::f64::consts::TAU)
                .collect::<Vec<_>>()
        };
        let mut w = w;
        w.sort_by(f64::total_cmp);
        for (a, b) in w.iter().zip(&hz) {
            assert!((a - b).abs() < 1e-8 * b, "{w:?} {hz:?}");
        }
    }
}

/// Sequentially phased equal planets: each planet's meshes see the same stiffness shifted by a
/// third of a mesh cycle, so on a periodic motion of one mesh cycle every planet's mesh force
/// reaches the same extremes (cyclic symmetry), while each mesh's force varies.
#[test]
fn a_phased_planetary_stage_is_cyclically_symmetric() {
    let spec = trains::planetary(&trains::PlanetaryParams::default()).unwrap();
    let op = TrainOperating {
        omega: 0.5,
        ..TrainOperating::default()
    };
    let m = TrainModel::<8>::new(&spec, &op).unwrap();
    assert_eq!(m.cycles_per_period(), 1);
    let opts = SimOptions {
        transient_periods: 300,
        record_periods: 30,
        ..Default::default()
    };
    let (_, s, _) = simulate_decided(&m, [0.0; 8], &opts, Decide::default()).unwrap();
    assert_eq!(s.period, 1, "{}", s.label);
    assert_eq!(s.meshes.len(), 6);
    let sun: Vec<f64> = (0..3).map(|n| s.meshes[2 * n].max_force).collect();
    let ring: Vec<f64> = (0..3).map(|n| s.meshes[2 * n + 1].max_force).collect();
    for v in [&sun, &ring] {
        // (each extreme is located on samples of its steps: to 1e-4 of its size)
        assert!(
            (v[1] - v[0]).abs() < 1e-4 * v[0] && (v[2] - v[0]).abs() < 1e-4 * v[0],
            "{v:?}"
        );
        assert!(v[0] > 0.1, "{v:?}");
    }
}

/// A train in a larger state padded with zeros steps exactly as in its own: the two-stage drive
/// (3 elastic degrees of freedom) in 6 and in 8 components gives the same stroboscopic mesh
/// states, forces and label to the last bit (the padding stays zero and the error norm counts
/// the moving components only), with contact loss.
#[test]
fn a_padded_train_steps_as_its_own_size() {
    let spec = trains::two_stage(&trains::TwoStageParams::default()).unwrap();
    for omega in [0.6, 1.0] {
        let op = TrainOperating {
            omega,
            ..TrainOperating::default()
        };
        let exact = TrainModel::<6>::new(&spec, &op).unwrap();
        let padded = TrainModel::<8>::new(&spec, &op).unwrap();
        assert_eq!(padded.dof(), 3);
        assert_eq!(padded.active_dim(), 6);
        let opts = SimOptions {
            transient_periods: 50,
            record_periods: 20,
            ..Default::default()
        };
        let (re, se, _) =
            simulate_decided(&exact, exact.static_state(), &opts, Decide::default()).unwrap();
        let (rp, sp, _) =
            simulate_decided(&padded, padded.static_state(), &opts, Decide::default()).unwrap();
        assert_eq!(se.label, sp.label, "omega {omega}");
        assert_eq!(se.max_force, sp.max_force);
        assert_eq!(re.strobe.len(), rp.strobe.len());
        for (a, b) in re.strobe.iter().zip(&rp.strobe) {
            for k in 0..exact.mesh_count() {
                assert_eq!(
                    exact.mesh_state(a.tau, &a.y, k),
                    padded.mesh_state(b.tau, &b.y, k)
                );
            }
            assert!(b.y[3] == 0.0 && b.y[7] == 0.0);
        }
    }
    // (a state too small for the train is refused, naming it)
    let e = TrainModel::<4>::new(&spec, &TrainOperating::default()).unwrap_err();
    assert!(e.to_string().contains("state dimension"), "{e}");
}

/// A fixed transducer on the ring of a cyclically symmetric stage sees only carrier orders that
/// are multiples of the number of planets (McFadden & Smith 1985, "An explanation for the
/// asymmetry of the modulation sidebands about the tooth meshing frequency in epicyclic gear
/// vibration", Proc. IMechE C 199: the planets' windowed contributions cancel elsewhere), so
/// the mesh order `Z_r = 95` of the 3-planet preset is absent and its neighbour 96 carries it;
/// the sun torque keeps only the mesh harmonics `h` with `h Z_s / N` whole (Parker 2000's
/// cancellation: `h = 3`, order 285).
#[test]
fn a_ring_transducer_sees_only_multiples_of_the_planet_count() {
    use geardyn_analysis::stage_signals::{stage_signals, StageSignalsRequest};
    let spec = trains::planetary(&trains::PlanetaryParams::default()).unwrap();
    let op = TrainOperating {
        omega: 0.5,
        ..TrainOperating::default()
    };
    let m = TrainModel::<8>::new(&spec, &op).unwrap();
    let s = stage_signals(
        &spec,
        &m,
        (0.0, m.static_state()),
        &StageSignalsRequest::default(),
    )
    .unwrap();
    assert_eq!(s.carrier_revolutions, 1.0);
    assert!((s.mesh_order - 95.0).abs() < 1e-9, "{}", s.mesh_order);
    assert_eq!(s.planets, 3);
    let a = &s.sensor_spectrum;
    let top = a[1..].iter().cloned().fold(0.0, f64::max);
    let off = (1..a.len())
        .filter(|j| j % 3 != 0)
        .map(|j| a[j])
        .fold(0.0, f64::max);
    assert!(
        off < 1e-6 * top,
        "largest order off the multiples of 3: {off:e} (top {top:e})"
    );
    let near = (90..=100).max_by(|&i, &j| a[i].total_cmp(&a[j])).unwrap();
    assert_eq!(near, 96, "{:?}", &a[90..=100]);
    assert!(a[96] > 1e-3 * top);
    let t = &s.sun_spectrum;
    let top = t[1..].iter().cloned().fold(0.0, f64::max);
    let off = (1..t.len())
        .filter(|j| j % 285 != 0)
        .map(|j| t[j])
        .fold(0.0, f64::max);
    assert!(
        off < 1e-6 * top,
        "sun torque off the multiples of 285: {off:e} (top {top:e})"
    );
}

/// A chipped sun tooth meets the three planets in turn, `N Z_r / Z_s = 11.4` times per carrier
/// revolution: the sun torque of the faulted, otherwise symmetric stage holds lines on the
/// multiples of that order only (the stage repeats itself, a planet on, every `Z_s / N` mesh
/// cycles), the first of them clearly present; the record closes on 5 carrier revolutions
/// (`lcm(25, 95)` mesh cycles).
#[test]
fn a_chipped_sun_tooth_shows_at_its_characteristic_order() {
    use geardyn_analysis::stage_signals::{stage_signals, StageSignalsRequest};
    let spec = trains::planetary(&trains::PlanetaryParams {
        sun_chip: 0.3,
        ..Default::default()
    })
    .unwrap();
    let op = TrainOperating {
        omega: 0.5,
        ..TrainOperating::default()
    };
    let m = TrainModel::<8>::new(&spec, &op).unwrap();
    assert_eq!(m.cycles_per_period(), 25);
    let s = stage_signals(
        &spec,
        &m,
        (0.0, m.static_state()),
        &StageSignalsRequest::default(),
    )
    .unwrap();
    assert_eq!(s.carrier_revolutions, 5.0);
    let fo = s.fault_order.unwrap();
    assert!((fo - 11.4).abs() < 1e-12, "{fo}");
    let t = &s.sun_spectrum;
    let top = t[1..].iter().cloned().fold(0.0, f64::max);
    let off = (1..t.len())
        .filter(|j| j % 57 != 0)
        .map(|j| t[j])
        .fold(0.0, f64::max);
    assert!(
        off < 1e-6 * top,
        "off the fault order's multiples: {off:e} (top {top:e})"
    );
    assert!(t[57] > 1e-3 * top, "{:e} {top:e}", t[57]);
}

/// A stage of 4 planets runs padded (5 elastic degrees of freedom in 16 components): its orbit's
/// multipliers are finite, the padding's are its decay factor (exactly decoupled), and the orbit
/// the decided motion settles on is stable (the Schur iteration alone did not converge beside the
/// padding's block of equal eigenvalues: every orbit read NaN and unstable).
#[test]
fn a_padded_stage_has_finite_floquet_multipliers() {
    let spec = trains::by_name("planetary", &[("stage.planets".into(), 4.0)]).unwrap();
    let op = TrainOperating {
        xi: 0.1,
        ..TrainOperating::default()
    };
    let m = TrainModel::<16>::new(&spec, &op).unwrap();
    assert_eq!(m.dof(), 5);
    let (res, s, _) = simulate_decided(
        &m,
        m.static_state(),
        &SimOptions::default(),
        Decide::default(),
    )
    .unwrap();
    assert_eq!(s.period, 1, "{}", s.describe());
    let y = *res.strobe_states().last().unwrap();
    let o = geardyn_analysis::orbits::find_orbit(&m, y, &Default::default()).unwrap();
    assert!(o.multipliers.iter().all(|mu| mu.abs().is_finite()));
    assert!(
        o.stable && o.multipliers[0].abs() < 1.0,
        "{:?}",
        o.multipliers
    );
    // the six padding components' multiplier: their own diagonal entry
    let pad = o.monodromy[5][5];
    assert_eq!(
        o.multipliers
            .iter()
            .filter(|mu| mu.re == pad && mu.im == 0.0)
            .count(),
        6
    );
}
