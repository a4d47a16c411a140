//! `geardyn lyapunov` of a gear train: the top Lyapunov exponent by the variational equation
//! with saltation (the exponent a train's decisions use), after the transient from the static
//! state, in runs of doubling length until converged (as for the pair: docs/analyses.md).

use crate::sweep::SimArgs;
use crate::train::{check_work, sim_options, with_model, TrainRun};
use anyhow::{bail, Result};
use geardyn_analysis::lyapunov::{LyapunovOptions, TangentSpace};
use geardyn_analysis::simulate::{simulate, SimOptions};
use geardyn_analysis::tle_convergence::{converge_by_doubling, Convergence, Round};
use geardyn_model::GearSystem;
use geardyn_train::dynamics::{elastic_dof, TrainModel};

/// The exponent of train `t` (`method`: `variational` or `both`, the default; `periods`: a run
/// of exactly that many periods instead of the doubling up to `max_periods`).
pub fn run(
    t: &TrainRun,
    sim: &SimArgs,
    method: &str,
    periods: Option<u64>,
    max_periods: u64,
) -> Result<()> {
    match method {
        "variational" | "both" => {}
        "two-trajectory" => bail!("--method two-trajectory: a train's exponent is computed by the variational equation with saltation (--method variational)"),
        m => bail!("--method {m}: expected variational, two-trajectory or both"),
    }
    let (opts, cap) = sim_options(sim)?;
    let conv = Convergence {
        max_periods: periods.unwrap_or(max_periods).max(1),
        start_periods: periods.unwrap_or(Convergence::default().start_periods),
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
        tle_of(t, &m, &opts, &conv, periods.is_some())
    })
}

fn tle_of<const N: usize>(
    t: &TrainRun,
    m: &TrainModel<N>,
    opts: &SimOptions,
    conv: &Convergence,
    fixed: bool,
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
    if fixed {
        println!(
            "variational TLE over {} transient + {} periods ...",
            opts.transient_periods, conv.max_periods
        );
    } else {
        println!(
            "variational TLE over {} transient periods from the static state, then runs of doubling length until converged (each printed when done):",
            opts.transient_periods
        );
    }
    let scheme = opts.method.scheme(m);
    let c = converge_by_doubling(
        conv,
        |n| {
            let lo = LyapunovOptions {
                period: m.excitation_period(),
                transient_periods: 0,
                periods: n,
                d0: 1e-6,
            };
            m.tle_variational_with(scheme, t0, y0, r.final_memory, &lo, true)
        },
        |r: &Round| {
            if !fixed {
                println!(
                    "  {:>7} periods: TLE {:.6} (at half the run {:.6}), block stderr {:.2e}",
                    r.periods, r.tle, r.half, r.stderr
                );
            }
        },
    )?;
    if !fixed {
        if c.converged {
            println!(
                "converged: |TLE(N) - TLE(N/2)| and the standard error are below {:.1e}",
                c.tol
            );
        } else {
            println!(
                "WARNING: not converged to {:.1e} within --max-periods {} (pass a larger cap, or --periods N for a fixed length)",
                c.tol, conv.max_periods
            );
        }
    }
    let spread = if c.result.spread.is_finite() {
        format!("+- {:.6}", c.result.spread)
    } else {
        "(no standard error: it needs at least 2 periods)".into()
    };
    println!(
        "TLE (variational, saltation): {:.6} {} per unit tau over {} periods (a train's dimensionless time: tau = omega_ref t, omega_ref = {:.1} rad/s)",
        c.result.tle,
        spread,
        c.rounds.last().map_or(0, |r| r.periods),
        m.omega_ref()
    );
    Ok(())
}
