//! `geardyn simulate`.

use crate::run_config::ConfigArgs;
use anyhow::Result;
use clap::Args;
use geardyn_analysis::simulate::Method;
use geardyn_io::simulate_folder;
use std::path::PathBuf;

/// Arguments of `geardyn simulate`.
#[derive(Args, Debug)]
pub struct SimulateArgs {
    #[command(flatten)]
    cfg: ConfigArgs,
    /// Recorded excitation periods (default: simulation.record_periods of the config).
    #[arg(long)]
    periods: Option<u64>,
    /// Transient excitation periods discarded first (default: simulation.transient_periods).
    #[arg(long)]
    transient: Option<u64>,
    /// Integrator (default: simulation.method of the config, dopri): dopri (adaptive) or rk4
    /// (fixed step, --steps-per-cycle per mesh cycle).
    #[arg(long, value_parser = ["dopri", "rk4"])]
    integrator: Option<String>,
    /// RK4 steps per mesh cycle (default: simulation.steps_per_cycle).
    #[arg(long)]
    steps_per_cycle: Option<u32>,
    /// Decision horizon: excitation periods (from the start) a motion with a positive Lyapunov
    /// exponent is followed before it is called chaotic (default: simulation.decision_periods).
    #[arg(long)]
    decision_periods: Option<u64>,
    /// Work budget of the decision in right-hand-side evaluations (default:
    /// simulation.decision_budget).
    #[arg(long)]
    decision_budget: Option<u64>,
    /// Cap on the estimated work in right-hand-side evaluations, the decision's worst case
    /// included; above it the run is refused (default: simulation.max_work, 1e12).
    #[arg(long)]
    max_work: Option<f64>,
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
    let mut cfg = args.cfg.config()?;
    // the sweeps' flags, applied by the same code (simulate has no checkpoint: no --force)
    crate::sweep::SimArgs {
        periods: args.periods,
        transient: args.transient,
        integrator: args.integrator.clone(),
        steps_per_cycle: args.steps_per_cycle,
        decision_periods: args.decision_periods,
        decision_budget: args.decision_budget,
        max_work: args.max_work,
        force: false,
    }
    .apply(&mut cfg, &args.cfg.sets)?;
    let out = &args.out;
    let run = simulate_folder::simulate(
        cfg,
        args.cfg.source(),
        Some(args.trajectory_periods),
        Some(out),
    )?;
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
