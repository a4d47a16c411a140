//! `geardyn simulate`.

use crate::run_config::ConfigArgs;
use anyhow::Result;
use clap::Args;
use geardyn_analysis::simulate::Method;
use geardyn_exec::{execute, SimulateJob};
use geardyn_io::simulate_folder;
use std::path::PathBuf;

/// Arguments of `geardyn simulate`.
#[derive(Args, Debug)]
pub struct SimulateArgs {
    #[command(flatten)]
    cfg: ConfigArgs,
    #[command(flatten)]
    sim: crate::sweep::SimArgs,
    /// Excitation periods (the last ones recorded) kept in trajectory.csv and the phase portrait
    /// (the time-history and mesh-force plots show the last 5 of them, 1 when an excitation
    /// period holds several mesh cycles).
    #[arg(long, default_value_t = simulate_folder::DEFAULT_TRAJECTORY_PERIODS, value_parser = clap::value_parser!(u64).range(1..=simulate_folder::MAX_TRAJECTORY_PERIODS))]
    trajectory_periods: u64,
    /// Output directory.
    #[arg(long, default_value = "out/simulate")]
    out: PathBuf,
}

pub fn run(args: SimulateArgs) -> Result<()> {
    if let Some(t) = crate::train::from_args(&args.cfg)? {
        return crate::train::simulate(&t, &args.sim, &args.out);
    }
    let mut cfg = args.cfg.config()?;
    args.sim.apply(&mut cfg, &args.cfg.sets)?;
    let out = &args.out;
    let source = args.cfg.source();
    let job = SimulateJob {
        config: &cfg,
        source: &source,
        trajectory_periods: Some(args.trajectory_periods),
        out: Some(out),
    };
    let run = execute(&job, None, &())?;
    let (summary, used, opts, res) = (&run.summary, &run.used, &run.requested, &run.res);
    let (model, elapsed) = (run.scenario.model(), run.elapsed_s);
    if let geardyn_analysis::Motion::Diverged { .. } = summary.motion {
        anyhow::bail!(
            "{} (outputs written to {})",
            summary.describe(),
            out.display()
        );
    }
    println!(
        "{}: label {}, {}, P_ID {:.4}, mesh force [{:.4}, {:.4}], {} impacts{}; {} steps in {:.3} s -> {}",
        match (summary.mesh_period, model.cycles_per_period()) {
            (_, 1) => summary.describe(),
            (Some(m), c) => format!(
                "{} (excitation period = 1 revolution = {c} mesh cycles; mesh-cycle strobe: period {m} mesh cycles)",
                summary.describe()
            ),
            (None, c) => format!(
                "{} (excitation period = 1 revolution = {c} mesh cycles; mesh-cycle strobe not periodic)",
                summary.describe()
            ),
        },
        summary.label,
        summary.health_text(),
        summary.p_id,
        summary.min_force,
        summary.max_force,
        summary.impacts,
        {
            let mut how = String::new();
            if used.transient_periods > opts.transient_periods {
                how += &format!(
                    "; transient extended to {} periods to decide",
                    used.transient_periods
                );
            }
            if let (Method::Dopri { rtol, .. }, true) = (used.method, used.method != opts.method) {
                how += &format!("; recorded at rtol {rtol:.0e} to tell its period from the integrator's noise");
            }
            how
        },
        res.steps,
        elapsed,
        out.display()
    );
    Ok(())
}
