//! `geardyn lyapunov` of a gear train: the top Lyapunov exponent by the variational equation
//! with saltation (the exponent a train's decisions use), after the transient from the static
//! state, in runs of doubling length until converged (as for the pair: docs/analyses.md).

use crate::sweep::SimArgs;
use crate::train::{check_work, sim_options, with_model, TrainRun};
use anyhow::{bail, Result};
use geardyn_analysis::lyapunov::{LyapunovOptions, TangentSpace};
use geardyn_analysis::lyapunov_request::{LyapunovRequest, TleMethod};
use geardyn_analysis::simulate::{simulate, SimOptions};
use geardyn_analysis::tle_convergence::{converge_by_doubling, Convergence};
use geardyn_model::GearSystem;
use geardyn_train::dynamics::{elastic_dof, TrainModel};

/// The exponent of train `t` as `req` asks (checked: its method, `periods` for a run of exactly
/// that many periods, else the doubling up to `max_periods`).
pub fn run(t: &TrainRun, sim: &SimArgs, req: &LyapunovRequest) -> Result<()> {
    if req.method == TleMethod::TwoTrajectory {
        bail!("--method two-trajectory: a train's exponent is computed by the variational equation with saltation (--method variational)");
    }
    let (opts, cap) = sim_options(sim)?;
    let conv = Convergence {
        max_periods: req.periods.unwrap_or(req.max_periods),
        ..Default::default()
    };
    with_model!(&t.spec, &t.op, |m| {
        // the transient and (at most) twice the longest run: the doubling's total
        let whole = SimOptions {
            record_periods: opts.transient_periods + 2 * conv.max_periods,
            transient_periods: 0,
            ..opts
        };
        check_work(&m, &whole, 1, cap)?;
        tle_of(t, &m, &opts, &conv, req.periods)
    })
}

fn tle_of<const N: usize>(
    t: &TrainRun,
    m: &TrainModel<N>,
    opts: &SimOptions,
    conv: &Convergence,
    fixed: Option<u64>,
) -> Result<()>
where
    TrainModel<N>: TangentSpace<N>,
{
    println!(
        "integrated: {} ({}), {} meshes, {} elastic degrees of freedom: omega = {}, F = {}, xi = {}, c = {}, D = {}, stiffness {}",
        t.spec.name,
        t.source,
        m.mesh_count(),
        elastic_dof(&t.spec),
        t.op.omega,
        t.op.load,
        t.op.xi,
        t.op.c,
        t.op.d,
        serde_json::to_string(&t.op.stiffness)?
    );
    let transient = SimOptions {
        record_periods: 0,
        trajectory: false,
        ..*opts
    };
    let r = simulate(m, m.static_state(), &transient)?;
    let (t0, y0) = r.final_state;
    if let Some(n) = fixed {
        println!(
            "variational TLE over {} transient + {n} periods ...",
            opts.transient_periods
        );
    } else {
        println!(
            "variational TLE over {} transient periods from the static state, then runs of doubling length until converged (each printed when done):",
            opts.transient_periods
        );
    }
    let scheme = opts.method.scheme(m);
    let run = |n: u64| {
        let lo = LyapunovOptions {
            period: m.excitation_period(),
            transient_periods: 0,
            periods: n,
            d0: 1e-6,
        };
        m.tle_variational_with(scheme, t0, y0, r.final_memory, &lo, true)
    };
    if let Some(n) = fixed {
        // exactly the periods asked for (the doubling starts at 20)
        let r = run(n)?;
        print_tle(m, r.tle, r.spread, n);
        return Ok(());
    }
    let c = converge_by_doubling(conv, run, crate::tle_text::print_round)?;
    crate::tle_text::print_convergence(&c, conv.max_periods);
    print_tle(
        m,
        c.result.tle,
        c.result.spread,
        c.rounds.last().map_or(0, |r| r.periods),
    );
    Ok(())
}

fn print_tle<const N: usize>(m: &TrainModel<N>, tle: f64, spread: f64, periods: u64) {
    let spread = if spread.is_finite() {
        format!("+- {spread:.6}")
    } else {
        "(no standard error: it needs at least 2 periods)".into()
    };
    println!(
        "TLE (variational, saltation): {tle:.6} {spread} per unit tau over {periods} periods (a train's dimensionless time: tau = omega_ref t, omega_ref = {:.1} rad/s)",
        m.omega_ref()
    );
}
