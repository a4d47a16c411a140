//! The affine step of the lockstep lanes (`MeshLanes` with a linear, bilateral, frictionless
//! contact law): each lane's RK4 step as `y1 = P y0 + q_e + s q_o` from tables built per lane.
//! Checked against the second method of the same crate, the RK4 stages evaluated lane by lane
//! (`MeshLanes::exact`, itself equal to the scalar integrator's RK4 path to the bit), in every
//! contact state and at every step phase of a harmonic and of a piecewise (zoned, broken)
//! stiffness.

// lane loops over several arrays read clearer with an index
#![allow(clippy::needless_range_loop)]

use geardyn_model::mesh_lanes::AffineTables;
use geardyn_model::{
    presets, ContactLaw, ContactState, MeshLaneBlock, MeshLanes, MeshMode, MeshModel,
};
use geardyn_solvers::ensemble::{At, Lockstep, Soa, Stage, StepStart};

const L: usize = 8;

fn mode(contact: ContactState) -> MeshMode {
    MeshMode {
        period: 0,
        seg: 0,
        contact,
        chi: 0.0,
    }
}

/// The lockstep step of `t` at phase `j` of the grid of step `h` from `(y0, f0)` (every lane at
/// grid point `j`): the lanes that take it, the end states and the end fields.
fn step_at(
    t: &MeshLanes,
    ln: &MeshLaneBlock<L>,
    work: &AffineTables<L>,
    j: usize,
    h: f64,
    y0: &Soa<2, L>,
    f0: &Soa<2, L>,
) -> (u32, Soa<2, L>, Soa<2, L>) {
    let (t0, t1, grid) = ([j as f64 * h; L], [(j + 1) as f64 * h; L], [j as f64; L]);
    let s = StepStart {
        j,
        t0: &t0,
        t1: &t1,
        grid: &grid,
        y0,
        f0,
    };
    let (mut y1, mut f1) = ([[0.0; L]; 2], [[0.0; L]; 2]);
    let mask = Lockstep::<2, L>::step(t, &s, ln, work, &mut y1, &mut f1);
    (mask, y1, f1)
}

/// Largest deviation of the affine step from the RK4 stages over every phase of `m`'s table
/// (states spread over `[-2, 2] x [-1, 1]`, lanes in drive contact, separated and back contact),
/// relative to `1 + |value|`; and the number of lanes whose no-event verdict differs.
fn deviation(m: &MeshModel, n: u32) -> (f64, usize) {
    let affine = MeshLanes::new(m, n, 0.0);
    assert!(affine.is_affine());
    let exact = affine.clone().exact();
    assert!(!exact.is_affine());
    let h = m.mesh_cycle_time() / n as f64;
    let states = [
        ContactState::Drive,
        ContactState::Separated,
        ContactState::Back,
    ];
    let mut la = <MeshLanes as Lockstep<2, L>>::idle_lanes(&affine);
    let mut le = la;
    let mut wa = <MeshLanes as Lockstep<2, L>>::new_work(&affine);
    let mut we = <MeshLanes as Lockstep<2, L>>::new_work(&exact);
    for l in 0..L {
        let md = mode(states[l % 3]);
        assert!(Lockstep::<2, L>::set_lane(
            &affine, &mut la, &mut wa, l, m, &md, h
        ));
        assert!(Lockstep::<2, L>::set_lane(
            &exact, &mut le, &mut we, l, m, &md, h
        ));
    }
    let steps = <MeshLanes as Lockstep<2, L>>::steps_per_period(&affine);
    let (mut worst, mut verdicts) = (0.0f64, 0);
    for j in 0..steps {
        let t0 = [j as f64 * h; L];
        let grid = [j as f64; L];
        let mut y0 = [[0.0; L]; 2];
        for l in 0..L {
            // a deterministic spread of states, different at every phase
            let u = ((j * L + l) as f64 * 0.618_033_988_749_895).fract();
            let v = ((j * L + l) as f64 * 0.414_213_562_373_095).fract();
            y0[0][l] = -2.0 + 4.0 * u;
            y0[1][l] = -1.0 + 2.0 * v;
        }
        let at = At { t: t0, grid };
        let mut f0 = [[0.0; L]; 2];
        Lockstep::<2, L>::rhs(&exact, j, Stage::Start, &at, &le, &y0, &mut f0);
        let (ma, ya, fa) = step_at(&affine, &la, &wa, j, h, &y0, &f0);
        let (me, ye, fe) = step_at(&exact, &le, &we, j, h, &y0, &f0);
        verdicts += (ma ^ me).count_ones() as usize;
        for i in 0..2 {
            for l in 0..L {
                for (a, e) in [(ya[i][l], ye[i][l]), (fa[i][l], fe[i][l])] {
                    worst = worst.max((a - e).abs() / (1.0 + e.abs()));
                }
            }
        }
    }
    (worst, verdicts)
}

#[test]
fn affine_step_equals_the_rk4_stages_on_a_harmonic_stiffness() {
    for w in [0.5, 1.3, 2.0] {
        let mut p = presets::classic();
        p.omega = w;
        let m = MeshModel::new(&p).unwrap();
        let (dev, verdicts) = deviation(&m, 512);
        eprintln!("classic omega {w}: {dev:e}, {verdicts} verdicts differ");
        assert!(dev < 1e-14, "omega {w}: {dev:e}");
        assert_eq!(verdicts, 0);
    }
}

#[test]
fn affine_step_equals_the_rk4_stages_on_a_broken_pair_without_friction() {
    // zones, a broken cycle and 40 cycles per period: 16 steps per cycle keeps the table small
    let mut p = presets::breakage();
    p.friction.mu = 0.0;
    p.contact = ContactLaw::Linear;
    let m = MeshModel::new(&p).unwrap();
    let (dev, verdicts) = deviation(&m, 16);
    eprintln!("breakage (mu = 0): {dev:e}, {verdicts} verdicts differ");
    assert!(dev < 1e-13, "{dev:e}");
    assert!(verdicts <= 2, "{verdicts}");
}

#[test]
fn the_affine_map_is_taken_only_where_it_is_exact() {
    let table = |p: &geardyn_model::ModelParams, n: u32| {
        MeshLanes::new(&MeshModel::new(p).unwrap(), n, 0.0).is_affine()
    };
    assert!(table(&presets::classic(), 512));
    // nonlinear law, friction (different flank factors), one-sided force, a table too large
    let mut p = presets::classic();
    p.contact = ContactLaw::Power { exponent: 1.5 };
    assert!(!table(&p, 512));
    let mut p = presets::breakage();
    p.contact = ContactLaw::Linear;
    assert!(!table(&p, 16));
    let mut p = presets::classic();
    p.unilateral = true;
    assert!(!table(&p, 512));
    assert!(!table(&presets::classic(), 4096));
}

/// The affine step tests finiteness once, on the end acceleration (an infinite or NaN `x` or
/// `x'` makes it infinite or NaN in every contact state, `0 * inf` included): no lane with a
/// non-finite start state, nor one whose step overflows, is ever taken in lockstep.
#[test]
fn the_affine_step_never_takes_a_non_finite_lane() {
    let m = MeshModel::new(&presets::classic()).unwrap();
    let n = 512;
    let t = MeshLanes::new(&m, n, 0.0);
    let h = m.mesh_cycle_time() / n as f64;
    let states = [
        ContactState::Drive,
        ContactState::Separated,
        ContactState::Back,
    ];
    let bad = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 1e308, -1e308];
    for st in states {
        let mut la = <MeshLanes as Lockstep<2, L>>::idle_lanes(&t);
        let mut wa = <MeshLanes as Lockstep<2, L>>::new_work(&t);
        for l in 0..L {
            assert!(Lockstep::<2, L>::set_lane(
                &t,
                &mut la,
                &mut wa,
                l,
                &m,
                &mode(st),
                h
            ));
        }
        for (k, &b) in bad.iter().enumerate() {
            for comp in 0..2 {
                let mut y0 = [[0.0; L]; 2];
                let x = match st {
                    ContactState::Drive => 1.5,
                    ContactState::Back => -1.5,
                    _ => 0.0,
                };
                y0[0] = [x; L];
                y0[comp][k] = b;
                let f0 = [[0.0; L]; 2];
                let (mask, y1, f1) = step_at(&t, &la, &wa, 37, h, &y0, &f0);
                let finite = y1[0][k].is_finite() && y1[1][k].is_finite() && f1[1][k].is_finite();
                assert!(
                    mask & (1 << k) == 0 || finite,
                    "{st:?}: component {comp} = {b:e} taken in lockstep to {:?}",
                    [y1[0][k], y1[1][k], f1[1][k]]
                );
                if !b.is_finite() {
                    assert_eq!(mask & (1 << k), 0, "{st:?}: {b:e} taken in lockstep");
                }
                // the finite neighbours still step
                assert_ne!(mask & !(1 << k) & ((1 << L) - 1), 0, "{st:?}");
            }
        }
    }
}
