//! Top Lyapunov exponents against published values and between the two independent methods.

use geardyn_analysis::lyapunov::{
    tle_two_trajectory, tle_variational, tle_variational_with, LyapunovOptions,
};
use geardyn_analysis::lyapunov::{LyapunovResult, Tangent};
use geardyn_model::reference::{ImpactOscillator, Lorenz};
use geardyn_model::{presets, MeshModel};
use geardyn_solvers::{HybridSystem, Scheme, Variational};

/// The exponent of `sys` from rest (DP5): variational with saltation, two trajectories, and
/// variational without saltation.
fn three_exponents<S>(sys: S, opts: &LyapunovOptions) -> [LyapunovResult; 3]
where
    S: Variational<2> + Clone,
    Tangent<S>: HybridSystem<5>,
{
    let (d, y0) = (Scheme::dopri_default(), [0.0, 0.0]);
    [
        tle_variational::<_, 2, 5>(sys.clone(), d, 0.0, y0, opts).unwrap(),
        tle_two_trajectory(sys.clone(), d, 0.0, y0, opts).unwrap(),
        tle_variational_with::<_, 2, 5>(sys, d, 0.0, y0, 0.0, opts, false).unwrap(),
    ]
}

#[test]
fn lorenz_matches_the_published_exponent() {
    // sigma = 10, rho = 28, beta = 8/3: lambda_1 = 0.9056 (Sprott, Chaos and Time-Series
    // Analysis, Oxford 2003, Table A.1; Wolf et al., Physica D 16 (1985) 285 give 0.90)
    // d0 must stay well above the integration error (rtol*|y| ~ 2e-8 here)
    let opts = LyapunovOptions {
        period: 1.0,
        transient_periods: 50,
        periods: 3000,
        d0: 1e-6,
    };
    let (d, y0) = (Scheme::dopri_default(), [1.0, 1.0, 1.0]);
    let r = tle_variational::<_, 3, 7>(Lorenz::default(), d, 0.0, y0, &opts).unwrap();
    assert!((r.tle - 0.9056).abs() < 0.03, "{} +- {}", r.tle, r.spread);
    let t = tle_two_trajectory(Lorenz::default(), d, 0.0, y0, &opts).unwrap();
    assert!((t.tle - 0.9056).abs() < 0.04, "two-trajectory {}", t.tle);
}

fn c1(omega: f64) -> MeshModel {
    let mut p = presets::classic();
    p.omega = omega;
    MeshModel::new(&p).unwrap()
}

fn c1_opts(m: &MeshModel, periods: u64) -> LyapunovOptions {
    LyapunovOptions {
        period: m.excitation_period(),
        transient_periods: 300,
        periods,
        d0: 1e-6,
    }
}

/// The exponent of C1 at `omega` from rest over `periods` periods (variational, DP5).
fn c1_variational(omega: f64, periods: u64) -> LyapunovResult {
    let m = c1(omega);
    let opts = c1_opts(&m, periods);
    tle_variational::<_, 2, 5>(m, Scheme::dopri_default(), 0.0, [0.0, 0.0], &opts).unwrap()
}

#[test]
fn c1_is_stable_at_0_8_and_chaotic_at_1_3() {
    let r = c1_variational(0.8, 200);
    assert!(r.tle < -0.01, "period-1 orbit: {}", r.tle);
    let r = c1_variational(1.3, 600);
    assert!(
        r.tle > 0.01 && r.tle > 4.0 * r.spread,
        "chaos: {} +- {}",
        r.tle,
        r.spread
    );
}

#[test]
fn methods_agree_on_c1() {
    // C1's damping acts only in contact: the field jumps by -c x' at every contact change.
    for omega in [0.8, 1.3] {
        let m = c1(omega);
        let opts = c1_opts(&m, 800);
        let var =
            tle_variational::<_, 2, 5>(m.clone(), Scheme::dopri_default(), 0.0, [0.0, 0.0], &opts)
                .unwrap();
        let two =
            tle_two_trajectory(m.clone(), Scheme::dopri_default(), 0.0, [0.0, 0.0], &opts).unwrap();
        let tol = 3.0 * (var.spread.max(two.spread)) + 0.005;
        assert!(
            (var.tle - two.tle).abs() < tol,
            "omega {omega}: variational {} vs two-trajectory {}",
            var.tle,
            two.tle
        );
    }
}

#[test]
fn saltation_is_needed_for_the_gear_impact_model() {
    // C1 with a rigid back stop (R = 0.7), F = 0.05, xi = 0.3, omega = 0.8: a period-1 orbit with
    // one back-side impact per period (label 1-1-1). The reset enters the exponent only through the
    // saltation matrix (det S = R^2 per impact, det R_y = -R).
    let mut p = presets::classic();
    p.omega = 0.8;
    p.load = 0.05;
    p.xi = 0.3;
    p.back_side = geardyn_model::BackSide::Impact(geardyn_model::ImpactLaw {
        restitution: 0.7,
        v_stick: 1e-6,
        k_c: 1.0,
    });
    let m = MeshModel::new(&p).unwrap();
    let opts = c1_opts(&m, 400);
    let [var, two, bare] = three_exponents(m, &opts);
    assert!(
        (var.tle - two.tle).abs() < 1e-3,
        "{} vs {}",
        var.tle,
        two.tle
    );
    assert!(var.tle < 0.0);
    assert!(
        (bare.tle - two.tle).abs() > 0.02,
        "without saltation {} vs {}",
        bare.tle,
        two.tle
    );
}

#[test]
fn impact_oscillator_exponent_from_saltation_matches_two_trajectories() {
    // forced impact oscillator on a period-1 impacting orbit: the restitution enters only through
    // the saltation matrix
    let sys = ImpactOscillator {
        zeta: 0.05,
        a: 1.0,
        omega: 1.5,
        gap: 0.2,
        r: 0.7,
    };
    let period = 2.0 * std::f64::consts::PI / 1.5;
    let opts = LyapunovOptions {
        period,
        transient_periods: 300,
        periods: 300,
        d0: 1e-9,
    };
    let [var, two, bare] = three_exponents(sys, &opts);
    assert!(
        (var.tle - two.tle).abs() < 0.01,
        "{} vs {}",
        var.tle,
        two.tle
    );
    assert!(
        (bare.tle - two.tle).abs() > 0.05,
        "without saltation {} vs {}",
        bare.tle,
        two.tle
    );
}
