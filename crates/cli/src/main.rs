//! `geardyn`: nonlinear dynamics of spur gear pairs from the command line.

mod bench;
mod bench_trains;
mod bifurcation;
mod global;
mod lyapunov;
mod modes;
mod orbits;
mod report;
mod run_config;
mod shard;
mod signals;
mod simulate;
mod stiffness;
mod sweep;
mod tle_text;
mod train;
mod train_basins;
mod train_continuation;
mod train_lyapunov;
mod train_map;
mod train_orbits;
mod train_response;
mod train_signals;

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(name = "geardyn", version, about = "Nonlinear dynamics of spur gear pairs", long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run the seed study of a preset and write an HTML report with figures, tables and claims.
    Report(report::ReportArgs),
    /// List the built-in presets.
    Presets,
    /// Print the full resolved configuration as TOML (ready to edit and pass to --config); of a
    /// gear train (--preset planetary, two-stage, pair, or --system) its resolved description
    /// (for --system), its speeds and static mesh forces.
    Show(run_config::ConfigArgs),
    /// Mesh stiffness, load shares, friction factors and backlash over the excitation period
    /// (healthy versus broken for a broken pair): stiffness.csv and plots.
    // negative values after a space (`--phase -0.1`) are values, not flags
    #[command(allow_negative_numbers = true)]
    Stiffness(stiffness::StiffnessArgs),
    /// Integrate the model and write trajectory, stroboscopic points, events, summary and plots.
    // negative values after a space (`--phase -0.1`) are values, not flags
    #[command(allow_negative_numbers = true)]
    Simulate(simulate::SimulateArgs),
    /// Bifurcation diagram over a parameter (fixed, continuation or multi-initial), resumable.
    // negative values after a space (`--phase -0.1`) are values, not flags
    #[command(allow_negative_numbers = true)]
    Bifurcation(bifurcation::BifurcationArgs),
    /// Top Lyapunov exponent (variational with saltation, and/or two-trajectory).
    // negative values after a space (`--phase -0.1`) are values, not flags
    #[command(allow_negative_numbers = true)]
    Lyapunov(lyapunov::LyapunovArgs),
    /// Frequency response: up and down continuation sweeps, RMS and peak-to-peak, jumps.
    // negative values after a space (`--phase -0.1`) are values, not flags
    #[command(allow_negative_numbers = true)]
    Response(bifurcation::ResponseArgs),
    /// Basins of attraction on a grid of initial states, with automatic attractor identification.
    // negative values after a space (`--phase -0.1`) are values, not flags
    #[command(allow_negative_numbers = true)]
    Basins(global::BasinArgs),
    /// Attractor continuation along a parameter: branches, basin fractions, events (resumable).
    // negative values after a space (`--phase -0.1`) are values, not flags
    #[command(allow_negative_numbers = true)]
    Continuation(global::ContinuationArgs),
    /// Periodic orbits by shooting: Floquet multipliers and stability of one orbit, or with
    /// --param/--range its branches (stable and unstable) and their bifurcations (period doubling,
    /// fold, torus, grazing, corner collision; any other change of stability is reported too).
    #[command(allow_negative_numbers = true)]
    Orbits(orbits::OrbitArgs),
    /// Vibration signals of the broken pair and its healthy twin (transmission error, mesh
    /// force, acceleration), spectra in orders and gear condition indicators (FM0, FM4, NA4, ...).
    /// Without --preset or --config the pair is `breakage`; `classic` has no physical pair and
    /// is refused.
    #[command(allow_negative_numbers = true)]
    Signals(signals::SignalsArgs),
    /// Two-parameter map of max mesh force, P_ID, period, TLE or motion class (resumable).
    // negative values after a space (`--phase -0.1`) are values, not flags
    #[command(allow_negative_numbers = true)]
    Map2d(global::MapArgs),
    /// Natural frequencies, mode shapes (rigid-body, rotational, planet modes with their
    /// multiplicity) and Campbell resonances of a gear train: --preset planetary (default),
    /// two-stage or pair, or --system FILE.
    #[command(allow_negative_numbers = true)]
    Modes(modes::ModesArgs),
    /// Measure integrator and sweep speed on case C1 and print the figures.
    Bench(bench::BenchArgs),
    /// Plan a map2d or bifurcation in shards over a Zarr store, to run on many machines
    /// (docs/distributed.md): `geardyn plan map2d <its arguments> --shards N --out STORE`.
    Plan(shard::PlanArgs),
    /// Compute one shard of a plan (--shard I, else SLURM_ARRAY_TASK_ID); a done shard is kept.
    RunShard(shard::RunShardArgs),
    /// List the done and missing shards of a plan.
    Status(shard::StatusArgs),
    /// Merge a plan's shards into the single command's files (map.csv, runs.csv, figures...).
    Merge(shard::MergeArgs),
}

/// Ctrl-C (through the `ctrlc` crate, on a thread of its own): stop every integration, say what
/// is kept, remove the folder's lock file and leave with the conventional status 130 (a
/// checkpointed command has its finished items on disk already, one line each).
fn on_interrupt() {
    const MSG: &str = "\ninterrupted: sweeps, responses, basins, continuations, maps and reports keep their finished work (run the same command again to resume); simulate, lyapunov, orbits, and a gear train's bifurcation and response start over";
    geardyn_solvers::cancel::request();
    geardyn_io::run_record::release_held_lock();
    eprintln!("{MSG}");
    std::process::exit(130);
}

fn main() {
    // Piping into `head` closes stdout early: end quietly like other Unix tools instead of
    // panicking on a failed print.
    #[cfg(unix)]
    // SAFETY: restoring the default disposition of SIGPIPE before any thread starts.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    // (a handler that cannot be installed leaves the default: Ctrl-C ends the process at once)
    let _ = ctrlc::set_handler(on_interrupt);
    let cli = Cli::parse();
    // the start of the command, as the run records of its folder state it
    let started = geardyn_io::run_record::now_unix_s();
    let result = match cli.command {
        Command::Report(args) => report::run(args),
        Command::Presets => {
            for (name, what) in geardyn_model::presets::PRESETS {
                println!("{name:<10} {what}");
            }
            println!("gear trains (geardyn {}):", run_config::TRAIN_COMMANDS);
            for (name, what) in [
                ("planetary", "sun 25 / planets 35 / ring 95, 3 equally spaced planets, m = 3 mm: sun input, carrier output, ring fixed"),
                ("two-stage", "20/50 then 22/61 teeth on an elastic intermediate shaft (40 mm x 150 mm steel)"),
                ("pair", "the seed-A 40/40 pair (healthy) written as a train"),
            ] {
                println!("{name:<10} {what}");
            }
            Ok(())
        }
        Command::Show(args) => match train::from_args(&args) {
            Ok(Some(t)) => train::show(&t),
            Err(e) => Err(e),
            Ok(None) => args.resolve().and_then(|(c, s)| {
                print!("{}", c.to_toml());
                print!("{}", geardyn_io::describe::describe(&s)?);
                Ok(())
            }),
        },
        Command::Stiffness(args) => stiffness::run(args, started),
        Command::Simulate(args) => simulate::run(args),
        Command::Bifurcation(args) => bifurcation::run(args, started),
        Command::Lyapunov(args) => lyapunov::run(args),
        // a gear train's analyses beside the pair's (the train modules use the pair's
        // arguments and writers, so the choice is made here)
        Command::Response(args) => match train::from_args(&args.run.cfg) {
            Ok(Some(t)) => train_response::response(&t, &args),
            Ok(None) => bifurcation::response(args, started),
            Err(e) => Err(e),
        },
        Command::Basins(args) => match train::from_args(&args.run.cfg) {
            Ok(Some(t)) => train_basins::basins(&t, &args),
            Ok(None) => global::basins_cmd(args, started),
            Err(e) => Err(e),
        },
        Command::Continuation(args) => match train::from_args(&args.run.cfg) {
            Ok(Some(t)) => train_continuation::continuation(&t, &args),
            Ok(None) => global::continuation_cmd(args, started),
            Err(e) => Err(e),
        },
        Command::Orbits(args) => match train::from_args(&args.cfg) {
            Ok(Some(t)) => train_orbits::run(&t, &args),
            Ok(None) => orbits::run(args, started),
            Err(e) => Err(e),
        },
        Command::Signals(args) => signals::run(args, started),
        Command::Map2d(args) => match train::from_args(&args.run.cfg) {
            Ok(Some(t)) => train_map::map(&t, &args),
            Ok(None) => global::map_cmd(args, started),
            Err(e) => Err(e),
        },
        Command::Modes(args) => modes::run(args),
        Command::Bench(args) => bench::run(args),
        Command::Plan(args) => shard::plan(args),
        Command::RunShard(args) => shard::run_shard(args),
        Command::Status(args) => shard::status(args),
        Command::Merge(args) => shard::merge(args),
    };
    if let Err(e) = result {
        eprintln!("error: {e:#}");
        std::process::exit(2);
    }
}
