//! `geardyn bench`: integrator speed on case C1 (docs/model.md §6), printed as figures.

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
    /// Interior guard samples per step (grazing detection); default: the integrator's choice.
    #[arg(long)]
    grazing: Option<usize>,
    /// Also time the C1 bifurcation diagram (200 values of omega in [0.5, 2], 300 + 100 periods).
    #[arg(long)]
    bifurcation: bool,
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
            let mut it = Integrator::new(model.clone(), scheme, 0.0, [0.0, 0.0])?.with_options(
                geardyn_solvers::Options {
                    grazing_samples: a.grazing,
                    ..Default::default()
                },
            );
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
    if a.bifurcation {
        use geardyn_analysis::bifurcation::{
            linspace, run_sweep, Section, SweepMode, SweepOptions,
        };
        use geardyn_analysis::simulate::{Method, SimOptions};
        for method in [
            Method::Rk4 {
                steps_per_cycle: a.steps_per_cycle,
            },
            Method::default(),
        ] {
            let opts = SweepOptions {
                param: "omega".into(),
                values: linspace(0.5, 2.0, 200),
                mode: SweepMode::Fixed,
                sim: SimOptions {
                    method,
                    transient_periods: 300,
                    record_periods: 100,
                    ..Default::default()
                },
                y0: [0.0, 0.0],
                sections: vec![Section::Strobe],
                lyapunov: false,
            };
            let t = std::time::Instant::now();
            let r = run_sweep(
                &geardyn_scenario::Scenario::dimensionless(p.clone())?,
                &opts,
                &Default::default(),
                |_| {},
            )?;
            let el = t.elapsed().as_secs_f64();
            println!(
                "C1 bifurcation, 200 values x 400 periods, {:?}, {} threads: {:.3} s ({} runs)",
                method,
                rayon::current_num_threads(),
                el,
                r.len()
            );
        }
    }
    Ok(())
}
