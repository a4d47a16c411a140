//! `geardyn report`.

use anyhow::Result;
use clap::Args;
use geardyn_io::config::assigns;
use geardyn_io::Config;
use std::path::PathBuf;

/// Arguments of `geardyn report`.
#[derive(Args, Debug)]
pub struct ReportArgs {
    /// Study plan and model: breakage (seed A), internal (seed B) or classic (case C1).
    #[arg(long, default_value = "breakage", value_parser = ["breakage", "internal", "classic"])]
    preset: String,
    /// Override a parameter of the preset: NAME=VALUE (repeatable).
    #[arg(long = "set", value_name = "NAME=VALUE")]
    sets: Vec<String>,
    /// Coarse version of every figure (well under a minute per preset).
    #[arg(long)]
    quick: bool,
    /// Output directory: the page goes into OUT/<preset>/, and OUT/index.html links every
    /// preset's page present (rerunning the same command resumes).
    #[arg(long, default_value = "out/report")]
    out: PathBuf,
    #[command(flatten)]
    decision: crate::sweep::DecisionArgs,
}

pub fn run(a: ReportArgs) -> Result<()> {
    let mut cfg = Config::preset(&a.preset)?;
    for s in &a.sets {
        cfg.apply_set(s)?;
    }
    // the decision flags (a field given by a flag and by --set is refused)
    a.decision
        .overrides()
        .apply(&mut cfg, &a.sets, geardyn_io::config::Face::Cli)?;
    cfg.resolve()?;
    let t = std::time::Instant::now();
    let index = geardyn_report::run(
        &cfg,
        &geardyn_report::ReportOptions {
            preset: a.preset.clone(),
            quick: a.quick,
            out: a.out.clone(),
            decision_given: (
                a.decision.decision_periods.is_some()
                    || a.sets.iter().any(|s| assigns(s, "decision_periods")),
                a.decision.decision_budget.is_some()
                    || a.sets.iter().any(|s| assigns(s, "decision_budget")),
            ),
        },
    )?;
    println!(
        "report for '{}' written in {:.1} s: {}",
        a.preset,
        t.elapsed().as_secs_f64(),
        index.display()
    );
    Ok(())
}
