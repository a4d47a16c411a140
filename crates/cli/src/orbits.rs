//! `geardyn orbits`: periodic orbits by shooting, their Floquet multipliers, and (with `--param`)
//! their branches and bifurcations.

use crate::run_config::ConfigArgs;
use crate::sweep::parse_range;
use anyhow::{bail, Result};
use clap::Args;
use geardyn_analysis::orbits::{
    continue_orbits, describe_orbit, find_orbit, BranchPoint, Continuation, ContinuationOptions,
    Orbit, OrbitOptions, MAX_ORBIT_PERIOD,
};
use geardyn_analysis::simulate::{simulate, summarize, SimOptions};
use geardyn_io::figure::{palette, write_figure, Figure, Layer, LegendEntry, Panel, Style};
use geardyn_io::output::{write_json, write_text};
use geardyn_io::run_record;
use geardyn_io::schema::{bifurcations_table, full, orbit_branch_table, OrbitRow};
use geardyn_scenario::Scenario;
use rayon::prelude::*;
use std::path::PathBuf;

/// Arguments of `geardyn orbits`.
#[derive(Args, Debug)]
pub struct OrbitArgs {
    #[command(flatten)]
    cfg: ConfigArgs,
    /// Excitation periods of the orbit sought; default: the period of the motion after the
    /// transient (which must then be periodic).
    #[arg(long)]
    period: Option<u32>,
    /// Excitation periods simulated from the initial state (`--set x0= --set v0=`) before
    /// Newton's method starts (0: start from the initial state itself).
    #[arg(long, default_value_t = 300)]
    transient: u64,
    /// Parameter continued (omega, F, xi, c, kappa, D, pair.mu, ...); without it, one orbit.
    #[arg(long)]
    param: Option<String>,
    /// START:STOP of the continuation (the first orbit is found at START).
    #[arg(long)]
    range: Option<String>,
    /// Largest arclength step of the continuation (scaled (x, x', parameter) space).
    #[arg(long, default_value_t = 0.02)]
    ds: f64,
    /// Most branch points in all.
    #[arg(long, default_value_t = 2000)]
    max_points: usize,
    /// Follow the doubled branch at each period doubling, up to this period (0: no switching).
    #[arg(long, default_value_t = 0)]
    switch_up_to: u32,
    /// Relative tolerance of the integration (absolute: 1e-2 times it).
    #[arg(long, default_value_t = 1e-11)]
    rtol: f64,
    /// Brute-force diagram drawn under the branches: values of the parameter over the range
    /// (simulated from the initial state, strobe points of the last 60 of 360 periods); 0: none.
    #[arg(long, default_value_t = 60)]
    diagram: usize,
    /// Output directory.
    #[arg(long, default_value = "out/orbits")]
    out: PathBuf,
}

/// The orbit's period read from the motion after the transient, or `None` when not periodic.
fn detected_period(sc: &Scenario, y: [f64; 2], tau0: f64) -> Result<Option<u32>> {
    let opts = SimOptions {
        transient_periods: 0,
        record_periods: 3 * 32,
        tau0,
        ..Default::default()
    };
    let res = simulate(sc.model(), y, &opts)?;
    let s = summarize(sc.model(), &res, &opts);
    Ok((s.period > 0).then_some(s.period as u32))
}

fn rows<'a>(
    sc: &Scenario,
    param: Option<&str>,
    pts: &'a [BranchPoint],
    tau0: f64,
) -> Vec<OrbitRow<'a>> {
    pts.par_iter()
        .map(|p| {
            let here = match param {
                Some(name) => sc.with(name, p.param).ok(),
                None => Some(sc.clone()),
            };
            let s = here.and_then(|m| describe_orbit(m.model(), &p.orbit, tau0).ok());
            OrbitRow {
                point: p,
                label: s.as_ref().map_or(String::new(), |s| s.label.clone()),
                max_force: s.as_ref().map_or(f64::NAN, |s| s.max_force),
                p_id: s.as_ref().map_or(f64::NAN, |s| s.p_id),
            }
        })
        .collect()
}

pub fn run(a: OrbitArgs) -> Result<()> {
    let started = run_record::now_unix_s();
    let (cfg, scenario) = a.cfg.resolve()?;
    if let Some(n) = a.period {
        if n == 0 || n > MAX_ORBIT_PERIOD {
            bail!("bad --period {n}: allowed 1 ..= {MAX_ORBIT_PERIOD}");
        }
    }
    if a.transient > geardyn_analysis::simulate::MAX_PERIODS {
        bail!(
            "bad --transient {}: allowed 0 ..= {}",
            a.transient,
            geardyn_analysis::simulate::MAX_PERIODS
        );
    }
    if !(a.ds > 0.0 && a.ds <= 1.0) {
        bail!(
            "bad --ds {}: allowed (0, 1]",
            geardyn_model::error::num(a.ds)
        );
    }
    if !(a.rtol >= 1e-14 && a.rtol <= 1e-6) {
        bail!(
            "bad --rtol {}: allowed [1e-14, 1e-6]",
            geardyn_model::error::num(a.rtol)
        );
    }
    if a.diagram > 2000 {
        bail!("bad --diagram {}: allowed 0 ..= 2000", a.diagram);
    }
    if a.max_points == 0 || a.max_points > 1_000_000 {
        bail!("bad --max-points {}: allowed 1 ..= 1000000", a.max_points);
    }
    if a.switch_up_to > MAX_ORBIT_PERIOD {
        bail!(
            "bad --switch-up-to {}: allowed 0 ..= {MAX_ORBIT_PERIOD}",
            a.switch_up_to
        );
    }
    let range = match (&a.param, &a.range) {
        (Some(p), Some(r)) => {
            let (lo, hi) = parse_two(r)?;
            scenario.with(p, lo)?;
            scenario.with(p, hi)?;
            Some((p.clone(), lo, hi))
        }
        (Some(_), None) => bail!("--param needs --range START:STOP"),
        (None, Some(_)) => bail!("--range needs --param NAME"),
        (None, None) => None,
    };
    let tau0 = cfg.simulation.tau0;
    let start_sc = match &range {
        Some((p, lo, _)) => scenario.with(p, *lo)?,
        None => scenario.clone(),
    };
    // the start: the initial state after the transient (near an attractor)
    let y0 = [cfg.simulation.x0, cfg.simulation.v0];
    let near = if a.transient > 0 {
        let opts = SimOptions {
            transient_periods: a.transient - 1,
            record_periods: 1,
            tau0,
            ..Default::default()
        };
        simulate(start_sc.model(), y0, &opts)?.final_state.1
    } else {
        y0
    };
    let period = match a.period {
        Some(n) => n,
        None => match detected_period(&start_sc, near, tau0)? {
            Some(n) => n,
            None => bail!(
                "the motion from x0 = {}, v0 = {} is not periodic after {} periods (within 32): \
                 give --period N to seek an orbit of N excitation periods (stable or not) near it",
                y0[0],
                y0[1],
                a.transient
            ),
        },
    };
    let orbit = OrbitOptions {
        period,
        tau0,
        rtol: a.rtol,
        atol: a.rtol * 1e-2,
        ..Default::default()
    };
    let lock = run_record::prepare_folder(&a.out, "orbits", None, false)?;
    let (result, param) = match &range {
        Some((p, lo, hi)) => {
            let opts = ContinuationOptions {
                param: p.clone(),
                start: *lo,
                stop: *hi,
                ds_max: a.ds,
                max_points: a.max_points,
                switch_up_to: a.switch_up_to,
                orbit,
            };
            let shown = std::sync::atomic::AtomicUsize::new(0);
            let c = continue_orbits(&scenario, near, &opts, &|pt| {
                let k = shown.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                if k.is_multiple_of(50) {
                    eprintln!(
                        "  branch {} point {k}: {p} = {:.6}, x = {:.6}, {}",
                        pt.branch,
                        pt.param,
                        pt.orbit.y[0],
                        if pt.orbit.stable {
                            "stable"
                        } else {
                            "unstable"
                        }
                    );
                }
            })?;
            (c, Some(p.as_str()))
        }
        None => {
            let o: Orbit = find_orbit(start_sc.model(), near, &orbit)?;
            let c = Continuation {
                points: vec![BranchPoint {
                    branch: 0,
                    param: f64::NAN,
                    orbit: o,
                }],
                ..Default::default()
            };
            (c, None)
        }
    };
    let table = rows(&scenario, param, &result.points, tau0);
    orbit_branch_table(param, &table).write_csv(&a.out.join("branch.csv"), full)?;
    if let Some(p) = param {
        bifurcations_table(p, &result.bifurcations)
            .write_csv(&a.out.join("bifurcations.csv"), full)?;
    }
    write_json(&a.out.join("orbits.json"), &result)?;
    write_text(&a.out.join("config.toml"), &cfg.to_toml())?;
    let swept: Vec<run_record::Swept> = match param {
        Some(p) => vec![run_record::Swept::of(
            p,
            &result.points.iter().map(|q| q.param).collect::<Vec<_>>(),
        )],
        None => Vec::new(),
    };
    if let Some((p, lo, hi)) = &range {
        let diagram = brute_force(&scenario, p, *lo, *hi, a.diagram, y0, tau0);
        plot(&a, &scenario, p, &result, &diagram)?;
    }
    run_record::write_sweep_record(
        &a.out,
        "orbits",
        &cfg,
        &scenario,
        &swept,
        started,
        run_record::now_unix_s() - started,
    )?;
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
        let (lo, hi, _) = parse_range(s)?;
        return Ok((lo, hi));
    }
    let bad = || anyhow::anyhow!("bad --range {s:?}: expected START:STOP with two finite numbers");
    if parts.len() != 2 {
        return Err(bad());
    }
    let lo: f64 = parts[0].trim().parse().map_err(|_| bad())?;
    let hi: f64 = parts[1].trim().parse().map_err(|_| bad())?;
    if !(lo.is_finite() && hi.is_finite()) || lo == hi {
        return Err(bad());
    }
    Ok((lo, hi))
}

/// Strobe points `(value, x)` of a plain simulation at `n` values of the range (300 + 60
/// periods from `y0`), for the figure.
fn brute_force(
    sc: &Scenario,
    param: &str,
    lo: f64,
    hi: f64,
    n: usize,
    y0: [f64; 2],
    tau0: f64,
) -> Vec<(f64, f64)> {
    if n == 0 {
        return Vec::new();
    }
    let values = geardyn_analysis::bifurcation::linspace(lo.min(hi), lo.max(hi), n.max(2));
    values
        .par_iter()
        .flat_map_iter(|&v| {
            let opts = SimOptions {
                transient_periods: 300,
                record_periods: 60,
                tau0,
                ..Default::default()
            };
            let pts: Vec<(f64, f64)> = sc
                .with(param, v)
                .ok()
                .and_then(|m| simulate(m.model(), y0, &opts).ok())
                .map(|r| r.strobe.iter().map(|p| (v, p[1])).collect())
                .unwrap_or_default();
            pts
        })
        .collect()
}

/// The branches (stable: solid lines, unstable: dots), the bifurcation points, and the
/// brute-force diagram in grey beneath.
fn plot(
    a: &OrbitArgs,
    sc: &Scenario,
    param: &str,
    c: &Continuation,
    diagram: &[(f64, f64)],
) -> Result<()> {
    let mut layers = Vec::new();
    let mut legend = Vec::new();
    if !diagram.is_empty() {
        let grey = plotters::style::RGBColor(120, 120, 120);
        layers.push(Layer {
            points: diagram.to_vec(),
            style: Style::Dots(1),
            color: grey,
        });
        legend.push(LegendEntry::dot("simulated (strobe)", grey));
    }
    // one colour per orbit period (the branches of one period share it)
    let mut periods: Vec<u32> = c.points.iter().map(|p| p.orbit.period).collect();
    periods.sort_unstable();
    periods.dedup();
    let branches = c.ends.len().max(1);
    for (k, &period) in periods.iter().enumerate() {
        let color = palette(k);
        let mut any_stable = false;
        let mut any_unstable = false;
        for b in 0..branches {
            let pts: Vec<&BranchPoint> = c
                .points
                .iter()
                .filter(|p| p.branch == b && p.orbit.period == period)
                .collect();
            if pts.is_empty() {
                continue;
            }
            // stable stretches as lines (a NaN breaks the line where the orbit is unstable),
            // unstable ones as dots
            let stable: Vec<(f64, f64)> = pts
                .iter()
                .map(|p| {
                    if p.orbit.stable {
                        (p.param, p.orbit.y[0])
                    } else {
                        (f64::NAN, f64::NAN)
                    }
                })
                .collect();
            let unstable: Vec<(f64, f64)> = pts
                .iter()
                .filter(|p| !p.orbit.stable)
                .map(|p| (p.param, p.orbit.y[0]))
                .collect();
            any_stable |= pts.iter().any(|p| p.orbit.stable);
            any_unstable |= !unstable.is_empty();
            layers.push(Layer {
                points: stable,
                style: Style::Line(2),
                color,
            });
            layers.push(Layer {
                points: unstable,
                style: Style::Dots(1),
                color,
            });
        }
        if any_stable {
            legend.push(LegendEntry::line(format!("period {period}, stable"), color));
        }
        if any_unstable {
            legend.push(LegendEntry::dot(
                format!("period {period}, unstable"),
                color,
            ));
        }
    }
    for (kind, color) in [
        ("period-doubling", plotters::style::RGBColor(200, 0, 0)),
        ("fold", plotters::style::RGBColor(0, 0, 0)),
        ("torus", plotters::style::RGBColor(128, 0, 160)),
        ("grazing", plotters::style::RGBColor(0, 140, 60)),
    ] {
        let pts: Vec<(f64, f64)> = c
            .bifurcations
            .iter()
            .filter(|b| b.kind.name() == kind)
            .map(|b| (b.param, b.orbit.y[0]))
            .collect();
        if !pts.is_empty() {
            layers.push(Layer {
                points: pts,
                style: Style::Dots(4),
                color,
            });
            legend.push(LegendEntry::dot(kind, color));
        }
    }
    let fig = Figure {
        title: format!(
            "Periodic orbits over {param}: {} ({})",
            a.cfg.source(),
            // the operating point without the swept parameter
            geardyn_io::describe::operating_point(sc)
                .split(", ")
                .filter(|s| !s.starts_with(&format!("{param} =")))
                .collect::<Vec<_>>()
                .join(", ")
        ),
        x_label: param.to_string(),
        panels: vec![Panel {
            y_label: "x at the strobe".into(),
            layers,
            weight: 1.6,
            ..Default::default()
        }],
        legend,
        ..Default::default()
    };
    write_figure(&a.out.join("branch"), &fig)?;
    Ok(())
}
