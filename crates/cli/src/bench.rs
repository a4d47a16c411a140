//! `geardyn bench`: integrator speed on case C1 (docs/model.md §6), printed as figures, with the
//! numba yardstick (`crates/cli/bench/c1_numba_rk4.py`, built in) run in the same command for ratios.
//!
//! Figures: ns per RK4 step (scalar, and per lane-step of the lockstep ensemble on one thread),
//! workload W1 (the C1 bifurcation diagram: 200 values of omega in [0.5, 2], 300 + 100 periods,
//! RK4 512 steps per period) with the ensemble, the scalar RK4 and DP5, and the 200 x 200 basin of
//! C1 at omega = 1.8 (ensemble RK4). The numba yardstick is run before and after the geardyn
//! workloads (its first run compiles and is not timed) and the ratios use the mean of its timed
//! runs. On a shared machine run it several times and compare ratios, not seconds.

use anyhow::{bail, Context, Result};
use clap::Args;
use geardyn_analysis::basins::{basins, Axis, BasinOptions};
use geardyn_analysis::bifurcation::{
    linspace, run_once, run_sweep, Section, SweepMode, SweepOptions,
};
use geardyn_analysis::driver::{run_periods, Discard};
use geardyn_analysis::lanes::{simulate_lanes, LaneSim, LANES};
use geardyn_analysis::simulate::{Method, SimOptions};
use geardyn_model::{presets, MeshModel};
use geardyn_solvers::{Integrator, Scheme};
use rayon::prelude::*;
use std::path::PathBuf;
use std::time::Instant;

/// Arguments of `geardyn bench`.
#[derive(Args, Debug)]
pub struct BenchArgs {
    /// Excitation periods per run (ns/step figures).
    #[arg(long, default_value_t = 400)]
    periods: u64,
    /// RK4 steps per mesh cycle.
    #[arg(long, default_value_t = 512)]
    steps_per_cycle: u32,
    /// Mesh frequency of the ns/step figures.
    #[arg(long, default_value_t = 1.3)]
    omega: f64,
    /// Repetitions of the ns/step figures (the best is reported).
    #[arg(long, default_value_t = 5)]
    repeat: u32,
    /// Interior guard samples per step (grazing detection); default: the integrator's choice.
    #[arg(long)]
    grazing: Option<usize>,
    /// Also time W1, the C1 bifurcation diagram (200 values of omega in [0.5, 2], 300 + 100
    /// periods): ensemble RK4, scalar RK4 and DP5.
    #[arg(long)]
    bifurcation: bool,
    /// Also time the 200 x 200 basin of C1 at omega = 1.8 (ensemble RK4).
    #[arg(long)]
    basins: bool,
    /// Also time the scalar RK4 basin (slow: minutes).
    #[arg(long)]
    scalar_basins: bool,
    /// Also time the basin with the adaptive DP5 (scalar; rtol 1e-7, the `geardyn basins`
    /// identification default).
    #[arg(long)]
    dopri_basins: bool,
    /// RK4 steps per mesh cycle of the basin (W1 uses --steps-per-cycle).
    #[arg(long, default_value_t = 512)]
    basin_steps: u32,
    /// Also time a decision's follow on the broken pair (the `breakage` preset at omega = 1.2,
    /// chaotic loads F = 0.03 ... 0.06, fixed-step RK4 at the follow's resolution, strobe only):
    /// ns per lane-step on a one-lane engine and on a full engine, one thread.
    #[arg(long)]
    follow: bool,
    /// Also time the gear trains: cost per mesh cycle of the planetary stage, the two-stage drive
    /// and the pair written as a train, beside the pair model's (DP5 and RK4).
    #[arg(long)]
    trains: bool,
    /// Everything: --bifurcation --basins --follow --trains --numba.
    #[arg(long)]
    all: bool,
    /// Run the numba yardstick in this command and print ratios.
    #[arg(long)]
    numba: bool,
    /// Python interpreter with numba (default: $GEARDYN_NUMBA_PYTHON, else python3).
    #[arg(long)]
    numba_python: Option<String>,
    /// The yardstick script (default: the copy built into geardyn, `crates/cli/bench/`, written
    /// to the temporary directory).
    #[arg(long)]
    numba_script: Option<PathBuf>,
}

/// The numba yardstick of W1 (plain fixed-step RK4 of C1, parallel over omega, no event location),
/// the project's reference script, shipped with the binary.
const YARDSTICK: &str = include_str!("../bench/c1_numba_rk4.py");

/// The yardstick script to run: `given`, or the built-in copy written to a fixed temporary path
/// (fixed so that numba's compilation cache beside it is reused between runs).
fn yardstick_path(given: &Option<PathBuf>) -> Result<PathBuf> {
    if let Some(p) = given {
        return Ok(p.clone());
    }
    let dir = std::env::temp_dir().join("geardyn-bench");
    let path = dir.join("c1_numba_rk4.py");
    if std::fs::read_to_string(&path).ok().as_deref() != Some(YARDSTICK) {
        std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
        std::fs::write(&path, YARDSTICK).with_context(|| format!("writing {}", path.display()))?;
    }
    Ok(path)
}

/// Runs the numba yardstick once; its compute time in seconds.
fn numba_once(python: &str, script: &PathBuf) -> Result<f64> {
    let out = std::process::Command::new(python)
        .arg(script)
        .env(
            "NUMBA_NUM_THREADS",
            rayon::current_num_threads().to_string(),
        )
        .output()
        .with_context(|| format!("running {python} {}", script.display()))?;
    if !out.status.success() {
        bail!(
            "numba yardstick failed: {}",
            String::from_utf8_lossy(&out.stderr).trim()
        );
    }
    let text = String::from_utf8_lossy(&out.stdout);
    // "rk4: 200 parameter points, 400 periods each, 1.66 s"
    let secs = text
        .split(',')
        .next_back()
        .and_then(|s| s.trim().trim_end_matches('s').trim().parse::<f64>().ok())
        .with_context(|| format!("unexpected yardstick output: {text}"))?;
    Ok(secs)
}

struct Numba {
    python: String,
    script: PathBuf,
    times: Vec<f64>,
}

impl Numba {
    fn run(&mut self, label: &str) -> Result<()> {
        let s = numba_once(&self.python, &self.script)?;
        println!("numba yardstick W1 ({label}): {s:.3} s");
        self.times.push(s);
        Ok(())
    }
    fn mean(&self) -> Option<f64> {
        (!self.times.is_empty()).then(|| self.times.iter().sum::<f64>() / self.times.len() as f64)
    }
}

fn w1_options(method: Method) -> SweepOptions {
    SweepOptions {
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
    }
}

fn load() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .ok()
        .and_then(|s| s.split_whitespace().next().map(str::to_string))
        .unwrap_or_else(|| "?".into())
}

/// Longest ns/step run of `geardyn bench` (excitation periods).
const MAX_BENCH_PERIODS: u64 = 100_000;
/// Most repetitions of the ns/step figures.
const MAX_BENCH_REPEAT: u32 = 100;

/// Refuses settings outside what a run accepts (each names the flag and its range).
fn check(a: &BenchArgs) -> Result<()> {
    use geardyn_analysis::simulate::{MAX_PERIODS, RK4_STEPS_PER_CYCLE};
    use geardyn_solvers::integrator::MAX_GRAZING_SAMPLES;
    let steps = &RK4_STEPS_PER_CYCLE;
    for (flag, n) in [
        ("--steps-per-cycle", a.steps_per_cycle),
        ("--basin-steps", a.basin_steps),
    ] {
        if !steps.contains(&n) {
            bail!(
                "bad {flag} {n}: allowed a whole number in [{}, {}]",
                steps.start(),
                steps.end()
            );
        }
    }
    // a benchmark, not a study: bounded so that the ns/step figures take minutes at most
    let periods = MAX_BENCH_PERIODS.min(MAX_PERIODS);
    if !(1..=periods).contains(&a.periods) {
        bail!(
            "bad --periods {}: allowed a whole number in [1, {periods}]",
            a.periods
        );
    }
    if !(1..=MAX_BENCH_REPEAT).contains(&a.repeat) {
        bail!(
            "bad --repeat {}: allowed a whole number in [1, {MAX_BENCH_REPEAT}]",
            a.repeat
        );
    }
    // the model's own range, under the flag's name
    let mut p = presets::classic();
    p.omega = a.omega;
    if let Err(e) = MeshModel::new(&p) {
        bail!("bad --omega {}: {e}", a.omega);
    }
    if let Some(g) = a.grazing {
        if g > MAX_GRAZING_SAMPLES {
            bail!("bad --grazing {g}: allowed a whole number in [0, {MAX_GRAZING_SAMPLES}]");
        }
    }
    Ok(())
}

pub fn run(a: BenchArgs) -> Result<()> {
    check(&a)?;
    let (bif, bas, num) = (a.bifurcation || a.all, a.basins || a.all, a.numba || a.all);
    println!(
        "geardyn bench: {} threads, ensemble {} lanes, {} dispatch, load average {}",
        rayon::current_num_threads(),
        LANES,
        geardyn_solvers::ensemble::dispatch_path(),
        load()
    );
    let mut numba = Numba {
        python: a
            .numba_python
            .clone()
            .or_else(|| std::env::var("GEARDYN_NUMBA_PYTHON").ok())
            .unwrap_or_else(|| "python3".into()),
        script: if num {
            yardstick_path(&a.numba_script)?
        } else {
            PathBuf::new()
        },
        times: Vec::new(),
    };
    if num {
        // the first run compiles (numba's cache), not timed
        numba_once(&numba.python, &numba.script)?;
        numba.run("before")?;
    }
    let mut p = presets::classic();
    p.omega = a.omega;
    let model = MeshModel::new(&p)?;
    scalar_figures(&a, &model)?;
    ensemble_figure(&a, &model)?;
    if a.follow || a.all {
        follow_figures(a.repeat)?;
    }
    if a.trains || a.all {
        crate::bench_trains::figures(a.repeat.min(3))?;
    }
    let w1_ens = if bif {
        Some(w1_figures(&a, &mut numba, num)?)
    } else {
        None
    };
    if bas {
        basin_figures(&a, &mut numba, num)?;
    }
    if let (Some(el), Some(nb)) = (w1_ens, numba.mean()) {
        println!(
            "summary: W1 ensemble {el:.3} s, numba {nb:.3} s (mean of {} runs), ratio {:.1}x",
            numba.times.len(),
            nb / el
        );
    }
    Ok(())
}

/// ns per step of the scalar integrators (RK4 and DP5) on C1, best of `--repeat`.
fn scalar_figures(a: &BenchArgs, model: &MeshModel) -> Result<()> {
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
            let t = Instant::now();
            run_periods(&mut it, ts, a.periods, &mut Discard)?;
            let el = t.elapsed().as_secs_f64();
            if el < best {
                best = el;
                stats = it.stats();
            }
        }
        println!(
            "C1 omega={} {} periods, scalar {name:<5}: {:>9} steps, {:>5} events, total {:.4} s, {:.1} ns/step",
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

/// ns per lane-step of the ensemble: one thread, one table, LANES * 2 trajectories of the same
/// model from different initial states (all steps recorded as in a sweep's run: transient 3/4,
/// record 1/4).
fn ensemble_figure(a: &BenchArgs, model: &MeshModel) -> Result<()> {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    let ics: Vec<[f64; 2]> = (0..2 * LANES)
        .map(|i| [-1.0 + 0.1 * i as f64, 0.0])
        .collect();
    let runs: Vec<(&MeshModel, [f64; 2])> = ics.iter().map(|&y| (model, y)).collect();
    let opts = SimOptions {
        method: Method::Rk4 {
            steps_per_cycle: a.steps_per_cycle,
        },
        transient_periods: a.periods - a.periods / 4,
        record_periods: a.periods / 4,
        ..Default::default()
    };
    let lane = LaneSim::new(&opts)?;
    let mut best = f64::INFINITY;
    let mut steps = 0;
    for _ in 0..a.repeat {
        let t = Instant::now();
        let r = pool.install(|| simulate_lanes(&runs, &lane));
        let el = t.elapsed().as_secs_f64();
        if el < best {
            best = el;
            steps = r.iter().map(|x| x.as_ref().map_or(0, |s| s.steps)).sum();
        }
    }
    println!(
        "C1 omega={} {} periods, ensemble rk4 x{} on 1 thread: {:>9} steps, total {:.4} s, {:.2} ns/step",
        a.omega,
        a.periods,
        runs.len(),
        steps,
        best,
        best * 1e9 / steps as f64
    );
    Ok(())
}

/// W1, the C1 bifurcation diagram: the ensemble sweep, its integration alone (with and without
/// recording), scalar RK4 and DP5; with the yardstick, the speed-ups. Returns the ensemble
/// sweep's seconds.
fn w1_figures(a: &BenchArgs, numba: &mut Numba, num: bool) -> Result<f64> {
    let scenario = geardyn_scenario::Scenario::dimensionless(presets::classic())?;
    let rk4 = Method::Rk4 {
        steps_per_cycle: a.steps_per_cycle,
    };
    // ensemble: the whole sweep (lanes; non-periodic values classified from their lanes result)
    let opts = w1_options(rk4);
    let t = Instant::now();
    let r = run_sweep(&scenario, &opts, &Default::default(), |_| {})?;
    let el = t.elapsed().as_secs_f64();
    let periodic = r.iter().filter(|x| x.runs[0].period > 0).count();
    println!(
        "W1 C1 bifurcation, 200 values x 400 periods, rk4 ensemble (sweep, classified): {el:.3} s ({periodic} periodic values)"
    );
    // ensemble: integration and recording only (the yardstick's work plus event location)
    let models: Vec<MeshModel> = opts
        .values
        .iter()
        .map(|&w| {
            let mut p = presets::classic();
            p.omega = w;
            MeshModel::new(&p)
        })
        .collect::<Result<_, _>>()?;
    let runs: Vec<(&MeshModel, [f64; 2])> = models.iter().map(|m| (m, [0.0, 0.0])).collect();
    let t = Instant::now();
    let r = simulate_lanes(&runs, &LaneSim::new(&opts.sim)?);
    let el_sim = t.elapsed().as_secs_f64();
    let steps: u64 = r.iter().map(|x| x.as_ref().map_or(0, |s| s.steps)).sum();
    println!(
        "W1 C1 bifurcation, 200 values x 400 periods, rk4 ensemble (integration + record): {el_sim:.3} s ({steps} steps)"
    );
    // the same runs with nothing recorded: what the lanes cost with exact events alone
    let bare = SimOptions {
        transient_periods: opts.sim.transient_periods + opts.sim.record_periods,
        record_periods: 0,
        ..opts.sim
    };
    let t = Instant::now();
    let r = simulate_lanes(&runs, &LaneSim::new(&bare)?);
    let el_bare = t.elapsed().as_secs_f64();
    let events: u64 = r
        .iter()
        .map(|x| {
            x.as_ref()
                .map_or(0, |s| s.rhs_evals.saturating_sub(4 * s.steps))
        })
        .sum();
    println!(
        "W1 C1 bifurcation, 200 values x 400 periods, rk4 ensemble (integration, nothing recorded): {el_bare:.3} s ({events} right-hand sides beyond 4 per step: event location)"
    );
    // scalar RK4: the sweep's runs one by one (run_once), in parallel over values
    let t = Instant::now();
    let _: Vec<_> = models
        .par_iter()
        .map(|m| run_once(m, [0.0, 0.0], 0, &opts))
        .collect();
    let el_scalar = t.elapsed().as_secs_f64();
    println!(
        "W1 C1 bifurcation, 200 values x 400 periods, rk4 scalar (sweep, classified): {el_scalar:.3} s"
    );
    let opts = w1_options(Method::default());
    let t = Instant::now();
    run_sweep(&scenario, &opts, &Default::default(), |_| {})?;
    let el_dp = t.elapsed().as_secs_f64();
    println!(
        "W1 C1 bifurcation, 200 values x 400 periods, dopri (sweep, classified): {el_dp:.3} s"
    );
    if num {
        numba.run("after W1")?;
        let nb = numba.mean().unwrap_or(f64::NAN);
        println!(
            "W1 speed-up over numba ({nb:.3} s): ensemble sweep {:.1}x, ensemble integration {:.1}x (nothing recorded {:.1}x), scalar rk4 {:.2}x, dopri {:.2}x",
            nb / el,
            nb / el_sim,
            nb / el_bare,
            nb / el_scalar,
            nb / el_dp
        );
    }
    Ok(el)
}

/// The 200 x 200 basin of C1 at omega = 1.8: ensemble RK4, and on request DP5 and scalar RK4.
fn basin_figures(a: &BenchArgs, numba: &mut Numba, num: bool) -> Result<()> {
    let mut p = presets::classic();
    p.omega = 1.8;
    let model = MeshModel::new(&p)?;
    let mut ident = geardyn_analysis::attractor::IdentifyOptions::default();
    ident.sim.method = Method::Rk4 {
        steps_per_cycle: a.basin_steps,
    };
    let opts = BasinOptions {
        x: Axis {
            min: -2.0,
            max: 2.0,
            n: 200,
        },
        v: Axis {
            min: -1.5,
            max: 1.5,
            n: 200,
        },
        identify: ident,
        slice: Default::default(),
    };
    let t = Instant::now();
    let r = basins(&model, &opts, &Default::default(), |_, _| {});
    let el = t.elapsed().as_secs_f64();
    println!(
        "basin 200x200 C1 omega=1.8, rk4 ensemble ({} steps/cycle): {el:.3} s ({} attractors, {} captured early, {} periods)",
        a.basin_steps,
        r.attractors.len(),
        r.captured_early,
        r.periods
    );
    if a.dopri_basins {
        let mut o = opts;
        o.identify.sim.method = Method::Dopri {
            rtol: 1e-7,
            atol: 1e-10,
        };
        let t = Instant::now();
        let r = basins(&model, &o, &Default::default(), |_, _| {});
        println!(
            "basin 200x200 C1 omega=1.8, dopri rtol 1e-7 (scalar): {:.3} s ({} attractors)",
            t.elapsed().as_secs_f64(),
            r.attractors.len()
        );
    }
    if a.scalar_basins {
        let t = Instant::now();
        let _ =
            geardyn_analysis::basins::basins_scalar(&model, &opts, &Default::default(), |_, _| {});
        println!(
            "basin 200x200 C1 omega=1.8, rk4 scalar: {:.3} s",
            t.elapsed().as_secs_f64()
        );
    }
    if num {
        numba.run("after basin")?;
        let nb = numba.mean().unwrap_or(f64::NAN);
        println!("basin time / numba W1 time ({nb:.3} s): {:.2}", el / nb);
    }
    Ok(())
}

/// Revolutions of each run of the follow figures.
const FOLLOW_REVOLUTIONS: u64 = 200;

/// ns per lane-step of a decision's follow on the broken pair (see [`BenchArgs::follow`]): one
/// run alone (the one-lane engine of a decision that finishes on its own) and `LANES` runs
/// together, on one thread, best of `repeat`.
fn follow_figures(repeat: u32) -> Result<()> {
    let base = geardyn_scenario::ScenarioSpec::preset("breakage")?
        .resolve()?
        .with("omega", 1.2)?;
    let scen: Vec<geardyn_scenario::Scenario> = linspace(0.03, 0.06, LANES)
        .into_iter()
        .map(|f| base.with("F", f))
        .collect::<Result<_, _>>()?;
    let method = geardyn_analysis::pair_engine::follow_method(
        scen[0].model(),
        &SimOptions {
            follow_steps: geardyn_analysis::classify::FOLLOW_STEPS,
            ..Default::default()
        },
    )
    .context("the broken pair has no lanes follow")?;
    let opts = SimOptions {
        method,
        transient_periods: FOLLOW_REVOLUTIONS,
        record_periods: 0,
        strobe_only: true,
        ..Default::default()
    };
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    let runs: Vec<(&MeshModel, [f64; 2])> = scen.iter().map(|s| (s.model(), [0.0, 0.0])).collect();
    let lane = LaneSim::new(&opts)?;
    for n in [1, LANES] {
        let mut best = f64::INFINITY;
        let (mut steps, mut events) = (0, 0);
        for _ in 0..repeat {
            let t = Instant::now();
            let r = pool.install(|| simulate_lanes(&runs[..n], &lane));
            let el = t.elapsed().as_secs_f64();
            if el < best {
                best = el;
                let ok = || r.iter().filter_map(|x| x.as_ref().ok());
                steps = ok().map(|s| s.steps).sum();
                events = ok().map(|s| s.rhs_evals).sum::<u64>();
            }
        }
        println!(
            "breakage omega=1.2 follow ({method:?}), {FOLLOW_REVOLUTIONS} revolutions x{n} on 1 thread: {steps:>9} steps, {events} evaluations, total {best:.4} s, {:.2} ns/step",
            best * 1e9 / steps.max(1) as f64
        );
    }
    Ok(())
}
