//! Gear-pair physics against closed forms, standards and limit cases.

use geardyn_physics::geometry::{PairGeometry, PairGeometryInput, PairKind};
use geardyn_physics::mesh_stiffness::{HertzModel, LoadSharing};
use geardyn_physics::pair::{BreakageSpec, OperatingPoint, PairSpec};
use std::f64::consts::PI;

fn spec_40_40() -> PairSpec {
    // the seed A pair (40/40, m = 3, 20 deg, B = 20 mm, 206 GPa, mu = 0.15), healthy
    let mut s = geardyn_physics::presets::breakage();
    s.breakage = None;
    s.samples_per_cycle = 512;
    s
}

/// A pair of module 3 mm, 20 degrees, standard addendum and clearance.
fn geometry(
    kind: PairKind,
    z1: u32,
    z2: u32,
    x1: f64,
    x2: f64,
) -> Result<PairGeometry, geardyn_physics::PhysicsError> {
    PairGeometry::new(&PairGeometryInput {
        kind,
        z1,
        z2,
        module: 3e-3,
        pressure_angle: 20f64.to_radians(),
        addendum: 1.0,
        clearance: 0.25,
        x1,
        x2,
    })
}

#[test]
fn contact_ratios_match_the_closed_forms() {
    let a = 20f64.to_radians();
    // external 40/40, m = 3: eps = (2 sqrt(ra^2 - rb^2) - 2 r sin a) / (pi m cos a)
    let g = geometry(PairKind::External, 40, 40, 0.0, 0.0).unwrap();
    let (r, ra) = (60e-3f64, 63e-3f64);
    let rb = r * a.cos();
    let eps = (2.0 * (ra * ra - rb * rb).sqrt() - 2.0 * r * a.sin()) / (PI * 3e-3 * a.cos());
    assert!((g.eps - eps).abs() < 1e-12, "{} vs {eps}", g.eps);
    assert!((eps - 1.7145).abs() < 1e-3);
    // internal 30/70, m = 3: eps = (sqrt(ra1^2 - rb1^2) - sqrt(ra2^2 - rb2^2) + a sin(alpha)) / p_b
    // with ra2 = r2 - m (ring tip inside), a = r2 - r1 (e.g. Maitra, Handbook of Gear Design, 1994)
    let gi = geometry(PairKind::Internal, 30, 70, 0.0, 0.0).unwrap();
    let (r1, r2) = (45e-3f64, 105e-3f64);
    let (rb1, rb2) = (r1 * a.cos(), r2 * a.cos());
    let (ra1, ra2) = (48e-3f64, 102e-3f64);
    let eps_i = ((ra1 * ra1 - rb1 * rb1).sqrt() - (ra2 * ra2 - rb2 * rb2).sqrt() + 60e-3 * a.sin())
        / (PI * 3e-3 * a.cos());
    assert!((gi.eps - eps_i).abs() < 1e-12, "{} vs {eps_i}", gi.eps);
    assert!(gi.eps > 1.9 && gi.eps < 2.0);
    // a profile-shifted pair: the operating pressure angle solves the involute equation
    let gs = geometry(PairKind::External, 20, 40, 0.3, 0.1).unwrap();
    let lhs = gs.alpha_w.tan() - gs.alpha_w;
    let rhs = a.tan() - a + 2.0 * a.tan() * 0.4 / 60.0;
    assert!((lhs - rhs).abs() < 1e-14);
    assert!((gs.a_w * gs.alpha_w.cos() - 90e-3 * a.cos()).abs() < 1e-12);
}

#[test]
fn impossible_geometry_is_rejected_with_the_reason() {
    let mk = |z1, z2, x1, kind| geometry(kind, z1, z2, x1, 0.0);
    let e = mk(12, 40, 0.0, PairKind::External).unwrap_err().to_string();
    assert!(e.contains("undercut") && e.contains("short by"), "{e}");
    assert!(mk(12, 40, 0.4, PairKind::External).is_ok());
    let e = mk(30, 36, 0.0, PairKind::Internal).unwrap_err().to_string();
    assert!(e.contains("interference"), "{e}");
    let mut s = spec_40_40();
    s.face_width_mm = -1.0;
    assert!(s.build().unwrap_err().to_string().contains("face_width_mm"));
    let mut s = spec_40_40();
    s.poisson = 0.7;
    assert!(s.build().unwrap_err().to_string().contains("poisson"));
}

#[test]
fn mesh_stiffness_lies_in_the_iso_6336_range() {
    // ISO 6336-1 method B for solid steel spur gears: single-pair stiffness c' ~ 14 N/(mm um)
    // (c'_th = 1/q' = 17.4 for 40/40 times C_M = 0.8) and mesh stiffness
    // c_gamma = c' (0.75 eps + 0.25) ~ 21 N/(mm um). Potential-energy models fall within about
    // +-35% of these (e.g. Liang, Zuo & Pandey, Mech. Mach. Theory 76 (2014) 20).
    let m = spec_40_40().build().unwrap();
    let b_mm = 20.0;
    // N/m per mm of face width -> N/(mm um)
    let single_max = m
        .rows
        .iter()
        .filter(|r| r.single)
        .map(|r| r.k_mesh)
        .fold(0.0, f64::max)
        / b_mm
        / 1e6;
    let c_gamma = m.k_av / b_mm / 1e6;
    assert!(
        single_max > 14.0 * 0.65 && single_max < 14.0 * 1.35,
        "c' = {single_max} N/(mm um)"
    );
    assert!(
        c_gamma > 21.0 * 0.65 && c_gamma < 21.0 * 1.35,
        "c_gamma = {c_gamma} N/(mm um)"
    );
}

#[test]
fn stiffness_continuous_inside_zones_and_jumping_at_borders() {
    let m = spec_40_40().build().unwrap();
    let rows = &m.rows;
    let mut jumps = 0;
    for w in rows.windows(2) {
        let dk = (w[1].k_mesh - w[0].k_mesh).abs() / m.k_av;
        if w[1].position == w[0].position {
            // a zone border: stored from both sides
            if dk > 0.2 {
                jumps += 1;
            }
        } else {
            assert!(
                dk < 0.02,
                "discontinuity inside a zone at {}: {dk}",
                w[0].position
            );
        }
    }
    assert!(jumps >= 1, "the double/single border must jump");
    // the double zone is stiffer than the single zone
    let dbl = rows
        .iter()
        .filter(|r| !r.single)
        .map(|r| r.k_mesh)
        .fold(f64::INFINITY, f64::min);
    let sgl = rows
        .iter()
        .filter(|r| r.single)
        .map(|r| r.k_mesh)
        .fold(0.0, f64::max);
    assert!(dbl > sgl);
}

#[test]
fn load_shares_sum_to_one_and_friction_behaves() {
    for sharing in [LoadSharing::Stiffness, LoadSharing::Linear] {
        let mut s = spec_40_40();
        s.load_sharing = sharing;
        let m = s.build().unwrap();
        for r in &m.rows {
            assert!((r.share1 + r.share2 - 1.0).abs() < 1e-12);
            if r.single {
                assert_eq!(r.share2, 0.0);
            }
        }
    }
    // mu = 0: h = 1 everywhere
    let mut s = spec_40_40();
    s.mu = 0.0;
    let m = s.build().unwrap();
    assert!(m.rows.iter().all(|r| r.h_drive == 1.0 && r.h_back == 1.0));
    // the sliding speed vanishes at the pitch point: S_p/S_g = omega_g/omega_p = z1/z2 there
    let g = m.geom;
    let (sp, sg) = g.friction_arms(g.s_p);
    assert!((sp / sg - g.z1 as f64 / g.z2 as f64).abs() < 1e-12);
    assert_eq!(g.sliding_direction(g.s_p - 1e-9), -1.0);
    assert_eq!(g.sliding_direction(g.s_p + 1e-9), 1.0);
    // in the single zone, friction opposes the pinion in recess (h > 1) and helps in approach
    let m = spec_40_40().build().unwrap();
    let single: Vec<_> = m.rows.iter().filter(|r| r.single).collect();
    assert!(single.first().unwrap().h_drive < 1.0 && single.last().unwrap().h_drive > 1.0);
}

#[test]
fn breakage_shortens_contact_and_never_stiffens() {
    let healthy = spec_40_40().build().unwrap();
    let mut s = spec_40_40();
    s.breakage = Some(BreakageSpec {
        removed_height_mm: Some(1.0),
        tip_radius_mm: None,
        broken_cycle: 3,
    });
    let broken = s.build().unwrap();
    let eb = broken.eps_b.unwrap();
    assert!(eb < broken.geom.eps);
    assert_eq!(broken.cycles, 40);
    // compare the dimensionless mesh stiffness at equal positions (same k_av: healthy cycles)
    assert!((broken.k_av - healthy.k_av).abs() < 1e-9 * healthy.k_av);
    let mut ph = geardyn_model::presets::breakage();
    ph.friction = Default::default(); // friction comes from the pair
    let mut pb = ph.clone();
    healthy.apply(&mut ph);
    broken.apply(&mut pb);
    ph.breakage = None;
    let (mh, mb) = (
        geardyn_model::MeshModel::new(&ph).unwrap(),
        geardyn_model::MeshModel::new(&pb).unwrap(),
    );
    let mut lower = 0;
    for i in 0..40 * 200 {
        let u = (i as f64 + 0.37) / 200.0;
        let (kh, kb) = (mh.stiffness_at(u.fract()), mb.stiffness_at(u));
        // (1e-6: the broken cycle is sampled on its own grid; linear interpolation differs by less)
        assert!(
            kb <= kh * (1.0 + 1e-6),
            "broken stiffer at {u}: {kb} > {kh}"
        );
        if kb < kh * 0.999 {
            lower += 1;
            assert!(u > 3.0 && u < 4.0, "only the broken cycle may change: {u}");
        }
    }
    assert!(lower > 0);
    // zone II of the broken cycle carries a single pair
    let zone2: Vec<_> = broken.pieces.iter().filter(|p| p.zone_ii).collect();
    assert_eq!(zone2.len(), 1);
    assert!((zone2[0].start - (3.0 + eb - 1.0)).abs() < 1e-12);
}

#[test]
fn normalisation_round_trips_and_matches_hand_values() {
    let mut s = spec_40_40();
    s.operating = Some(OperatingPoint {
        speed_rpm: 1500.0,
        torque_nm: 200.0,
        error_amplitude_um: 5.0,
        half_backlash_um: 10.0,
    });
    let m = s.build().unwrap();
    // m_e from the inertias, for equal gears: I / (2 rb^2)
    assert!((m.m_e - m.i_p / (2.0 * m.geom.rb1 * m.geom.rb1)).abs() < 1e-12 * m.m_e);
    // solid disk of the pitch radius with a bore of half of it: I = rho B pi (r^4 - r_i^4)/2
    let (r, ri) = (60e-3f64, 30e-3f64);
    assert!((m.i_p - 7850.0 * 0.02 * PI * (r.powi(4) - ri.powi(4)) / 2.0).abs() < 1e-12);
    let d = m.to_dimensionless(&s.operating.unwrap());
    assert!((d.omega - 40.0 * 1500.0 * 2.0 * PI / 60.0 / (m.k_av / m.m_e).sqrt()).abs() < 1e-12);
    assert!((d.d - 1.0).abs() < 1e-12 && (d.xi - 0.5).abs() < 1e-12);
    let back = m.to_physical(&d);
    assert!((back.speed_rpm - 1500.0).abs() < 1e-9 && (back.torque_nm - 200.0).abs() < 1e-9);
    // the model built from it is consistent
    let mut p = geardyn_model::presets::breakage();
    p.friction = Default::default(); // friction comes from the pair
    m.apply(&mut p);
    let mm = geardyn_model::MeshModel::new(&p).unwrap();
    assert!((p.omega - d.omega).abs() < 1e-15);
    // mean of k/k_av over the healthy cycle is 1
    let mean: f64 = (0..4000)
        .map(|i| mm.stiffness_at((i as f64 + 0.5) / 4000.0))
        .sum::<f64>()
        / 4000.0;
    assert!((mean - 1.0).abs() < 1e-3, "{mean}");
}

#[test]
fn internal_pair_builds_and_is_stiffer_per_pair_than_external() {
    let mut s = spec_40_40();
    s.kind = PairKind::Internal;
    s.z1 = 30;
    s.z2 = 70;
    s.face_width_mm = 25.0;
    s.youngs_modulus_gpa = 210.0;
    let m = s.build().unwrap();
    assert!(m.geom.eps > 1.9 && m.geom.eps < 2.0);
    // the concave ring flank and its thick-rooted teeth make the internal mesh stiffer than an
    // external 30/30 pair of the same module and width
    let mut e = s.clone();
    e.kind = PairKind::External;
    e.z2 = 30;
    let me = e.build().unwrap();
    let stiffest_single = |rows: &[geardyn_physics::pair::StiffnessRow]| {
        rows.iter()
            .filter(|r| r.single)
            .map(|r| r.k_mesh)
            .fold(0.0, f64::max)
    };
    let (single_i, single_e) = (stiffest_single(&m.rows), stiffest_single(&me.rows));
    assert!(single_i > single_e, "{single_i} vs {single_e}");
}

#[test]
fn friction_factor_magnitude_matches_hand_value() {
    // equal gears: g = m_e R_b (S_p + S_g)/I = N1N2/(2 R_b) * 2 = tan(alpha_w); in the single
    // zone h = 1 -+ mu tan(alpha_w)
    let m = spec_40_40().build().unwrap();
    let expect = 0.15 * m.geom.alpha_w.tan();
    for r in m.rows.iter().filter(|r| r.single) {
        assert!(
            ((r.h_drive - 1.0).abs() - expect).abs() < 1e-12,
            "{}",
            r.h_drive
        );
    }
}

#[test]
fn prescribed_mean_stiffness_scales_the_tables() {
    let mut s = spec_40_40();
    s.mean_stiffness_n_per_m = Some(4e8);
    let m = s.build().unwrap();
    assert!((m.k_av - 4e8).abs() < 1.0);
    let n = m.rows.len() as f64;
    // rows of one healthy cycle, trapezoid-free mean close to k_av
    let mean = m.rows.iter().map(|r| r.k_mesh).sum::<f64>() / n;
    assert!((mean / 4e8 - 1.0).abs() < 0.02, "{mean}");
}

fn internal_spec() -> PairSpec {
    let mut s = geardyn_physics::presets::internal();
    s.mean_stiffness_n_per_m = None;
    s
}

#[test]
fn thermal_and_nonlinear_hertz_lower_the_stiffness_and_vanish_in_the_limit() {
    // seed B: both terms lower the mesh stiffness; with no temperature rise and the linear Hertz
    // law the elastic potential-energy stiffness is recovered exactly
    let full = internal_spec().build().unwrap();
    let mut elastic = internal_spec();
    elastic.hertz = HertzModel::Linear;
    elastic.thermal = None;
    let e = elastic.build().unwrap();
    let mut zero_dt = internal_spec();
    zero_dt.hertz = HertzModel::Linear;
    zero_dt.thermal.as_mut().unwrap().temperature_rise_k = 0.0;
    let z = zero_dt.build().unwrap();
    for (a, b) in e.rows.iter().zip(&z.rows) {
        assert_eq!(a.k_mesh, b.k_mesh);
    }
    let mut only_hertz = internal_spec();
    only_hertz.thermal = None;
    let h = only_hertz.build().unwrap();
    assert!(
        h.k_av < e.k_av && full.k_av < h.k_av,
        "elastic {} > nonlinear Hertz {} > + thermal {}",
        e.k_av,
        h.k_av,
        full.k_av
    );
}

#[test]
fn lubrication_gives_a_friction_coefficient_per_pair_and_backlash_grows_in_the_single_zone() {
    let m = internal_spec().build().unwrap();
    for r in &m.rows {
        assert!(r.mu1 >= 0.0 && r.mu1 <= 0.1 + 1e-12, "{}", r.mu1);
        assert!(r.film1 > 0.0 && r.lambda1 > 0.0);
    }
    // near the pitch point sliding vanishes: the EHL coefficient drops there
    let g = m.geom;
    let near = m
        .rows
        .iter()
        .flat_map(|r| {
            let s0 = g.s_a + r.position * g.pb;
            [(s0, r.mu1), (s0 + g.pb, r.mu2)]
        })
        .filter(|(s, _)| (s - g.s_p).abs() < 0.01 * g.pb)
        .map(|(_, mu)| mu)
        .fold(f64::INFINITY, f64::min);
    let far = m.rows.iter().map(|r| r.mu1).fold(0.0, f64::max);
    assert!(near < 0.3 * far, "{near} vs {far}");
    // D_s > D_d comes out of the load-deformation term (the single zone is softer)
    let (dd, ds) = m.backlash.unwrap();
    assert!(ds > dd, "{ds} vs {dd}");
    // more temperature: less backlash
    let mut hot = internal_spec();
    hot.thermal.as_mut().unwrap().temperature_rise_k = 60.0;
    assert!(hot.build().unwrap().backlash.unwrap().0 < dd);
    // bad input is named
    let mut bad = internal_spec();
    bad.lubrication.as_mut().unwrap().viscosity_mpas = -2.0;
    assert!(bad
        .build()
        .unwrap_err()
        .to_string()
        .contains("viscosity_mpas"));
    let mut bad = internal_spec();
    bad.operating = None;
    assert!(bad.build().unwrap_err().to_string().contains("operating"));
}

#[test]
fn physically_absurd_pairs_are_refused_with_the_field_range_and_unit() {
    // a face width of 1e-300 mm gave m_e = 0, omega_n = inf and "inf rpm"
    type Spoil = fn(&mut PairSpec);
    let cases: [(&str, Spoil); 3] = [
        ("face_width_mm", |s| s.face_width_mm = 1e-300),
        ("youngs_modulus_gpa", |s| s.youngs_modulus_gpa = 1e-300),
        ("density_kg_m3", |s| s.density_kg_m3 = 1e9),
    ];
    for (field, set) in cases {
        let mut s = geardyn_physics::presets::breakage();
        set(&mut s);
        let e = s.build().unwrap_err().to_string();
        assert!(e.contains(field) && e.contains('['), "{field}: {e}");
    }
    // the presets themselves are inside the ranges
    assert!(geardyn_physics::presets::breakage().build().is_ok());
    assert!(geardyn_physics::presets::internal().build().is_ok());
}

/// The sliding direction flips at the pitch point (`lambda` of docs/model.md): the
/// friction factor jumps there by `2 mu g L`, so the pitch point must be a piece border (a time
/// breakpoint the integrator steps onto) and every piece's table must be continuous. The jump
/// had been sampled across one table interval: RK4 at 256 steps per mesh cycle then erred by
/// 1e-3 per revolution on the broken pair and a period-3 orbit existed only in the tables.
#[test]
fn friction_jumps_only_at_piece_borders_and_the_pitch_point_is_one() {
    let mut broken = geardyn_physics::presets::breakage();
    broken.samples_per_cycle = 512;
    for spec in [spec_40_40(), broken] {
        let m = spec.build().unwrap();
        let g = &m.geom;
        let pitch = (g.s_p - g.s_a) / g.pb;
        assert!(
            pitch > g.eps - 1.0 && pitch < 1.0,
            "pitch point in the single zone"
        );
        for c in 0..m.cycles {
            let at = c as f64 + pitch;
            let border = m
                .pieces
                .windows(2)
                .find(|w| (w[0].end - at).abs() < 1e-9 && (w[1].start - at).abs() < 1e-9)
                .unwrap_or_else(|| panic!("no piece border at the pitch point {at}"));
            // the jump: lambda flips from -1 to +1 on the single pair (load share 1)
            let before = *border[0].h_drive.last().unwrap();
            let after = border[1].h_drive[0];
            let arm = {
                let (sp, sg) = g.friction_arms(g.s_p);
                m.m_e * (g.rb1 * sp / m.i_p + g.rb2 * sg / m.i_g)
            };
            let mu = spec.mu;
            assert!(
                ((after - before) - 2.0 * mu * arm).abs() < 1e-9,
                "jump {} vs 2 mu g = {}",
                after - before,
                2.0 * mu * arm
            );
        }
        for p in &m.pieces {
            for w in p.h_drive.windows(2) {
                // within a piece one sample interval (1/512 cycle) changes h by far less than
                // the pitch jump (0.11 here)
                assert!(
                    (w[1] - w[0]).abs() < 0.01,
                    "{w:?} in [{}, {}]",
                    p.start,
                    p.end
                );
            }
        }
    }
}
