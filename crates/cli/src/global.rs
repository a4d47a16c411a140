//! Global analyses: `geardyn basins`, `geardyn continuation`, `geardyn map2d`.

use crate::sweep::{parse_range, progress, InitialStatesArgs, RunArgs};
use anyhow::{bail, Context, Result};
use clap::Args;
use geardyn_analysis::attractor::{IdentifyOptions, IdentifyRequest};
use geardyn_analysis::basins::{Axis, BasinResult, BasinsRequest};
use geardyn_analysis::bifurcation::{range_values, MAX_RANGE_VALUES};
use geardyn_analysis::continuation::ContinuationResult;
use geardyn_exec::request::{ContinuationRequest, MapRequest};
use geardyn_exec::{execute, BasinsJob, Checkpointed, ContinuationJob, MapJob};
use geardyn_io::figure::LabelColors;
use geardyn_io::output::{write_csv, write_json};
use geardyn_io::schema::full;
use geardyn_io::{npy, run_record, sweep_output, Config};
use geardyn_scenario::Scenario;
use std::path::{Path, PathBuf};

/// Attractor-identification settings.
#[derive(Args, Debug)]
pub struct IdentArgs {
    /// Early-capture tolerance (state units); matching uses ten times it.
    #[arg(long, default_value_t = IdentifyRequest::DEFAULT.capture_tol)]
    capture_tol: f64,
    /// Integrate every cell for the whole transient (no early stop on a known attractor).
    #[arg(long)]
    no_early_stop: bool,
    /// Relative tolerance of the adaptive integrator for identification (the capture test
    /// needs ~1e-5 in the state; 1e-7 leaves a factor 100).
    #[arg(long, default_value_t = IdentifyRequest::DEFAULT.ident_rtol)]
    ident_rtol: f64,
}

impl IdentArgs {
    /// The library's request (which checks it, as Python's).
    pub(crate) fn request(&self) -> IdentifyRequest {
        IdentifyRequest {
            capture_tol: self.capture_tol,
            ident_rtol: self.ident_rtol,
            early_capture: !self.no_early_stop,
        }
    }

    /// The identification options on the configuration's simulation settings.
    fn options(&self, cfg: &Config) -> Result<IdentifyOptions> {
        Ok(self.request().options(cfg.sim_options()?)?)
    }
}

/// Arguments of `geardyn basins`.
#[derive(Args, Debug)]
pub struct BasinArgs {
    #[command(flatten)]
    pub(crate) run: RunArgs,
    #[command(flatten)]
    pub(crate) ident: IdentArgs,
    /// Grid axes: `--grid x:MIN:MAX:N --grid v:MIN:MAX:N` (default 200 x 200 over ±2 D, ±1.5).
    #[arg(
        long = "grid",
        allow_hyphen_values = true,
        value_name = "AXIS:MIN:MAX:N"
    )]
    grid: Vec<String>,
    /// Phase of the initial states as a fraction of the excitation period, in [0, 1).
    #[arg(long, default_value_t = 0.0)]
    pub(crate) phase: f64,
    /// Gear trains: the mesh whose deflection and deflection rate span the grid (its name, or
    /// its number from 1; default the first mesh), the other coordinates in the static state.
    #[arg(long)]
    pub(crate) mesh: Option<String>,
    /// Output directory (rerunning the same command there resumes).
    #[arg(long, default_value = "out/basins")]
    pub(crate) out: PathBuf,
}

/// Parses `x:MIN:MAX:N` or `v:MIN:MAX:N` (the limits are the library's: [`BasinsRequest`]).
fn parse_axis(s: &str) -> Result<(char, (f64, f64, usize))> {
    let parts: Vec<&str> = s.split(':').collect();
    if parts.len() != 4 || !(parts[0] == "x" || parts[0] == "v") {
        bail!("bad --grid '{s}': expected x:MIN:MAX:N or v:MIN:MAX:N");
    }
    let axis = crate::sweep::parse_numbers(
        &parts[1..].join(":"),
        &format!("--grid {}", parts[0]),
        "x:MIN:MAX:N or v:MIN:MAX:N",
    )?;
    Ok((parts[0].chars().next().unwrap_or('x'), axis))
}

impl BasinArgs {
    /// The grid as stated (`--grid`, `--phase`), before it is checked.
    pub(crate) fn request(&self) -> Result<BasinsRequest> {
        let mut req = BasinsRequest {
            phase: self.phase,
            ..Default::default()
        };
        for g in &self.grid {
            let (name, ax) = parse_axis(g)?;
            let slot = if name == 'x' { &mut req.x } else { &mut req.v };
            if slot.is_some() {
                bail!("--grid {name} given twice: give each axis once (x and v)");
            }
            *slot = Some(ax);
        }
        Ok(req)
    }

    /// One axis given: says what the other is, rather than silently running N x 200.
    pub(crate) fn note_default_axis(&self, req: &BasinsRequest, x: Axis, v: Axis) {
        if req.x.is_some() != req.v.is_some() {
            let (name, ax) = if req.x.is_some() { ("v", v) } else { ("x", x) };
            eprintln!(
                "note: no --grid {name}: {name} takes its default, [{}, {}] in {} cells",
                ax.min, ax.max, ax.n
            );
        }
    }
}

pub fn basins_cmd(a: BasinArgs, started: f64) -> Result<()> {
    if a.mesh.is_some() {
        bail!("--mesh picks the mesh of a gear train's basin plane; the pair's grid is its whole state (x0, x0')");
    }
    let (cfg, scenario) = a.run.resolve()?;
    let model = scenario.model();
    let req = a.request()?;
    let opts = req.options(model, a.ident.options(&cfg)?)?;
    a.note_default_axis(&req, opts.x, opts.v);
    cfg.check_work(model, &opts.identify.sim, opts.x.n * opts.v.n, false)?;
    let t = std::time::Instant::now();
    let r = execute(
        &BasinsJob { model, opts: &opts },
        Some(&mut Checkpointed::folder(&a.out, &cfg, a.run.force.force)?),
        &progress(&a.out),
    )?;
    let elapsed = t.elapsed().as_secs_f64();
    run_record::write_config_and_record(&a.out, "basins", &cfg, &scenario, &[], started)?;
    let title = format!(
        "Basins of attraction (initial phase {}): {}",
        a.phase,
        sweep_output::operating_point(&a.run.cfg.source(), scenario.params(), &[])
    );
    write_basins(&a.out, &r, &title, ("x0", "x0'"), serde_json::Map::new())?;
    print_basins(&r, elapsed, &a.out);
    Ok(())
}

/// Writes a basin result's files: basins.csv (`x0, v0, attractor`), basins.npy, attractors.json
/// (the result without its cells, with `extra` fields) and the figure, its axes `labels`.
pub(crate) fn write_basins(
    out: &Path,
    r: &BasinResult,
    title: &str,
    labels: (&str, &str),
    extra: serde_json::Map<String, serde_json::Value>,
) -> Result<()> {
    let (x, v) = (r.x, r.v);
    write_csv(
        &out.join("basins.csv"),
        &["x0", "v0", "attractor"],
        (0..x.n * v.n).map(|c| {
            vec![
                full(x.value(c % x.n)),
                full(v.value(c / x.n)),
                r.cells[c].to_string(),
            ]
        }),
    )?;
    npy::write_i64(&out.join("basins.npy"), &[v.n, x.n], &r.cells)?;
    // the cells are in basins.npy and basins.csv: a third copy in JSON made a 1000 x 1000
    // basin's attractors.json 7 MB
    let mut summary = serde_json::to_value(r)?;
    if let Some(m) = summary.as_object_mut() {
        m.remove("cells");
        m.extend(extra);
    }
    write_json(&out.join("attractors.json"), &summary)?;
    sweep_output::plot_basins(&out.join("basins"), title, r, labels)?;
    Ok(())
}

/// Prints the attractors and the grid's shares.
pub(crate) fn print_basins(r: &BasinResult, elapsed: f64, out: &Path) {
    let (x, v) = (r.x, r.v);
    for at in &r.attractors {
        println!(
            "attractor #{}: {}{}, {}, basin fraction {:.4}",
            at.id,
            at.descriptor.label,
            at.descriptor
                .mesh_period
                .map_or(String::new(), |m| format!(" [period {m} mesh cycles]")),
            geardyn_analysis::simulate::health_text(
                at.descriptor.healthy,
                at.descriptor.period > 0
            ),
            at.fraction
        );
    }
    println!(
        "{}x{} cells in {:.2} s ({:.0} cells/s), {} captured early; divergent {:.4}, failed {:.4}, boundary {:.4}{} -> {}",
        x.n,
        v.n,
        elapsed,
        (x.n * v.n) as f64 / elapsed,
        r.captured_early,
        r.diverged,
        r.failed,
        r.boundary_fraction,
        if r.inadmissible > 0.0 {
            format!(
                " (of the admissible cells; {:.4} of the grid lies behind the back stop and was not run)",
                r.inadmissible
            )
        } else {
            String::new()
        },
        out.display()
    );
}

/// Arguments of `geardyn continuation`.
#[derive(Args, Debug)]
pub struct ContinuationArgs {
    #[command(flatten)]
    pub(crate) run: RunArgs,
    #[command(flatten)]
    pub(crate) ident: IdentArgs,
    /// Parameter.
    #[arg(long, default_value = "omega")]
    pub(crate) param: String,
    /// START:STOP:COUNT.
    #[arg(long, allow_hyphen_values = true, default_value = "0.5:2:61")]
    pub(crate) range: String,
    /// Initial states per value.
    #[arg(long, default_value_t = ContinuationRequest::DEFAULT_ICS)]
    pub(crate) ics: usize,
    // seed and ranges of the initial states
    #[command(flatten)]
    pub(crate) initial: InitialStatesArgs,
    /// Phase of the initial states as a fraction of the excitation period, in [0, 1) (as for
    /// `basins`: each value's runs start at this phase of its own excitation period).
    #[arg(long, default_value_t = 0.0)]
    pub(crate) phase: f64,
    /// Gear trains: the mesh whose deflection and rate the initial states' box spans (its name,
    /// or its number from 1; default the first mesh), as for `basins`.
    #[arg(long)]
    pub(crate) mesh: Option<String>,
    /// Output directory (rerunning the same command there resumes).
    #[arg(long, default_value = "out/continuation")]
    pub(crate) out: PathBuf,
}

pub fn continuation_cmd(a: ContinuationArgs, started: f64) -> Result<()> {
    if a.mesh.is_some() {
        bail!("--mesh picks the mesh of a gear train's plane of initial states; the pair's are its whole state (x0, x0')");
    }
    let (cfg, scenario) = a.run.resolve()?;
    let values = parse_range(&a.range)?;
    let (x0_range, v0_range) = a.initial.ranges()?;
    let req = ContinuationRequest {
        param: a.param.clone(),
        values,
        ics: a.ics,
        seed: a.initial.seed,
        x0_range,
        v0_range,
        phase: a.phase,
        identify: a.ident.request(),
    };
    let opts = req.options(&cfg, &scenario)?;
    let r = execute(
        &ContinuationJob {
            scenario: &scenario,
            opts: &opts,
        },
        Some(&mut Checkpointed::folder(&a.out, &cfg, a.run.force.force)?),
        &progress(&a.out),
    )?;
    run_record::write_config_and_record(
        &a.out,
        "continuation",
        &cfg,
        &scenario,
        &[run_record::Swept::of(&a.param, &opts.values)],
        started,
    )?;
    let title = format!(
        "Attractor continuation over {} ({} initial states per value): {}",
        a.param,
        a.ics,
        sweep_output::operating_point(&a.run.cfg.source(), scenario.params(), &[&a.param])
    );
    write_continuation(&a.out, (&a.param, "x"), &opts.values, &r, &title)?;
    print_continuation(&a.param, &r, &a.out);
    Ok(())
}

/// Writes a continuation's files: continuation.csv (a row per attractor and value),
/// continuation.json and the figure.
pub(crate) fn write_continuation(
    out: &Path,
    (param, point): (&str, &str),
    values: &[f64],
    r: &ContinuationResult,
    title: &str,
) -> Result<()> {
    write_csv(
        &out.join("continuation.csv"),
        &[
            param,
            "branch",
            "label",
            "period",
            "healthy",
            "fraction",
            "max_force",
            "x",
            "v",
        ],
        r.points.iter().map(|p| {
            vec![
                full(p.value),
                p.branch.to_string(),
                p.label.clone(),
                p.period.to_string(),
                p.healthy.to_string(),
                full(p.fraction),
                full(p.max_force),
                full(p.x),
                full(p.v),
            ]
        }),
    )?;
    write_json(&out.join("continuation.json"), r)?;
    sweep_output::plot_continuation(
        &out.join("continuation"),
        title,
        (param, point),
        values,
        r,
        &mut LabelColors::default(),
    )?;
    Ok(())
}

/// Prints a continuation's intervals and events.
pub(crate) fn print_continuation(param: &str, r: &ContinuationResult, out: &Path) {
    for iv in &r.intervals {
        let fmt = |l: &Vec<(usize, String, f64, f64)>| {
            l.iter()
                .map(|e| format!("{} [{:.2}-{:.2}]", e.1, e.2, e.3))
                .collect::<Vec<_>>()
                .join(", ")
        };
        println!(
            "{} in [{:.4}, {:.4}]: healthy {{{}}} non-healthy (back-side contact or not periodic) {{{}}}",
            param,
            iv.from,
            iv.to,
            fmt(&iv.healthy),
            fmt(&iv.non_healthy)
        );
    }
    for e in &r.events {
        println!(
            "between {:.4} and {:.4}: {} ({})",
            e.from, e.to, e.text, e.kind
        );
    }
    println!("-> {}", out.display());
}

/// Arguments of `geardyn map2d`.
#[derive(Args, Debug)]
pub struct MapArgs {
    #[command(flatten)]
    pub(crate) run: RunArgs,
    /// x axis: NAME:START:STOP:COUNT.
    #[arg(long, allow_hyphen_values = true, default_value = "xi:0.001:0.3:40")]
    pub(crate) x: String,
    /// y axis: NAME:START:STOP:COUNT.
    #[arg(long, allow_hyphen_values = true, default_value = "F:0.001:0.2:40")]
    pub(crate) y: String,
    /// Metric of the heatmap: max_force, min_force, p_id, period, tle, healthy, class (gear
    /// trains: also dynamic_factor, load_sharing; no tle).
    #[arg(long, default_value = MapRequest::DEFAULT_METRIC)]
    pub(crate) metric: String,
    /// Output directory (rerunning the same command there resumes).
    #[arg(long, default_value = "out/map2d")]
    pub out: PathBuf,
}

pub(crate) fn parse_param_axis(s: &str, what: &str) -> Result<(String, Vec<f64>)> {
    let (name, rest) = s
        .split_once(':')
        .with_context(|| format!("bad {what} '{s}': expected NAME:START:STOP:COUNT"))?;
    let r = crate::sweep::parse_numbers(rest, what, "NAME:START:STOP:COUNT, e.g. omega:0.5:2:40")?;
    // (the axis named as Python names it: `x`, `y`)
    let axis = what.trim_start_matches('-');
    Ok((name.to_string(), range_values(axis, r, MAX_RANGE_VALUES)?))
}

impl MapArgs {
    /// The resolved request and its scenario: the one place `map2d` and `plan map2d` turn their
    /// flags into options (validated, the work checked against its cap).
    pub fn request(&self) -> Result<(MapRequest, Scenario)> {
        let (cfg, scenario) = self.run.resolve()?;
        let x = parse_param_axis(&self.x, "--x")?;
        let y = parse_param_axis(&self.y, "--y")?;
        let req = MapRequest::new(
            cfg,
            self.run.cfg.source(),
            &scenario,
            self.metric.clone(),
            x,
            y,
        )?;
        Ok((req, scenario))
    }
}

pub fn map_cmd(a: MapArgs, started: f64) -> Result<()> {
    let (req, scenario) = a.request()?;
    let opts = &req.options;
    let (nx, ny) = (opts.x_values.len(), opts.y_values.len());
    let t = std::time::Instant::now();
    let cells = execute(
        &MapJob {
            scenario: &scenario,
            opts,
        },
        Some(&mut Checkpointed::folder(
            &a.out,
            &req.config,
            a.run.force.force,
        )?),
        &progress(&a.out),
    )?;
    let (lo, hi) = req.write_folder(&a.out, &scenario, &cells, started)?;
    println!(
        "{}x{} cells in {:.2} s; {} in [{:.4}, {:.4}] -> {}",
        nx,
        ny,
        t.elapsed().as_secs_f64(),
        a.metric,
        lo,
        hi,
        a.out.display()
    );
    Ok(())
}
