//! `geardyn bifurcation` and `geardyn response`.

use crate::sweep::{parse_range, run_checkpointed, InitialStatesArgs, RunArgs};
use anyhow::Result;
use clap::Args;
use geardyn_analysis::bifurcation::detect_jumps;
use geardyn_exec::request::{BifurcationRequest, SweepSpec};
use geardyn_io::{output, run_record, schema, sweep_output};
use geardyn_scenario::Scenario;
use std::path::PathBuf;

/// Arguments of `geardyn bifurcation`.
#[derive(Args, Debug)]
pub struct BifurcationArgs {
    #[command(flatten)]
    run: RunArgs,
    /// Parameter swept (omega, F, xi, c, D, D_d, D_s, mu, R, kappa, ...).
    #[arg(long, default_value = "omega")]
    param: String,
    /// START:STOP:COUNT.
    #[arg(long, allow_hyphen_values = true, default_value = "0.5:2:200")]
    range: String,
    /// fixed (same initial state), sweep (continuation up and down) or multi (K initial states).
    #[arg(long, default_value = "fixed")]
    mode: String,
    /// Initial states per value (multi).
    #[arg(long, default_value_t = SweepSpec::default().ics)]
    ics: usize,
    // seed and ranges of the initial states (multi)
    #[command(flatten)]
    initial: InitialStatesArgs,
    /// Sections: comma-separated from strobe, ds_up, ds_down, dd_up, dd_down, impact.
    #[arg(long, default_value = "strobe")]
    sections: String,
    /// Also compute the top Lyapunov exponent per value (variational, with saltation).
    #[arg(long)]
    lyapunov: bool,
    /// Output directory (rerunning the same command there resumes).
    #[arg(long, default_value = "out/bifurcation")]
    pub out: PathBuf,
}

impl BifurcationArgs {
    /// The resolved request and its scenario: the one place `bifurcation` and `plan bifurcation`
    /// turn their flags into options (validated, the work checked against its cap).
    pub fn request(&self) -> Result<(BifurcationRequest, Scenario)> {
        let (cfg, scenario) = self.run.resolve()?;
        let values = parse_range(&self.range)?;
        let (x0_range, v0_range) = self.initial.ranges()?;
        let spec = SweepSpec {
            param: self.param.clone(),
            values,
            mode: self.mode.clone(),
            ics: self.ics,
            seed: self.initial.seed,
            x0_range,
            v0_range,
            sections: self.sections.split(',').map(str::to_string).collect(),
            lyapunov: self.lyapunov,
        };
        let req = BifurcationRequest::new(cfg, self.run.cfg.source(), &scenario, &spec)?;
        Ok((req, scenario))
    }
}

pub fn run(a: BifurcationArgs, started: f64) -> Result<()> {
    if let Some(t) = crate::train::from_args(&a.run.cfg)? {
        return crate::train::bifurcation(
            &t,
            &a.run.sim,
            &a.param,
            &parse_range(&a.range)?,
            (&a.mode, &a.sections, a.lyapunov),
            &a.out,
        );
    }
    let (req, scenario) = a.request()?;
    let opts = &req.options;
    let n = opts.values.len();
    let t = std::time::Instant::now();
    let results = run_checkpointed(
        &req.config,
        &scenario,
        opts,
        &a.out,
        "bifurcation",
        a.run.force.force,
    )?;
    let elapsed = t.elapsed().as_secs_f64();
    req.write_folder(&a.out, &scenario, &results, started)?;
    let runs: usize = results.iter().map(|r| r.runs.len()).sum();
    // the runs whose decision went on past the requested record (runs.csv: periods_integrated)
    let base = opts.sim.transient_periods + opts.sim.record_periods;
    let longer = results
        .iter()
        .flat_map(|r| &r.runs)
        .filter(|u| u.periods_integrated > base)
        .count();
    let longer = if longer > 0 {
        format!(
            " ({longer} followed further to decide them, up to {} periods)",
            opts.sim.decision_periods
        )
    } else {
        String::new()
    };
    println!(
        "{} values, {} runs in all, of {}+{} periods{} in {:.2} s -> {}",
        n,
        runs,
        opts.sim.transient_periods,
        opts.sim.record_periods,
        longer,
        elapsed,
        a.out.display()
    );
    Ok(())
}

/// Arguments of `geardyn response`.
#[derive(Args, Debug)]
pub struct ResponseArgs {
    #[command(flatten)]
    pub(crate) run: RunArgs,
    /// Parameter swept (normally omega).
    #[arg(long, default_value = "omega")]
    pub(crate) param: String,
    /// START:STOP:COUNT.
    #[arg(long, allow_hyphen_values = true, default_value = "0.5:2:150")]
    pub(crate) range: String,
    /// Output directory (rerunning the same command there resumes).
    #[arg(long, default_value = "out/response")]
    pub(crate) out: PathBuf,
}

pub fn response(a: ResponseArgs, started: f64) -> Result<()> {
    let (cfg, scenario) = a.run.resolve()?;
    let opts =
        SweepSpec::response(a.param.clone(), parse_range(&a.range)?).options(&cfg, &scenario)?;
    let results = run_checkpointed(
        &cfg,
        &scenario,
        &opts,
        &a.out,
        "response",
        a.run.force.force,
    )?;
    run_record::write_config_and_record(
        &a.out,
        "response",
        &cfg,
        &scenario,
        &[run_record::Swept::of(&a.param, &opts.values)],
        started,
    )?;
    sweep_output::write_response(&a.out.join("response.csv"), &a.param, &results)?;
    // every run of both sweeps with the columns of every runs table (Python's `response().runs`)
    schema::runs_table(&a.param, &results).write_csv(&a.out.join("runs.csv"), schema::full)?;
    let jumps = detect_jumps(&results);
    output::write_json(&a.out.join("jumps.json"), &jumps)?;
    sweep_output::plot_response(
        &a.out.join("response"),
        &a.param,
        &results,
        &format!(
            "Frequency response over {}: {}",
            a.param,
            sweep_output::operating_point(&a.run.cfg.source(), scenario.params(), &[&a.param])
        ),
    )?;
    for j in &jumps {
        println!(
            "jump on the {} sweep between {} = {:.4} and {:.4}: RMS x {:.4} -> {:.4}",
            j.branch, a.param, j.from, j.to, j.rms_before, j.rms_after
        );
    }
    println!(
        "{} values, both sweeps -> {}",
        opts.values.len(),
        a.out.display()
    );
    Ok(())
}
