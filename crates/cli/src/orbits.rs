//! `geardyn orbits`: periodic orbits by shooting, their Floquet multipliers, and (with `--param`)
//! their branches and bifurcations.

use crate::run_config::ConfigArgs;
use crate::sweep::parse_numbers;
use anyhow::{bail, Result};
use clap::Args;
use geardyn_analysis::bifurcation::{range_values, MAX_RANGE_VALUES};
use geardyn_analysis::orbit_branches::BranchPoint;
use geardyn_analysis::orbits_request::{strobe_diagram, OrbitsRequest};
use geardyn_exec::{execute, Each, OrbitsJob};
use geardyn_io::output::write_json;
use geardyn_io::run_record;
use geardyn_io::schema::{bifurcations_table, full, orbit_branch_table, orbit_rows};
use std::path::PathBuf;

/// Values of the brute-force diagram under a branch by default.
pub(crate) const DEFAULT_DIAGRAM: usize = 60;

/// Arguments of `geardyn orbits`.
#[derive(Args, Debug)]
pub struct OrbitArgs {
    #[command(flatten)]
    pub(crate) cfg: ConfigArgs,
    /// Excitation periods of the orbit sought; default: the period of the motion after the
    /// transient (which must then be periodic).
    #[arg(long)]
    pub(crate) period: Option<u32>,
    /// Excitation periods simulated from the initial state (`--set x0= --set v0=`) before
    /// Newton's method starts (0: start from the initial state itself).
    #[arg(long, default_value_t = OrbitsRequest::default().transient)]
    pub(crate) transient: u64,
    /// Parameter continued (omega, F, xi, c, kappa, D, pair.mu, ...); without it, one orbit.
    #[arg(long)]
    pub(crate) param: Option<String>,
    /// START:STOP of the continuation (the first orbit is found at START; a gear train's:
    /// START:STOP[:COUNT], the values it is followed at, default 41).
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) range: Option<String>,
    /// Largest arclength step of the continuation (scaled (x, x', parameter) space).
    #[arg(long, default_value_t = OrbitsRequest::default().ds)]
    pub(crate) ds: f64,
    /// Most branch points in all.
    #[arg(long, default_value_t = OrbitsRequest::default().max_points)]
    pub(crate) max_points: usize,
    /// Follow the doubled branch at each period doubling, up to this period (0: no switching).
    #[arg(long, default_value_t = OrbitsRequest::default().switch_up_to)]
    pub(crate) switch_up_to: u32,
    /// Relative tolerance of the integration (absolute: 1e-2 times it).
    #[arg(long, default_value_t = OrbitsRequest::default().rtol)]
    pub(crate) rtol: f64,
    /// Brute-force diagram drawn under the branches: values of the parameter over the range
    /// (simulated from the initial state, strobe points of the last 60 of 360 periods); 0: none.
    #[arg(long, default_value_t = DEFAULT_DIAGRAM)]
    pub(crate) diagram: usize,
    /// Output directory.
    #[arg(long, default_value = "out/orbits")]
    pub(crate) out: PathBuf,
}

pub fn run(a: OrbitArgs, started: f64) -> Result<()> {
    let (cfg, scenario) = a.cfg.resolve()?;
    if a.diagram > 2000 {
        bail!("bad --diagram {}: allowed 0 ..= 2000", a.diagram);
    }
    let range = match (&a.param, &a.range) {
        (Some(p), Some(r)) => {
            let (lo, hi) = parse_two(r)?;
            Some((p.clone(), lo, hi))
        }
        (Some(_), None) => bail!("--param needs --range START:STOP"),
        (None, Some(_)) => bail!("--range needs --param NAME"),
        (None, None) => None,
    };
    let tau0 = cfg.simulation.tau0;
    let y0 = [cfg.simulation.x0, cfg.simulation.v0];
    let req = OrbitsRequest {
        range: range.clone(),
        period: a.period,
        transient: a.transient,
        y0,
        tau0,
        ds: a.ds,
        max_points: a.max_points,
        switch_up_to: a.switch_up_to,
        rtol: a.rtol,
    };
    // every setting is checked before the folder is touched
    req.check(&scenario)?;
    let lock = run_record::prepare_folder(&a.out, "orbits", None, false)?;
    let shown = std::sync::atomic::AtomicUsize::new(0);
    let job = OrbitsJob {
        scenario: &scenario,
        request: &req,
    };
    let result = execute(
        &job,
        None,
        &Each(|pt: &BranchPoint| {
            let k = shown.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            if k > 0 && k.is_multiple_of(100) {
                eprintln!(
                    "  {k} orbits; branch {} at {} = {:.6}",
                    pt.branch,
                    a.param.as_deref().unwrap_or("-"),
                    pt.param
                );
            }
        }),
    )?;
    let param = range.as_ref().map(|r| r.0.as_str());
    let table = orbit_rows(&scenario, param, &result.points, tau0);
    // a rerun in the folder replaces what an earlier run wrote and this one does not
    for stale in ["bifurcations.csv", "branch.png", "branch.svg"] {
        let f = a.out.join(stale);
        if f.is_file() {
            std::fs::remove_file(&f)?;
        }
    }
    orbit_branch_table(param, &table).write_csv(&a.out.join("branch.csv"), full)?;
    if let Some(p) = param {
        bifurcations_table(p, &result.bifurcations)
            .write_csv(&a.out.join("bifurcations.csv"), full)?;
    }
    write_json(&a.out.join("orbits.json"), &result)?;
    let swept: Vec<run_record::Swept> = match param {
        Some(p) => vec![run_record::Swept::of(
            p,
            &result.points.iter().map(|q| q.param).collect::<Vec<_>>(),
        )],
        None => Vec::new(),
    };
    if let Some((p, lo, hi)) = &range {
        let diagram = strobe_diagram(&scenario, p, *lo, *hi, a.diagram, y0, tau0);
        let title = format!(
            "Periodic orbits over {p}: {} ({})",
            a.cfg.source(),
            geardyn_io::describe::operating_point_without(&scenario, p)
        );
        geardyn_io::sweep_output::plot_orbits(&a.out.join("branch"), &title, p, &result, &diagram)?;
    }
    run_record::write_config_and_record(&a.out, "orbits", &cfg, &scenario, &swept, started)?;
    drop(lock);
    // what was found, in words
    match param {
        None => {
            let o = &result.points[0].orbit;
            let r = &table[0];
            println!(
                "period-{} orbit {}: x = {}, x' = {}, multipliers {} and {} ({}), label {}, max force {}, P_ID {}",
                o.period,
                a.cfg.source(),
                o.y[0],
                o.y[1],
                mu_text(o.multipliers[0]),
                mu_text(o.multipliers[1]),
                if o.stable { "stable" } else { "unstable" },
                r.label,
                r.max_force,
                r.p_id
            );
        }
        Some(p) => {
            println!(
                "{} orbits on {} branch(es) over {p}; {} bifurcation(s):",
                result.points.len(),
                result.ends.len(),
                result.bifurcations.len()
            );
            for b in &result.bifurcations {
                println!(
                    "  {} of the period-{} branch at {p} = {} (x = {}, multipliers {}, {})",
                    b.kind.name(),
                    b.orbit.period,
                    b.param,
                    b.orbit.y[0],
                    mu_text(b.orbit.multipliers[0]),
                    mu_text(b.orbit.multipliers[1])
                );
                for n in &b.branches {
                    println!(
                        "    an orbit branches off: at {p} = {} x = {} (multipliers {}, {})",
                        n.param,
                        n.orbit.y[0],
                        mu_text(n.orbit.multipliers[0]),
                        mu_text(n.orbit.multipliers[1])
                    );
                }
            }
            for e in &result.ends {
                println!("  {e}");
            }
        }
    }
    println!("-> {}", a.out.display());
    Ok(())
}

fn mu_text(m: geardyn_analysis::orbits::Multiplier) -> String {
    if m.im == 0.0 {
        format!("{:.6}", m.re)
    } else {
        format!("{:.6}{:+.6}i", m.re, m.im)
    }
}

/// `START:STOP` (or `START:STOP:COUNT`, the count ignored: a continuation chooses its steps).
fn parse_two(s: &str) -> Result<(f64, f64)> {
    let parts: Vec<&str> = s.split(':').collect();
    if parts.len() == 3 {
        let (lo, hi, n) = parse_numbers(s, "--range", "START:STOP or START:STOP:COUNT")?;
        // (checked as any range, though the count is not used)
        range_values("range", (lo, hi, n), MAX_RANGE_VALUES)?;
        return Ok((lo, hi));
    }
    let bad = || anyhow::anyhow!("bad --range {s:?}: expected START:STOP with two finite numbers");
    if parts.len() != 2 {
        return Err(bad());
    }
    let lo: f64 = parts[0].trim().parse().map_err(|_| bad())?;
    let hi: f64 = parts[1].trim().parse().map_err(|_| bad())?;
    if !(lo.is_finite() && hi.is_finite()) {
        return Err(bad());
    }
    if lo == hi {
        anyhow::bail!("bad --range {s:?}: START and STOP are equal; a continuation needs two different values");
    }
    Ok((lo, hi))
}
