//! Gear trains against closed forms: kinematics of a planetary stage, its planet modes (Lin &
//! Parker 1999), the single pair's natural frequency, invariants of the two-stage drive's
//! eigenvalues, the Campbell crossings, and the errors of bad descriptions.

use approx::assert_relative_eq;
use geardyn_train::campbell::crossings;
use geardyn_train::kinematics::Kinematics;
use geardyn_train::linear::LinearModel;
use geardyn_train::presets::{self, PlanetaryParams, TwoStageParams};
use geardyn_train::{ModeKind, Modes, TrainSpec};
use nalgebra::DMatrix;

fn planetary(planets: u32) -> TrainSpec {
    presets::planetary(&PlanetaryParams {
        planets,
        ..Default::default()
    })
    .unwrap()
}

fn mesh(t: &TrainSpec, name: &str) -> geardyn_train::Mesh {
    t.meshes.iter().find(|m| m.name == name).unwrap().clone()
}

/// Ring fixed: carrier speed `Omega_s / (1 + Z_r / Z_s)`; a planet's speed relative to the
/// carrier `-(Z_s / Z_p)(Omega_s - Omega_c)`; mesh frequency `Z_r Omega_c = Z_s (Omega_s -
/// Omega_c)` (any textbook of epicyclic gearing, e.g. Müller, *Epicyclic Drive Trains*, 1982).
#[test]
fn planetary_kinematics_follow_the_willis_equation() {
    let t = planetary(3);
    let k = Kinematics::of(&t).unwrap();
    let (zs, zp, zr) = (25.0, 35.0, 95.0);
    let wc = 1.0 / (1.0 + zr / zs);
    assert_relative_eq!(k.ratios[1], wc, max_relative = 1e-10);
    assert_eq!(k.ratios[2], 0.0);
    for p in 3..6 {
        assert_relative_eq!(
            k.ratios[p] - wc,
            -(zs / zp) * (1.0 - wc),
            max_relative = 1e-9
        );
    }
    for o in &k.mesh_orders {
        assert_relative_eq!(*o, zr * wc, max_relative = 1e-9);
        assert_relative_eq!(*o, zs * (1.0 - wc), max_relative = 1e-9);
    }
    // a chipped sun tooth meets the 3 planets 3 (1 - wc) times per sun revolution
    assert_relative_eq!(k.fault_order(&t, 0), 3.0 * (1.0 - wc), max_relative = 1e-9);
}

/// Purely rotational planetary model with equally spaced, identical planets: the **planet
/// modes** move the planets only (sun, ring, carrier still), the planets' rotations summing to
/// zero, at `omega² = (k_sp + k_rp) r_bp² / I_p`, with multiplicity `N - 1` (Lin & Parker 1999,
/// J. Vib. Acoust. 121:316–321, whose translational model has `N - 3` planet modes; its
/// rotational reduction, as in Kahraman 1994, J. Sound Vib. 173:125–130, has `N - 1`). The
/// other modes: one rigid-body mode (sun and carrier free) and two rotational modes.
#[test]
fn planet_modes_have_their_closed_form_frequency_and_multiplicity() {
    for n in [3, 4] {
        let t = planetary(n);
        let m = Modes::of(&t);
        let sp = mesh(&t, "sun-planet 1");
        let rp = mesh(&t, "ring-planet 1");
        let rb = sp.base_radii_mm[1] * 1e-3;
        assert_relative_eq!(rb, rp.base_radii_mm[0] * 1e-3, max_relative = 1e-12);
        let ip = t.bodies[3].inertia_kgm2;
        let f = ((sp.stiffness_n_per_m + rp.stiffness_n_per_m) * rb * rb / ip).sqrt()
            / std::f64::consts::TAU;
        let planet: Vec<_> = m
            .modes
            .iter()
            .filter(|x| x.kind == ModeKind::Planet)
            .collect();
        assert_eq!(planet.len(), n as usize - 1, "{n} planets");
        for p in &planet {
            assert_relative_eq!(p.frequency_hz, f, max_relative = 1e-9);
            assert_eq!(p.multiplicity, n as usize - 1);
            let sum: f64 = p.shape[3..].iter().sum();
            assert!(sum.abs() < 1e-9, "{sum}");
            assert!(p.shape[..3].iter().all(|x| x.abs() < 1e-6), "{:?}", p.shape);
        }
        assert_eq!(m.count(ModeKind::RigidBody), 1);
        assert_eq!(m.count(ModeKind::Rotational), 2);
        for r in m.modes.iter().filter(|x| x.kind == ModeKind::Rotational) {
            assert_eq!(r.multiplicity, 1);
            // the planets move alike in a rotational mode
            let p0 = r.shape[3];
            assert!(r.shape[3..]
                .iter()
                .all(|x| (x - p0).abs() < 1e-9 * p0.abs().max(1.0)));
        }
    }
}

/// The rigid-body mode is the train's kinematic motion (a second computation: the rolling
/// conditions' null space against the stiffness matrix's).
#[test]
fn the_rigid_body_mode_turns_the_train_as_its_kinematics() {
    for t in [
        planetary(4),
        presets::two_stage(&TwoStageParams::default()).unwrap(),
    ] {
        let k = Kinematics::of(&t).unwrap();
        let m = Modes::of(&t);
        let rigid = &m.modes[0];
        assert_eq!(rigid.kind, ModeKind::RigidBody);
        let input = t.body_index(&t.load.input).unwrap();
        for (s, r) in rigid.shape.iter().zip(&k.ratios) {
            assert_relative_eq!(s / rigid.shape[input], *r, epsilon = 1e-9);
        }
    }
}

/// The single pair as a train: one elastic mode at the pair model's natural frequency
/// `sqrt(k_av / m_e)`, `m_e = I_p I_g / (r_b1² I_g + r_b2² I_p)` (computed by the pair physics).
#[test]
fn the_single_pair_as_a_train_has_the_pairs_natural_frequency() {
    let t = presets::single_pair().unwrap();
    let m = Modes::of(&t);
    let pm = geardyn_physics::presets::breakage().build().unwrap();
    assert_eq!(m.modes.len(), 2);
    assert_eq!(m.modes[0].kind, ModeKind::RigidBody);
    assert_relative_eq!(
        m.modes[1].frequency_hz,
        pm.omega_n / std::f64::consts::TAU,
        max_relative = 1e-9
    );
}

/// The two-stage drive's eigenvalues against invariants of `M⁻¹ K` computed another way: their
/// sum is its trace, and each makes `det(K - lambda M)` vanish; with a very soft shaft the two
/// stages decouple into two pairs of frequency `sqrt(k / m_e)` each.
#[test]
fn two_stage_eigenvalues_match_trace_determinant_and_the_decoupled_limit() {
    let t = presets::two_stage(&TwoStageParams::default()).unwrap();
    let lin = LinearModel::of(&t);
    let m = Modes::of(&t);
    let lambdas: Vec<f64> = m
        .modes
        .iter()
        .map(|x| (x.frequency_hz * std::f64::consts::TAU).powi(2))
        .collect();
    let trace: f64 = (0..lin.len())
        .map(|i| lin.stiffness[(i, i)] / lin.mass[i])
        .sum();
    assert_relative_eq!(lambdas.iter().sum::<f64>(), trace, max_relative = 1e-9);
    let mm = DMatrix::from_diagonal(&lin.mass);
    let kn = lin.stiffness.norm();
    for &l in &lambdas[1..] {
        let d = (&lin.stiffness - &mm * l).determinant();
        // relative to the scale of the product of the other terms
        let scale: f64 = (0..lin.len())
            .map(|i| lin.stiffness[(i, i)].max(l * lin.mass[i]))
            .product();
        assert!(d.abs() < 1e-7 * scale, "{l} {d} {scale} {kn}");
    }
    assert_eq!(m.count(ModeKind::RigidBody), 1);
    assert_eq!(m.count(ModeKind::Rotational), 3);
    // a soft shaft (1 mm diameter, 10 m long): the stages ring on their own
    let soft = presets::two_stage(&TwoStageParams {
        shaft_mm: [1.0, 10_000.0],
        ..Default::default()
    })
    .unwrap();
    let ms = Modes::of(&soft);
    let pair_f = |z1: u32, z2: u32| {
        let p = geardyn_physics::PairSpec {
            z1,
            z2,
            breakage: None,
            mu: 0.0,
            ..geardyn_physics::presets::breakage()
        }
        .build()
        .unwrap();
        p.omega_n / std::f64::consts::TAU
    };
    let mut want = [pair_f(20, 50), pair_f(22, 61)];
    want.sort_by(f64::total_cmp);
    assert_relative_eq!(ms.modes[2].frequency_hz, want[0], max_relative = 1e-4);
    assert_relative_eq!(ms.modes[3].frequency_hz, want[1], max_relative = 1e-4);
}

/// A crossing's speed puts harmonic `h` of its mesh frequency on the natural frequency; a
/// planetary stage's meshes all share one mesh frequency (one family).
#[test]
fn campbell_crossings_put_the_mesh_harmonic_on_the_mode() {
    let t = planetary(3);
    let k = Kinematics::of(&t).unwrap();
    let m = Modes::of(&t);
    let fams = geardyn_train::campbell::mesh_families(&t, &k);
    assert_eq!(fams.len(), 1);
    let c = crossings(&t, &k, &m, 3, 1e6);
    assert_eq!(c.len(), 3 * m.distinct().len());
    for x in &c {
        let fm = x.input_rpm / 60.0 * fams[0].1;
        assert_relative_eq!(
            f64::from(x.harmonic) * fm,
            x.frequency_hz,
            max_relative = 1e-12
        );
    }
}

/// The stage's mesh phases come from the planet positions: 25 sun teeth and 3 planets are
/// sequentially phased (0, 1/3, 2/3), the ring's 95 teeth the other way.
#[test]
fn the_preset_carries_the_geometric_mesh_phases() {
    let t = planetary(3);
    let sp: Vec<f64> = (1..=3)
        .map(|n| mesh(&t, &format!("sun-planet {n}")).phase)
        .collect();
    let rp: Vec<f64> = (1..=3)
        .map(|n| mesh(&t, &format!("ring-planet {n}")).phase)
        .collect();
    assert_relative_eq!(sp[1], 1.0 / 3.0, epsilon = 1e-12);
    assert_relative_eq!(sp[2], 2.0 / 3.0, epsilon = 1e-12);
    assert_relative_eq!(rp[1], 1.0 / 3.0, epsilon = 1e-12);
    assert_relative_eq!(rp[2], 2.0 / 3.0, epsilon = 1e-12);
}

#[test]
fn a_description_survives_toml() {
    let t = planetary(4);
    let back = TrainSpec::from_toml(&t.to_toml()).unwrap();
    assert_eq!(back, t);
}

fn err(t: &str) -> String {
    TrainSpec::from_toml(t)
        .and_then(|t| Kinematics::of(&t).map(|_| ()))
        .unwrap_err()
        .to_string()
}

fn planetary_err(sets: &[(&str, f64)]) -> String {
    let sets: Vec<(String, f64)> = sets.iter().map(|(k, v)| (k.to_string(), *v)).collect();
    presets::by_name("planetary", &sets)
        .unwrap_err()
        .to_string()
}

#[test]
fn bad_trains_are_refused_naming_the_field() {
    // planets that cannot be equally spaced, that interfere, teeth that do not close
    let e = planetary_err(&[("stage.planets", 7.0)]);
    assert!(
        e.contains("stage.planets = 7") && e.contains("equal spacing"),
        "{e}"
    );
    let e = planetary_err(&[("stage.planets", 5.0)]);
    assert!(e.contains("interfere"), "{e}");
    let e = planetary_err(&[("stage.ring_teeth", 96.0)]);
    assert!(
        e.contains("stage.ring_teeth = 96") && e.contains("95"),
        "{e}"
    );
    let e = planetary_err(&[("stage.module_mm", -3.0)]);
    assert!(
        e.contains("stage.module_mm = -3") && e.contains("mm"),
        "{e}"
    );
    let e = planetary_err(&[("stage.planets", 2.5)]);
    assert!(
        e.contains("stage.planets = 2.5") && e.contains("whole"),
        "{e}"
    );
    let e = planetary_err(&[("stage.teeth", 2.0)]);
    assert!(
        e.contains("stage.teeth") && e.contains("stage.sun_teeth"),
        "{e}"
    );
    // a mesh between bodies that do not exist
    let pair = presets::single_pair().unwrap().to_toml();
    let e = err(&pair.replace(
        "gears = [\"pinion\", \"gear\"]",
        "gears = [\"pinion\", \"wheel\"]",
    ));
    assert!(
        e.contains("mesh[0].gears = \"wheel\"") && e.contains("pinion, gear"),
        "{e}"
    );
    // a body joined to nothing
    let e = err(&format!(
        "{pair}\n[[body]]\nname = \"idler\"\ninertia_kgm2 = 1.0\n"
    ));
    assert!(
        e.contains("body[2].name = \"idler\"") && e.contains("joined to nothing"),
        "{e}"
    );
    // no load path: the output meshes with a third body only
    let mut t = presets::single_pair().unwrap();
    let mut idler = t.bodies[1].clone();
    idler.name = "idler".into();
    let mut wheel = idler.clone();
    wheel.name = "wheel".into();
    t.bodies.extend([idler, wheel]);
    let mut m = t.meshes[0].clone();
    m.name = "idler mesh".into();
    m.gears = ["idler".into(), "wheel".into()];
    t.meshes.push(m);
    t.load.output = "wheel".into();
    let e = t.validate().unwrap_err().to_string();
    assert!(e.contains("no load path"), "{e}");
    // a differential: the planetary stage with its ring let go
    let mut t = planetary(3);
    t.supports.clear();
    let e = Kinematics::of(&t).unwrap_err().to_string();
    assert!(e.contains("2 free motions"), "{e}");
    // a locked train: ring and carrier both held
    let mut t = planetary(3);
    t.load.output = "planet 1".into();
    t.supports.push(geardyn_train::Support {
        body: "carrier".into(),
        stiffness_nm_per_rad: None,
    });
    let e = Kinematics::of(&t).unwrap_err().to_string();
    assert!(e.contains("locked") || e.contains("0 free"), "{e}");
    // a pin error out of range, or on a body no carrier carries
    let e = planetary_err(&[("stage.pin_error", 200.0)]);
    assert!(
        e.contains("stage.pin_error = 200") && e.contains("[-100, 100]"),
        "{e}"
    );
    let mut t = planetary(3);
    t.bodies[0].pin_error = 0.1;
    let e = t.validate().unwrap_err().to_string();
    assert!(
        e.contains("body[0].pin_error") && e.contains("carried"),
        "{e}"
    );
    let mut t = planetary(3);
    let p = t.body_index("planet 2").unwrap();
    t.bodies[p].pin_error = f64::NAN;
    let e = t.validate().unwrap_err().to_string();
    assert!(e.contains(&format!("body[{p}].pin_error")), "{e}");
    // unknown fields and NaN
    assert!(err("name = 1").contains("invalid type"));
    let e = err(&pair.replace("stiffness_n_per_m = ", "stiffness_n_per_m = -"));
    assert!(e.contains("mesh[0].stiffness_n_per_m"), "{e}");
}

/// Planet phasing (Parker 2000, J. Sound Vib. 236:561–573, rotational model): harmonic `h` of
/// the mesh frequency of `N` equally spaced planets around `Z` sun teeth excites the rotational
/// modes when `h Z / N` is whole and the planet modes otherwise. 25 sun teeth and 3 planets:
/// harmonics 1 and 2 excite only the planet modes, harmonic 3 only the rotational ones; 24 sun
/// teeth and 4 planets (in phase): every harmonic excites only the rotational modes.
#[test]
fn planet_phasing_decides_which_crossings_excite_their_modes() {
    let check = |t: &TrainSpec, rule: &dyn Fn(u32, ModeKind) -> bool| {
        let k = Kinematics::of(t).unwrap();
        let m = Modes::of(t);
        let c = crossings(t, &k, &m, 4, 1e9);
        assert_eq!(c.len(), 4 * m.distinct().len());
        for x in &c {
            let kind = if x.kind == "planet" {
                ModeKind::Planet
            } else {
                ModeKind::Rotational
            };
            assert_eq!(x.excited, rule(x.harmonic, kind), "{x:?}");
        }
    };
    check(&planetary(3), &|h, kind| {
        if h % 3 == 0 {
            kind == ModeKind::Rotational
        } else {
            kind == ModeKind::Planet
        }
    });
    let in_phase = presets::planetary(&PlanetaryParams {
        sun: 24,
        planet: 36,
        ring: 96,
        planets: 4,
        ..Default::default()
    })
    .unwrap();
    check(&in_phase, &|_, kind| kind == ModeKind::Rotational);
    // a drive without planets: every crossing counts
    let t = presets::two_stage(&TwoStageParams::default()).unwrap();
    let k = Kinematics::of(&t).unwrap();
    assert!(crossings(&t, &k, &Modes::of(&t), 2, 1e9)
        .iter()
        .all(|x| x.excited));
}

/// A shaft far stiffer than the meshes (2 m in diameter) leaves one rigid-body mode: the others
/// are real, however small beside the shaft's (a relative threshold called them rigid).
#[test]
fn a_stiff_shaft_does_not_make_modes_rigid() {
    let t = presets::two_stage(&TwoStageParams {
        shaft_mm: [2000.0, 150.0],
        ..Default::default()
    })
    .unwrap();
    let m = Modes::of(&t);
    assert_eq!(m.count(ModeKind::RigidBody), 1);
    assert!(m.modes[1].frequency_hz > 100.0, "{:?}", m.modes[1]);
    // the shaft's mode is rigid in the limit: the rest is the lumped three-body drive
    let soft = Modes::of(&presets::two_stage(&TwoStageParams::default()).unwrap());
    assert!(m.modes[1].frequency_hz > soft.modes[1].frequency_hz);
}

/// A chipped sun tooth enters the sun–planet meshes at whole cycles of each (as every tooth
/// does) and meets the planets in turn every `Z_s / N` cycles of mesh 1: 25/3 for the preset,
/// the sun-fault frequency `N f_m / Z_s` of McFadden & Smith 1985; a planet's tooth fault and a
/// loss outside [0, 1) are refused by name.
#[test]
fn a_chipped_sun_tooth_meets_the_planets_in_turn() {
    use geardyn_train::fault::windows;
    use geardyn_train::presets::{planetary, PlanetaryParams};
    let mut spec = planetary(&PlanetaryParams {
        sun_chip: 0.2,
        ..Default::default()
    })
    .unwrap();
    let w = windows(&spec).unwrap();
    let mut arrivals: Vec<f64> = spec
        .meshes
        .iter()
        .zip(&w)
        .filter_map(|(m, w)| w.map(|w| (w.offset - m.phase).rem_euclid(25.0)))
        .collect();
    assert_eq!(arrivals.len(), 3);
    arrivals.sort_by(f64::total_cmp);
    for (a, b) in arrivals.iter().zip(&arrivals[1..]) {
        assert!((b - a - 25.0 / 3.0).abs() < 1e-9, "{arrivals:?}");
    }
    for w in w.iter().flatten() {
        assert_eq!(w.offset.fract(), 0.0);
        assert_eq!(w.period, 25.0);
        assert_eq!(
            (
                w.weight(w.offset + 0.5 * (w.length - 1.0)),
                w.weight(w.offset + 0.99)
            ),
            (0.5, 1.0)
        );
        assert_eq!(w.weight(w.offset + w.length + 0.01), 0.0);
    }
    let f = spec.fault.as_mut().unwrap();
    f.gear = "planet 2".into();
    let e = spec.validate().unwrap_err().to_string();
    assert!(e.contains("fault.gear") && e.contains("planet"), "{e}");
    let e = planetary(&PlanetaryParams {
        sun_chip: 1.0,
        ..Default::default()
    })
    .unwrap_err()
    .to_string();
    assert!(e.contains("stage.sun_chip"), "{e}");
}
