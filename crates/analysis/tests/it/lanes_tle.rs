//! Top Lyapunov exponents in lockstep lanes against the scalar variational integration.

use geardyn_analysis::lanes_tle::{tle_lanes, tle_lanes_with};
use geardyn_analysis::lyapunov::{tle_variational, LyapunovOptions};
use geardyn_analysis::simulate::{simulate, Method, SimOptions};
use geardyn_model::{presets, MeshModel};
use geardyn_solvers::Scheme;

/// The models of `preset` at `omegas`.
fn models_at(preset: fn() -> geardyn_model::ModelParams, omegas: &[f64]) -> Vec<MeshModel> {
    omegas
        .iter()
        .map(|&w| {
            let mut p = preset();
            p.omega = w;
            MeshModel::new(&p).unwrap()
        })
        .collect()
}

/// Each model's state after `transient` periods of RK4 with `n` steps per mesh cycle.
fn after_transient(
    models: &[MeshModel],
    n: u32,
    transient: u64,
) -> Vec<(&MeshModel, f64, [f64; 2], f64)> {
    let sim = SimOptions {
        method: Method::Rk4 { steps_per_cycle: n },
        transient_periods: transient,
        record_periods: 1,
        ..Default::default()
    };
    models
        .iter()
        .map(|m| {
            let r = simulate(m, [0.0, 0.0], &sim).unwrap();
            (m, r.final_state.0, r.final_state.1, r.final_memory)
        })
        .collect()
}

/// The scalar variational exponent from `(t, y)` over `periods`, RK4 with `n` steps per cycle.
fn scalar_tle(
    m: &MeshModel,
    t: f64,
    y: [f64; 2],
    n: u32,
    periods: u64,
) -> geardyn_analysis::lyapunov::LyapunovResult {
    let lo = LyapunovOptions {
        period: m.excitation_period(),
        transient_periods: 0,
        periods,
        d0: 1e-6,
    };
    let h = m.mesh_cycle_time() / n as f64;
    tle_variational::<_, 2, 5>(m.clone(), Scheme::Rk4 { h }, t, y, &lo).unwrap()
}

/// C1 (the classic backlash oscillator) at periodic and chaotic values of omega, each exponent
/// started from the end of a transient: on a periodic orbit the lanes give the scalar RK4
/// exponent to rounding; on a chaotic one (the lanes' and the scalar trajectory part after a
/// few periods, as any two computations do) the same positive exponent within its spread.
/// One lane and sixteen give the same bits.
#[test]
fn c1_exponents_equal_the_scalar_variational_integration() {
    let n = 256;
    let periods = 150;
    let omegas = [0.7, 0.9, 1.3, 1.8, 2.3];
    let models = models_at(presets::classic, &omegas);
    let starts = after_transient(&models, n, 200);
    let lanes = tle_lanes(&starts, periods, n, 0.0);
    let one = tle_lanes_with::<1>(&starts, periods, n, 0.0);
    let mut chaotic = 0;
    let mut periodic = 0;
    for (i, &(m, t, y, _)) in starts.iter().enumerate() {
        let a = lanes[i].as_ref().unwrap();
        let b = one[i].as_ref().unwrap();
        assert_eq!(a.tle.to_bits(), b.tle.to_bits(), "omega {}", omegas[i]);
        let s = scalar_tle(m, t, y, n, periods);
        eprintln!(
            "omega {}: lanes {} ± {}, scalar {} ± {}",
            omegas[i], a.tle, a.spread, s.tle, s.spread
        );
        if s.tle < -1e-3 {
            periodic += 1;
            assert!(
                (a.tle - s.tle).abs() < 1e-9 * s.tle.abs().max(1.0),
                "omega {}",
                omegas[i]
            );
        } else {
            chaotic += 1;
            assert!(
                a.tle > 0.0 && (a.tle - s.tle).abs() < 4.0 * (a.spread + s.spread),
                "omega {}",
                omegas[i]
            );
        }
    }
    assert!(
        periodic >= 2 && chaotic >= 1,
        "{periodic} periodic, {chaotic} chaotic"
    );
}

/// A law the affine table does not take (the breakage preset: friction makes the drive and back
/// flanks' factors differ), so the lanes compose the RK4 stages of state and tangent: on its
/// periodic orbits the exponent equals the scalar variational integration to rounding.
#[test]
fn composed_lanes_equal_the_scalar_variational_integration() {
    let n = 256;
    let periods = 60;
    let omegas = [0.9, 0.95];
    let models = models_at(presets::breakage, &omegas);
    assert!(models
        .iter()
        .all(geardyn_analysis::lanes::lanes_cover_contact));
    let starts = after_transient(&models, n, 100);
    let lanes = tle_lanes(&starts, periods, n, 0.0);
    for (i, &(m, t, y, _)) in starts.iter().enumerate() {
        let a = lanes[i].as_ref().unwrap();
        let s = scalar_tle(m, t, y, n, periods);
        eprintln!("omega {}: lanes {}, scalar {}", omegas[i], a.tle, s.tle);
        assert!(s.tle < 0.0, "omega {}: a periodic value", omegas[i]);
        assert!(
            (a.tle - s.tle).abs() < 1e-9 * s.tle.abs().max(1.0),
            "omega {}: {} vs {}",
            omegas[i],
            a.tle,
            s.tle
        );
    }
}
