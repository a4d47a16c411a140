//! `geardyn bench`: integrator speed on case C1 (MODEL.md §6), printed as figures.

use anyhow::Result;
use clap::Args;
use geardyn_analysis::driver::{run_periods, Discard};
use geardyn_model::{presets, MeshModel};
use geardyn_solvers::{Integrator, Scheme};

/// Arguments of `geardyn bench`.
#[derive(Args, Debug)]
pub struct BenchArgs {
    /// Excitation periods per run.
    #[arg(long, default_value_t = 400)]
    periods: u64,
    /// RK4 steps per mesh cycle.
    #[arg(long, default_value_t = 512)]
    steps_per_cycle: u32,
    /// Mesh frequency.
    #[arg(long, default_value_t = 1.3)]
    omega: f64,
    /// Repetitions (the best is reported).
    #[arg(long, default_value_t = 5)]
    repeat: u32,
}

pub fn run(a: BenchArgs) -> Result<()> {
    let mut p = presets::classic();
    p.omega = a.omega;
    let model = MeshModel::new(&p)?;
    let ts = model.excitation_period();
    for (name, scheme) in [
        (
            "rk4",
            Scheme::Rk4 {
                h: model.mesh_cycle_time() / a.steps_per_cycle as f64,
            },
        ),
        ("dopri", Scheme::dopri_default()),
    ] {
        let mut best = f64::INFINITY;
        let mut stats = Default::default();
        for _ in 0..a.repeat {
            let mut it = Integrator::new(model.clone(), scheme, 0.0, [0.0, 0.0])?;
            let t = std::time::Instant::now();
            run_periods(&mut it, ts, a.periods, &mut Discard)?;
            let el = t.elapsed().as_secs_f64();
            if el < best {
                best = el;
                stats = it.stats();
            }
        }
        println!(
            "C1 omega={} {} periods, {name:<5}: {:>9} steps, {:>5} events, total {:.4} s, {:.1} ns/step",
            a.omega,
            a.periods,
            stats.steps,
            stats.events,
            best,
            best * 1e9 / stats.steps as f64
        );
    }
    Ok(())
}
