//! `geardyn lyapunov`.

use crate::run_config::ConfigArgs;
use crate::sweep::SimArgs;
use anyhow::Result;
use clap::Args;
use geardyn_analysis::lyapunov::{tle_two_trajectory, tle_variational, LyapunovOptions};

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
    /// Initial distance of the two-trajectory method.
    #[arg(long, default_value_t = 1e-6)]
    d0: f64,
}

pub fn run(a: LyapunovArgs) -> Result<()> {
    let mut cfg = a.cfg.config()?;
    a.sim.apply(&mut cfg)?;
    let scenario = cfg.resolve()?;
    if !(a.d0 > 0.0 && a.d0 < 1e-2) {
        anyhow::bail!("bad --d0 {}: allowed (0, 0.01)", a.d0);
    }
    let model = scenario.model().clone();
    let p = scenario.params();
    println!(
        "integrated: omega = {}, F = {}, xi = {}, c = {}, D_d = {}, D_s = {}",
        p.omega, p.load, p.xi, p.c, p.d_double, p.d_single
    );
    let sim = cfg.sim_options()?;
    let opts = LyapunovOptions {
        period: model.excitation_period(),
        transient_periods: sim.transient_periods,
        periods: sim.record_periods,
        d0: a.d0,
    };
    let y0 = [cfg.simulation.x0, cfg.simulation.v0];
    let scheme = sim.method.scheme(&model);
    let t0 = sim.tau0;
    if a.method != "two-trajectory" {
        let r = tle_variational::<_, 2, 4>(model.clone(), scheme, t0, y0, &opts)?;
        println!(
            "TLE (variational, saltation): {:.6} +- {:.6} per unit tau over {} periods{}",
            r.tle,
            r.spread,
            opts.periods,
            if r.annihilated > 0 {
                format!(" ({} sticking intervals)", r.annihilated)
            } else {
                String::new()
            }
        );
    }
    if a.method != "variational" {
        let r = tle_two_trajectory(model, scheme, t0, y0, &opts)?;
        println!(
            "TLE (two-trajectory, d0 = {:e}): {:.6} +- {:.6} per unit tau",
            a.d0, r.tle, r.spread
        );
    }
    Ok(())
}
