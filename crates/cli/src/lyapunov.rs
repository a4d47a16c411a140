//! `geardyn lyapunov`.

use crate::run_config::ConfigArgs;
use crate::sweep::SimArgs;
use crate::tle_text::{print_convergence, print_round};
use anyhow::Result;
use clap::Args;
use geardyn_analysis::lyapunov::LyapunovResult;
use geardyn_analysis::lyapunov_request::{LyapunovRequest, TleMethod};
use geardyn_exec::{execute, Each, LyapunovJob};

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
    #[arg(long, default_value = "both")]
    method: String,
    /// Largest run length (excitation periods) while converging; `--periods N` runs exactly N.
    #[arg(long, default_value_t = LyapunovRequest::default().max_periods)]
    max_periods: u64,
    /// Initial distance of the two-trajectory method.
    #[arg(long, default_value_t = LyapunovRequest::default().d0)]
    d0: f64,
}

pub fn run(a: LyapunovArgs) -> Result<()> {
    if let Some(t) = crate::train::from_args(&a.cfg)? {
        let periods = match a.sim.periods {
            Some(p) if p.is_finite() && p >= 1.0 && p.fract() == 0.0 => Some(p as u64),
            Some(p) => anyhow::bail!("--periods {p}: a whole number of excitation periods from 1"),
            None => None,
        };
        if a.d0 != LyapunovRequest::default().d0 {
            anyhow::bail!("--d0 is the two-trajectory method's: a train's exponent is variational");
        }
        // the pair's checks of the method and the lengths
        let req = LyapunovRequest {
            method: TleMethod::from_name(&a.method)?,
            periods,
            max_periods: a.max_periods,
            d0: a.d0,
        };
        req.check()?;
        return crate::train_lyapunov::run(&t, &a.sim, &req);
    }
    let (cfg, scenario) = a.sim.resolve(&a.cfg)?;
    let sim = cfg.sim_options()?;
    let req = LyapunovRequest {
        method: TleMethod::from_name(&a.method)?,
        periods: a.sim.periods.map(|_| sim.record_periods),
        max_periods: a.max_periods,
        d0: a.d0,
    };
    req.check()?;
    let model = scenario.model();
    let p = scenario.params();
    // this command writes no folder: what ran is printed in full
    println!(
        "integrated: {}: {}, contact {}, back side {}",
        a.cfg.source(),
        geardyn_io::describe::operating_point(&scenario),
        serde_json::to_string(&p.contact)?,
        serde_json::to_string(&p.back_side)?
    );
    match req.periods {
        None => println!(
            "variational TLE over {} transient periods, then runs of doubling length until converged (each printed when done):",
            sim.transient_periods
        ),
        Some(n) => println!(
            "{} TLE over {} transient + {n} periods ...",
            req.method.name(),
            sim.transient_periods
        ),
    }
    let y0 = [cfg.simulation.x0, cfg.simulation.v0];
    let job = LyapunovJob {
        model,
        sim: &sim,
        y0,
        request: &req,
    };
    let r = execute(&job, None, &Each(print_round))?;
    if let Some(c) = &r.convergence {
        print_convergence(c, a.max_periods);
    }
    if let Some(v) = &r.variational {
        print_variational(v, r.periods);
    }
    if let Some(t) = &r.two_trajectory {
        println!(
            "TLE (two-trajectory, d0 = {:e}, over {} transient + {} periods): {:.6} {} per unit tau",
            a.d0,
            sim.transient_periods,
            r.periods,
            t.tle,
            spread_text(t.spread)
        );
    }
    if let (true, Some(v), Some(t)) = (r.disagree(), &r.variational, &r.two_trajectory) {
        println!(
            "WARNING: the two methods disagree ({:.4} against {:.4}): see the notes below and docs/analyses.md, section \"Top Lyapunov exponent (TLE)\"",
            v.tle, t.tle
        );
        println!(
            "note: the two-trajectory exponent measures the integrator's noise where d0 is not far above it: with the adaptive integrator the two runs take different steps, and their difference carries an error of about rtol per step (a pair with many events per period, such as the broken pair, needs more than the default d0); rerun with --integrator rk4 (both runs on the same grid) or a larger --d0. It is also biased where the flow depends discontinuously on the state (the two runs on either side of an impact or a grazing contact). The classification uses the variational exponent"
        );
    }
    Ok(())
}
