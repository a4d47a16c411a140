//! `geardyn lyapunov`.

use crate::run_config::ConfigArgs;
use crate::sweep::SimArgs;
use anyhow::Result;
use clap::Args;
use geardyn_analysis::lyapunov::{
    tle_two_trajectory, tle_variational, LyapunovOptions, LyapunovResult,
};
use geardyn_analysis::tle_convergence::{tle_converged, Convergence};

/// `+- spread`, or why there is none (one period: no blocks to compare).
fn spread_text(spread: f64) -> String {
    if spread.is_finite() {
        format!("+- {spread:.6}")
    } else {
        "(no standard error: it needs at least 2 periods)".to_string()
    }
}

fn print_variational(r: &LyapunovResult, periods: u64) {
    println!(
        "TLE (variational, saltation): {:.6} {} per unit tau over {} periods{}",
        r.tle,
        spread_text(r.spread),
        periods,
        if r.annihilated > 0 {
            format!(" ({} sticking intervals)", r.annihilated)
        } else {
            String::new()
        }
    );
}

/// Arguments of `geardyn lyapunov`.
#[derive(Args, Debug)]
pub struct LyapunovArgs {
    #[command(flatten)]
    cfg: ConfigArgs,
    #[command(flatten)]
    sim: SimArgs,
    /// variational (saltation matrices), two-trajectory, or both.
    #[arg(long, default_value = "both", value_parser = ["variational", "two-trajectory", "both"])]
    method: String,
    /// Largest run length (excitation periods) while converging; `--periods N` runs exactly N.
    #[arg(long, default_value_t = 25_600)]
    max_periods: u64,
    /// Initial distance of the two-trajectory method.
    #[arg(long, default_value_t = 1e-6)]
    d0: f64,
}

pub fn run(a: LyapunovArgs) -> Result<()> {
    let mut cfg = a.cfg.config()?;
    a.sim.apply(&mut cfg, &a.cfg.sets)?;
    let scenario = cfg.resolve()?;
    if !(a.d0 > 0.0 && a.d0 < 1e-2) {
        anyhow::bail!(
            "bad --d0 {}: allowed (0, 0.01)",
            geardyn_model::error::num(a.d0)
        );
    }
    let model = scenario.model().clone();
    let p = scenario.params();
    // this command writes no folder: what ran is printed in full
    println!(
        "integrated: {}: {}, contact {}, back side {}",
        a.cfg.source(),
        geardyn_io::describe::operating_point(&scenario),
        serde_json::to_string(&p.contact)?,
        serde_json::to_string(&p.back_side)?
    );
    let sim = cfg.sim_options()?;
    let mut opts = LyapunovOptions {
        period: model.excitation_period(),
        transient_periods: sim.transient_periods,
        periods: sim.record_periods,
        d0: a.d0,
    };
    let y0 = [cfg.simulation.x0, cfg.simulation.v0];
    let scheme = sim.method.scheme(&model);
    let t0 = sim.tau0;
    let mut variational = None;
    if a.sim.periods.is_none() {
        // no explicit length: run until converged (the two-trajectory check uses the same length)
        if !(20..=geardyn_analysis::simulate::MAX_PERIODS).contains(&a.max_periods) {
            anyhow::bail!(
                "bad --max-periods {}: allowed 20 ..= {}",
                a.max_periods,
                geardyn_analysis::simulate::MAX_PERIODS
            );
        }
        let conv = Convergence {
            max_periods: a.max_periods,
            ..Default::default()
        };
        println!(
            "variational TLE over {} transient periods, then runs of doubling length until converged (each printed when done):",
            opts.transient_periods
        );
        let c = tle_converged(model.clone(), scheme, t0, y0, &opts, &conv, |r| {
            println!(
                "  {:>7} periods: TLE {:.6} (at half the run {:.6}), block stderr {:.2e}",
                r.periods, r.tle, r.half, r.stderr
            );
        })?;
        opts.periods = c.rounds.last().map_or(opts.periods, |r| r.periods);
        if c.converged {
            println!(
                "converged: |TLE(N) - TLE(N/2)| and the standard error are below {:.1e}",
                c.tol
            );
        } else {
            println!(
                "WARNING: not converged to {:.1e} within --max-periods {} (pass a larger cap, or --periods N for a fixed length)",
                c.tol, a.max_periods
            );
        }
        if a.method != "two-trajectory" {
            print_variational(&c.result, opts.periods);
            variational = Some((c.result.tle, c.result.spread));
        }
    } else if a.method != "two-trajectory" {
        println!(
            "variational TLE over {} transient + {} periods ...",
            opts.transient_periods, opts.periods
        );
        let r = tle_variational::<_, 2, 5>(model.clone(), scheme, t0, y0, &opts)?;
        print_variational(&r, opts.periods);
        variational = Some((r.tle, r.spread));
    }
    let mut disagree = false;
    if a.method != "variational" {
        println!(
            "two-trajectory TLE over {} transient + {} periods ...",
            opts.transient_periods, opts.periods
        );
        let r = tle_two_trajectory(model, scheme, t0, y0, &opts)?;
        println!(
            "TLE (two-trajectory, d0 = {:e}): {:.6} {} per unit tau",
            a.d0,
            r.tle,
            spread_text(r.spread)
        );
        if let Some((v, sv)) = variational {
            // (a missing spread counts as none: f64::max drops the NaN)
            disagree = (v - r.tle).abs() > 3.0 * (sv.max(0.0) + r.spread.max(0.0)) + 1e-3;
            if disagree {
                println!(
                    "WARNING: the two methods disagree ({v:.4} against {:.4}): see the notes below and docs/analyses.md, section \"Top Lyapunov exponent (TLE)\"",
                    r.tle
                );
            }
        }
    }
    if disagree {
        println!(
            "note: the two-trajectory exponent measures the integrator's noise where d0 is not far above it: with the adaptive integrator the two runs take different steps, and their difference carries an error of about rtol per step (a pair with many events per period, such as the broken pair, needs more than the default d0); rerun with --integrator rk4 (both runs on the same grid) or a larger --d0. It is also biased where the flow depends discontinuously on the state (the two runs on either side of an impact or a grazing contact). The classification uses the variational exponent"
        );
    }
    Ok(())
}
