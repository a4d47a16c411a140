//! `geardyn`: nonlinear dynamics of spur gear pairs from the command line.

mod bench;
mod run_config;
mod simulate;

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(name = "geardyn", version, about = "Nonlinear dynamics of spur gear pairs", long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// List the built-in presets.
    Presets,
    /// Print the full resolved configuration as TOML (ready to edit and pass to --config).
    Show(run_config::ConfigArgs),
    /// Integrate the model and write trajectory, stroboscopic points, events, summary and plots.
    Simulate(simulate::SimulateArgs),
    /// Measure integrator speed on case C1 and print the figures.
    Bench(bench::BenchArgs),
}

fn main() {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Presets => {
            for (name, what) in geardyn_model::presets::PRESETS {
                println!("{name:<10} {what}");
            }
            Ok(())
        }
        Command::Show(args) => args.resolve().map(|c| print!("{}", c.to_toml())),
        Command::Simulate(args) => simulate::run(args),
        Command::Bench(args) => bench::run(args),
    };
    if let Err(e) = result {
        eprintln!("error: {e:#}");
        std::process::exit(2);
    }
}
