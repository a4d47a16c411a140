//! Shared machinery of the sweep commands: simulation arguments, ranges, checkpointed parallel
//! execution with a progress bar.

use anyhow::{bail, Context, Result};
use clap::Args;
use geardyn_analysis::bifurcation::{run_sweep, tasks, SweepOptions, Task, TaskResult};
use geardyn_io::checkpoint::Checkpoint;
use geardyn_io::Config;
use indicatif::{ProgressBar, ProgressStyle};
use std::collections::HashMap;
use std::path::Path;
use std::sync::Mutex;

/// Integration settings on the command line (override the config's `[simulation]`).
#[derive(Args, Debug, Clone)]
pub struct SimArgs {
    /// Recorded excitation periods per run.
    #[arg(long)]
    pub periods: Option<u64>,
    /// Transient excitation periods discarded per run.
    #[arg(long)]
    pub transient: Option<u64>,
    /// Integrator: dopri (adaptive, default) or rk4 (fixed step).
    #[arg(long, value_parser = ["dopri", "rk4"])]
    pub integrator: Option<String>,
    /// RK4 steps per mesh cycle.
    #[arg(long)]
    pub steps_per_cycle: Option<u32>,
}

impl SimArgs {
    /// Applies the overrides to the config.
    pub fn apply(&self, cfg: &mut Config) -> Result<()> {
        if let Some(p) = self.periods {
            cfg.set("record_periods", p as f64)?;
        }
        if let Some(t) = self.transient {
            cfg.set("transient_periods", t as f64)?;
        }
        if let Some(m) = &self.integrator {
            cfg.simulation.method = m.clone();
        }
        if let Some(n) = self.steps_per_cycle {
            cfg.set("steps_per_cycle", n as f64)?;
        }
        cfg.sim_options()?;
        Ok(())
    }
}

/// Parses `START:STOP:COUNT`.
pub fn parse_range(s: &str) -> Result<(f64, f64, usize)> {
    let parts: Vec<&str> = s.split(':').collect();
    if parts.len() != 3 {
        bail!("bad --range '{s}': expected START:STOP:COUNT, e.g. 0.5:2:200");
    }
    let a: f64 = parts[0]
        .trim()
        .parse()
        .with_context(|| format!("bad --range start '{}'", parts[0]))?;
    let b: f64 = parts[1]
        .trim()
        .parse()
        .with_context(|| format!("bad --range stop '{}'", parts[1]))?;
    let n: usize = parts[2]
        .trim()
        .parse()
        .with_context(|| format!("bad --range count '{}': a positive integer", parts[2]))?;
    if !(a.is_finite() && b.is_finite()) || n == 0 || n > 1_000_000 {
        bail!("bad --range '{s}': finite START, STOP and 1 <= COUNT <= 1000000");
    }
    Ok((a, b, n))
}

/// Parses `MIN:MAX`.
pub fn parse_pair(s: &str, what: &str) -> Result<(f64, f64)> {
    let (a, b) = s
        .split_once(':')
        .with_context(|| format!("bad {what} '{s}': expected MIN:MAX"))?;
    let a: f64 = a
        .trim()
        .parse()
        .with_context(|| format!("bad {what} '{s}'"))?;
    let b: f64 = b
        .trim()
        .parse()
        .with_context(|| format!("bad {what} '{s}'"))?;
    if !(a.is_finite() && b.is_finite() && a <= b) {
        bail!("bad {what} '{s}': finite MIN <= MAX");
    }
    Ok((a, b))
}

/// Runs a sweep with a checkpoint in `out` and a progress bar on stderr.
pub fn run_checkpointed(
    cfg: &Config,
    opts: &SweepOptions,
    out: &Path,
    kind: &str,
) -> Result<Vec<TaskResult>> {
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    let key =
        serde_json::to_string(&serde_json::json!({ "kind": kind, "config": cfg, "sweep": opts }))?;
    let (cp, done) = Checkpoint::open::<TaskResult>(&out.join("checkpoint.jsonl"), &key)?;
    let done: HashMap<Task, TaskResult> = done.into_iter().map(|r| (r.task, r)).collect();
    let total = tasks(opts).len() as u64;
    let pb = ProgressBar::new(total);
    pb.set_style(
        ProgressStyle::with_template(
            "{msg} [{bar:40}] {pos}/{len} values, {elapsed} elapsed, ETA {eta}",
        )
        .expect("valid template")
        .progress_chars("=> "),
    );
    pb.set_message(kind.to_string());
    if !done.is_empty() {
        eprintln!(
            "resuming: {} of {total} values already computed in {}",
            done.len(),
            out.display()
        );
        pb.set_position(done.len() as u64);
        pb.reset_eta();
    }
    let write_err = Mutex::new(None);
    let results = run_sweep(&cfg.model, opts, &done, |r| {
        if let Err(e) = cp.append(r) {
            write_err
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .get_or_insert(e);
        }
        pb.inc(1);
    })?;
    pb.finish_and_clear();
    if let Some(e) = write_err.into_inner().unwrap_or_else(|e| e.into_inner()) {
        return Err(e.into());
    }
    Ok(results)
}
