//! `geardyn._geardyn`: the Rust half of the Python package. Every function mirrors a `geardyn`
//! command of the CLI (crates/cli) on the same library calls and with the same defaults, so that
//! Python and the CLI give the same numbers for the same inputs. The pure-Python wrapper
//! (`geardyn/__init__.py`) adds keyword arguments, docstrings and result objects.

mod util;

use anyhow::{bail, Context, Result};
use geardyn_analysis::attractor::{IdentifyOptions, IdentifyRequest, Outcome};
use geardyn_analysis::basins::BasinsRequest;
use geardyn_analysis::bifurcation::{
    detect_jumps, range_values, SweepOptions, TaskResult, MAX_RANGE_VALUES,
};
use geardyn_analysis::continuation::ValueAttractors;
use geardyn_analysis::lyapunov_request::{LyapunovRequest, TleMethod};
use geardyn_analysis::map2d::MapCell;
use geardyn_exec::request::{BifurcationRequest, ContinuationRequest, SweepSpec};
use geardyn_exec::shard;
use geardyn_exec::{execute, BasinsJob, Checkpointed, ContinuationJob, MapJob, SweepJob};
use geardyn_io::config::{assigns, Face, SimOverrides};
use geardyn_io::Config;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use util::{arr1, arr2, json_to_py, ser_to_py, to_pyerr, Columns, Ctl};

/// Where a configuration comes from: a preset, a TOML file, or a configuration as JSON (the dict
/// `geardyn.config()` returns), then `NAME=VALUE` overrides in order (as `--set`).
#[derive(Clone, Debug, FromPyObject)]
#[pyo3(from_item_all)]
struct Source {
    preset: Option<String>,
    config_path: Option<String>,
    config_json: Option<String>,
    sets: Vec<String>,
    contact: Option<String>,
}

impl Source {
    /// What the model comes from, for figure titles (as `ConfigArgs::source` of the CLI).
    fn source(&self) -> String {
        match (&self.preset, &self.config_path, &self.config_json) {
            (_, Some(path), _) => format!("config {path}"),
            (_, None, Some(_)) => "config dict".into(),
            (Some(name), None, None) => format!("preset {name}"),
            (None, None, None) => "preset classic".into(),
        }
    }

    /// The configuration with all overrides applied (as `ConfigArgs::config` of the CLI).
    fn config(&self) -> Result<Config> {
        let mut c = match (&self.preset, &self.config_path, &self.config_json) {
            (Some(_), Some(_), _) | (Some(_), _, Some(_)) => {
                bail!("preset and config exclude each other: give one of them")
            }
            (_, Some(path), _) => Config::from_file(std::path::Path::new(path))?,
            (_, None, Some(json)) => {
                let v: serde_json::Value =
                    serde_json::from_str(json).context("malformed config dict")?;
                let t = toml::Value::try_from(v)
                    .map_err(|e| anyhow::anyhow!("malformed config dict: {e}"))?;
                let text = toml::to_string(&t)
                    .map_err(|e| anyhow::anyhow!("malformed config dict: {e}"))?;
                Config::from_toml(&text)?
            }
            (Some(name), None, None) => Config::preset(name)?,
            (None, None, None) => Config::preset("classic")?,
        };
        if let Some(law) = &self.contact {
            c.apply_contact(law)?;
        }
        for s in &self.sets {
            c.apply_set(s)?;
        }
        Ok(c)
    }
}

/// Integration settings of the sweep commands (the CLI's `SimArgs`).
#[derive(Clone, Debug, Default, FromPyObject)]
#[pyo3(from_item_all)]
struct Sim {
    periods: Option<f64>,
    transient: Option<f64>,
    integrator: Option<String>,
    steps_per_cycle: Option<f64>,
}

impl Sim {
    /// Applies the settings; `sets` are the call's `set=` assignments (a field given by both is
    /// refused, as in the CLI).
    fn apply(&self, cfg: &mut Config, sets: &[String]) -> Result<()> {
        let o = SimOverrides {
            periods: self.periods,
            transient: self.transient,
            integrator: self.integrator.clone(),
            steps_per_cycle: self.steps_per_cycle,
            ..Default::default()
        };
        Ok(o.apply(cfg, sets, Face::Python)?)
    }
}

/// Attractor-identification settings (the CLI's `IdentArgs`, same defaults).
#[derive(Clone, Debug, FromPyObject)]
#[pyo3(from_item_all)]
struct Ident {
    capture_tol: f64,
    early_stop: bool,
    ident_rtol: f64,
}

impl Ident {
    /// The library's request (which checks it, as the CLI's).
    fn request(&self) -> IdentifyRequest {
        IdentifyRequest {
            capture_tol: self.capture_tol,
            ident_rtol: self.ident_rtol,
            early_capture: self.early_stop,
        }
    }

    /// The identification options on the configuration's simulation settings.
    fn options(&self, cfg: &Config) -> Result<IdentifyOptions> {
        Ok(self.request().options(cfg.sim_options()?)?)
    }
}

/// Parameter values: explicit, or `(start, stop, count)` through the library's `linspace` (the
/// CLI's `--range`).
fn values_of(values: Option<Vec<f64>>, range: Option<(f64, f64, usize)>) -> Result<Vec<f64>> {
    values_named("range", values, range)
}

/// [`values_of`] of an axis called `name` in messages (a map's `x`, `y`).
fn values_named(
    name: &str,
    values: Option<Vec<f64>>,
    range: Option<(f64, f64, usize)>,
) -> Result<Vec<f64>> {
    match (values, range) {
        (Some(_), Some(_)) => bail!("values and range exclude each other: give one of them"),
        (Some(v), None) => {
            if v.is_empty() || v.len() > 1_000_000 {
                bail!("bad values: 1 to 1000000 values");
            }
            if let Some(x) = v.iter().find(|x| !x.is_finite()) {
                bail!(
                    "bad values: {} is not finite",
                    geardyn_model::error::num(*x)
                );
            }
            Ok(v)
        }
        (None, Some(r)) => Ok(range_values(name, r, MAX_RANGE_VALUES)?),
        (None, None) => {
            bail!("give the parameter values: values=[...] or range=(start, stop, count)")
        }
    }
}

fn config_py<'py>(py: Python<'py>, cfg: &Config) -> PyResult<Bound<'py, PyAny>> {
    ser_to_py(py, &cfg.to_value())
}

/// `geardyn presets`: `[(name, description)]`.
#[pyfunction]
fn presets() -> Vec<(String, String)> {
    geardyn_model::presets::PRESETS
        .iter()
        .map(|(n, w)| (n.to_string(), w.to_string()))
        .collect()
}

/// Names accepted as parameters (`--set` names besides `pair.*`).
#[pyfunction]
fn parameter_names() -> Vec<String> {
    geardyn_model::PARAMETER_NAMES
        .iter()
        .chain(geardyn_io::config::SIMULATION_NAMES)
        .map(|s| s.to_string())
        .collect()
}

/// `geardyn show` (the TOML part): the resolved configuration as a dict, or as the TOML text.
#[pyfunction]
fn config<'py>(py: Python<'py>, src: Source, as_toml: bool) -> PyResult<Bound<'py, PyAny>> {
    let (cfg, _) = resolve(&src).map_err(to_pyerr)?;
    if as_toml {
        Ok(pyo3::types::PyString::new(py, &cfg.to_toml()).into_any())
    } else {
        config_py(py, &cfg)
    }
}

fn resolve(src: &Source) -> Result<(Config, geardyn_scenario::Scenario)> {
    let c = src.config()?;
    let s = c.resolve().context("configuration rejected")?;
    Ok((c, s))
}

/// `geardyn show` (the comment part): derived quantities.
#[pyfunction]
fn derived<'py>(py: Python<'py>, src: Source) -> PyResult<Bound<'py, PyAny>> {
    let (_, s) = resolve(&src).map_err(to_pyerr)?;
    let text = geardyn_io::describe::describe(&s).map_err(|e| to_pyerr(e.into()))?;
    let d = PyDict::new(py);
    d.set_item("parameters", ser_to_py(py, &s.record())?)?;
    let model = s.model();
    d.set_item("excitation_period", model.excitation_period())?;
    d.set_item("cycles_per_period", model.cycles_per_period())?;
    d.set_item("mesh_cycle_time", model.mesh_cycle_time())?;
    let (dd, ds) = model.backlash_levels();
    d.set_item("backlash_levels", (dd, ds))?;
    if let Some(pm) = s.pair_model() {
        let g = &pm.geom;
        let pair = PyDict::new(py);
        pair.set_item("eps", g.eps)?;
        pair.set_item("eps_b", pm.eps_b)?;
        pair.set_item("centre_distance_mm", g.a_w * 1e3)?;
        pair.set_item("operating_pressure_angle_deg", g.alpha_w.to_degrees())?;
        pair.set_item("base_pitch_mm", g.pb * 1e3)?;
        pair.set_item("path_of_contact_mm", (g.s_d - g.s_a) * 1e3)?;
        pair.set_item("k_av_n_per_m", pm.k_av)?;
        pair.set_item("m_e_kg", pm.m_e)?;
        pair.set_item("i_p_kg_m2", pm.i_p)?;
        pair.set_item("i_g_kg_m2", pm.i_g)?;
        pair.set_item("omega_n_rad_per_s", pm.omega_n)?;
        pair.set_item("b_c_um", pm.b_c * 1e6)?;
        pair.set_item("cycles", pm.cycles)?;
        pair.set_item("physical_backlash", pm.backlash)?;
        let p = s.params();
        let op = pm.to_physical(&geardyn_physics::pair::Dimensionless {
            omega: p.omega,
            load: p.load,
            xi: p.xi,
            d: p.d_single,
        });
        pair.set_item("operating_point", ser_to_py(py, &op)?)?;
        d.set_item("pair", pair)?;
    } else {
        d.set_item("pair", py.None())?;
    }
    let lines: Vec<String> = text
        .lines()
        .map(|l| l.trim_start_matches('#').trim().to_string())
        .filter(|l| !l.is_empty() && !l.starts_with("---"))
        .collect();
    d.set_item("text", lines)?;
    Ok(d.into_any())
}

/// `geardyn simulate` without the files: the same run, returned.
#[pyfunction]
#[pyo3(signature = (src, periods, transient, integrator, trajectory_periods, progress, out))]
#[allow(clippy::too_many_arguments)]
fn simulate<'py>(
    py: Python<'py>,
    src: Source,
    periods: Option<f64>,
    transient: Option<f64>,
    integrator: Option<String>,
    trajectory_periods: Option<u64>,
    progress: bool,
    out: Option<std::path::PathBuf>,
) -> PyResult<Bound<'py, PyAny>> {
    let out = util::run(py, "simulate", progress, None, move |_ctl: &Ctl| {
        let mut cfg = src.config()?;
        Sim {
            periods,
            transient,
            integrator,
            steps_per_cycle: None,
        }
        .apply(&mut cfg, &src.sets)?;
        let source = src.source();
        let job = geardyn_exec::SimulateJob {
            config: &cfg,
            source: &source,
            trajectory_periods,
            out: out.as_deref(),
        };
        let run = execute(&job, None, &())?;
        // summary.json of the CLI
        let mut v = serde_json::to_value(&run.summary)?;
        if let (Some(obj), serde_json::Value::Object(more)) = (
            v.as_object_mut(),
            geardyn_io::simulate_folder::summary_extra(&run.finished()),
        ) {
            obj.extend(more);
        }
        let model = run.scenario.model();
        let (period, levels) = (model.excitation_period(), model.backlash_levels());
        let description = run.summary.describe();
        Ok((run.cfg, run.res, v, period, levels, description))
    })?;
    let (cfg, res, summary, period, levels, description) = out;
    let d = PyDict::new(py);
    let n = res.strobe.len();
    d.set_item(
        "strobe",
        arr2(
            py,
            res.strobe
                .iter()
                .flat_map(|p| [p.tau, p.y[0], p.y[1]])
                .collect(),
            n,
            3,
        )?,
    )?;
    let tr = Columns::new(py);
    tr.f64("tau", res.mesh().trajectory.iter().map(|p| p.tau).collect())?;
    tr.f64("x", res.mesh().trajectory.iter().map(|p| p.x).collect())?;
    tr.f64("v", res.mesh().trajectory.iter().map(|p| p.v).collect())?;
    tr.f64(
        "mesh_force",
        res.mesh().trajectory.iter().map(|p| p.mesh_force).collect(),
    )?;
    d.set_item(
        "trajectory_state",
        arr1(
            py,
            res.mesh()
                .trajectory
                .iter()
                .map(|p| p.state)
                .collect::<Vec<i8>>(),
        ),
    )?;
    tr.dict.set_item("state", d.get_item("trajectory_state")?)?;
    d.del_item("trajectory_state")?;
    d.set_item("trajectory", tr.dict)?;
    let ev = Columns::new(py);
    ev.f64("tau", res.mesh().events.iter().map(|e| e.tau).collect())?;
    ev.f64(
        "cycle_position",
        res.mesh().events.iter().map(|e| e.cycle_position).collect(),
    )?;
    ev.str(
        "kind",
        res.mesh()
            .events
            .iter()
            .map(|e| {
                serde_json::to_value(e.kind)
                    .ok()
                    .and_then(|v| v.as_str().map(str::to_string))
                    .unwrap_or_default()
            })
            .collect(),
    )?;
    ev.f64("x", res.mesh().events.iter().map(|e| e.x).collect())?;
    ev.f64(
        "v_before",
        res.mesh().events.iter().map(|e| e.v_before).collect(),
    )?;
    ev.f64(
        "v_after",
        res.mesh().events.iter().map(|e| e.v_after).collect(),
    )?;
    ev.f64(
        "peak_force",
        res.mesh().events.iter().map(|e| e.peak_force).collect(),
    )?;
    d.set_item("events", ev.dict)?;
    let se = Columns::new(py);
    se.str(
        "section",
        res.mesh()
            .crossings
            .iter()
            .map(|c| c.level.name().to_string())
            .collect(),
    )?;
    se.f64("tau", res.mesh().crossings.iter().map(|c| c.tau).collect())?;
    se.f64("x", res.mesh().crossings.iter().map(|c| c.x).collect())?;
    se.f64("v", res.mesh().crossings.iter().map(|c| c.v).collect())?;
    d.set_item("sections", se.dict)?;
    d.set_item("summary", json_to_py(py, &summary)?)?;
    d.set_item("description", description)?;
    if res.mesh_strobe.is_empty() {
        d.set_item("mesh_strobe", arr2(py, Vec::<f64>::new(), 0, 2)?)?;
    } else {
        let m = res.mesh_strobe.len();
        d.set_item(
            "mesh_strobe",
            arr2(
                py,
                res.mesh_strobe.iter().flatten().copied().collect(),
                m,
                2,
            )?,
        )?;
    }
    d.set_item(
        "impact_force_per_period",
        arr1(py, res.mesh().impact_force_per_period.clone()),
    )?;
    d.set_item("amplitudes", ser_to_py(py, &res.amplitudes())?)?;
    d.set_item(
        "final_state",
        (
            res.final_state.0,
            res.final_state.1[0],
            res.final_state.1[1],
        ),
    )?;
    d.set_item("excitation_period", period)?;
    d.set_item("backlash_levels", levels)?;
    d.set_item("config", config_py(py, &cfg)?)?;
    Ok(d.into_any())
}

/// `geardyn lyapunov`.
#[pyfunction]
#[pyo3(signature = (src, sim, method, max_periods, d0, progress))]
fn lyapunov<'py>(
    py: Python<'py>,
    src: Source,
    sim: Sim,
    method: String,
    max_periods: u64,
    d0: f64,
    progress: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let v = util::run(py, "lyapunov", progress, None, move |_ctl: &Ctl| {
        let method = TleMethod::from_name(&method)?;
        let mut cfg = src.config()?;
        sim.apply(&mut cfg, &src.sets)?;
        let scenario = cfg.resolve()?;
        let so = cfg.sim_options()?;
        let req = LyapunovRequest {
            method,
            periods: sim.periods.map(|_| so.record_periods),
            max_periods,
            d0,
        };
        req.check()?;
        let p = scenario.params();
        let integrated = serde_json::json!({
            "omega": p.omega, "F": p.load, "xi": p.xi, "c": p.c, "D_d": p.d_double, "D_s": p.d_single,
        });
        let y0 = [cfg.simulation.x0, cfg.simulation.v0];
        let job = geardyn_exec::LyapunovJob {
            model: scenario.model(),
            sim: &so,
            y0,
            request: &req,
        };
        let r = execute(&job, None, &())?;
        let c = r.convergence.as_ref();
        Ok(serde_json::json!({
            "method": method.name(), "integrated": integrated,
            "converged": c.map(|c| c.converged), "tol": c.map(|c| c.tol),
            "rounds": c.map(|c| &c.rounds), "variational": r.variational,
            "two_trajectory": r.two_trajectory, "d0": d0, "periods": r.periods,
            "config": cfg.to_value(),
        }))
    })?;
    json_to_py(py, &v)
}

/// The three tables of a sweep, with the CLI's columns (`geardyn_io::schema`): `points`
/// (bifurcation.csv), `runs` (runs.csv) and `impact_force` (impact_force.csv).
fn sweep_results<'py>(
    py: Python<'py>,
    param: &str,
    results: &[TaskResult],
) -> PyResult<Bound<'py, PyDict>> {
    use geardyn_io::schema;
    let d = PyDict::new(py);
    d.set_item(
        "points",
        util::table(py, &schema::points_table(param, results))?,
    )?;
    d.set_item(
        "runs",
        util::table(py, &schema::runs_table(param, results))?,
    )?;
    d.set_item(
        "impact_force",
        util::table(py, &schema::impact_force_table(param, results))?,
    )?;
    Ok(d)
}

/// Runs a checked sweep ([`SweepSpec::options`]) on the worker, counting and keeping its
/// finished values.
fn sweep(
    ctl: &Ctl,
    scenario: &geardyn_scenario::Scenario,
    opts: &SweepOptions,
) -> Result<Vec<TaskResult>> {
    Ok(execute(&SweepJob::new("sweep", scenario, opts), None, ctl)?)
}

/// The partial result of an interrupted sweep of `param`: its finished values, as a sweep's
/// result (the same columns when no value has finished).
fn kept_sweep(py: Python<'_>, param: &str, ctl: &util::Ctl) -> PyResult<Option<Py<PyAny>>> {
    let mut results: Vec<TaskResult> = ctl.take_kept();
    results.sort_by_key(|r| (r.task.branch, r.task.index));
    Ok(Some(
        sweep_results(py, param, &results)?.into_any().unbind(),
    ))
}

/// `geardyn bifurcation`: with `out`, also its folder (checkpoint, tables, figures) there, and
/// resumed from that folder's checkpoint as the CLI resumes it.
#[pyfunction]
#[pyo3(signature = (src, sim, param, values, range, mode, ics, seed, x0_range, v0_range, sections_, lyapunov, progress, out))]
#[allow(clippy::too_many_arguments)]
fn bifurcation<'py>(
    py: Python<'py>,
    src: Source,
    sim: Sim,
    param: String,
    values: Option<Vec<f64>>,
    range: Option<(f64, f64, usize)>,
    mode: String,
    ics: usize,
    seed: u64,
    x0_range: Option<(f64, f64)>,
    v0_range: Option<(f64, f64)>,
    sections_: Vec<String>,
    lyapunov: bool,
    progress: bool,
    out: Option<std::path::PathBuf>,
) -> PyResult<Bound<'py, PyAny>> {
    let name = param.clone();
    let partial: util::Partial = Box::new(move |py, ctl| kept_sweep(py, &name, ctl));
    let (results, cfg, opts) = util::run(py, "bifurcation", progress, Some(partial), move |ctl| {
        let started = geardyn_io::run_record::now_unix_s();
        let mut cfg = src.config()?;
        sim.apply(&mut cfg, &src.sets)?;
        let scenario = cfg.resolve()?;
        let spec = SweepSpec {
            param,
            values: values_of(values, range)?,
            mode,
            ics,
            seed,
            x0_range,
            v0_range,
            sections: sections_,
            lyapunov,
        };
        let Some(out) = out else {
            let opts = spec.options(&cfg, &scenario)?;
            let results = sweep(ctl, &scenario, &opts)?;
            return Ok((results, cfg, opts));
        };
        // the CLI's folder: the same request, store and writer as `geardyn bifurcation --out`
        // (so either face resumes the other's folder)
        let req = BifurcationRequest::new(cfg, src.source(), &scenario, &spec)?;
        let mut store = Checkpointed::folder(&out, &req.config, false)?;
        let job = SweepJob::new("bifurcation", &scenario, &req.options);
        let results = execute(&job, Some(&mut store), ctl)?;
        req.write_folder(&out, &scenario, &results, started)?;
        Ok((results, req.config, req.options))
    })?;
    let d = sweep_results(py, &opts.param, &results)?;
    d.set_item("param", &opts.param)?;
    d.set_item("values", arr1(py, opts.values.clone()))?;
    d.set_item("settings", ser_to_py(py, &opts)?)?;
    d.set_item("config", config_py(py, &cfg)?)?;
    Ok(d.into_any())
}

/// `geardyn response` without the files.
#[pyfunction]
#[pyo3(signature = (src, sim, param, values, range, progress))]
fn response<'py>(
    py: Python<'py>,
    src: Source,
    sim: Sim,
    param: String,
    values: Option<Vec<f64>>,
    range: Option<(f64, f64, usize)>,
    progress: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let name = param.clone();
    let partial: util::Partial = Box::new(move |py, ctl| kept_sweep(py, &name, ctl));
    let (results, cfg, opts) = util::run(py, "response", progress, Some(partial), move |ctl| {
        let mut cfg = src.config()?;
        sim.apply(&mut cfg, &src.sets)?;
        let scenario = cfg.resolve()?;
        let opts =
            SweepSpec::response(param, values_of(values, range)?).options(&cfg, &scenario)?;
        let results = sweep(ctl, &scenario, &opts)?;
        Ok((results, cfg, opts))
    })?;
    let d = sweep_results(py, &opts.param, &results)?;
    d.set_item("jumps", ser_to_py(py, &detect_jumps(&results))?)?;
    d.set_item("param", &opts.param)?;
    d.set_item("values", arr1(py, opts.values.clone()))?;
    d.set_item("settings", ser_to_py(py, &opts)?)?;
    d.set_item("config", config_py(py, &cfg)?)?;
    Ok(d.into_any())
}

/// The partial result of interrupted basins, as columns (a grid may hold millions of cells):
/// `cell` (row-major index, `iv * nx + ix`), `kind` (0 captured by a known attractor, 1 recorded
/// to the end, 2 diverged, 3 failed) and `attractor` (the capturing attractor's index among those
/// known at that pass — not yet the final numbering —, else -1).
fn kept_basins(py: Python<'_>, ctl: &util::Ctl) -> PyResult<Option<Py<PyAny>>> {
    let mut kept: Vec<(usize, Outcome)> = ctl.take_kept();
    kept.sort_by_key(|k| k.0);
    let c = Columns::new(py);
    c.i64("cell", kept.iter().map(|k| k.0 as i64).collect())?;
    let (kind, attractor): (Vec<i64>, Vec<i64>) = kept
        .iter()
        .map(|(_, o)| match o {
            Outcome::Captured { id, .. } => (0, *id as i64),
            Outcome::Recorded(_) => (1, -1),
            Outcome::Diverged => (2, -1),
            Outcome::Failed(_) => (3, -1),
        })
        .unzip();
    c.i64("kind", kind)?;
    c.i64("attractor", attractor)?;
    Ok(Some(c.dict.into_any().unbind()))
}

/// `geardyn basins` without the files.
#[pyfunction]
#[pyo3(signature = (src, sim, ident, x, v, phase, progress))]
#[allow(clippy::too_many_arguments)]
fn basins<'py>(
    py: Python<'py>,
    src: Source,
    sim: Sim,
    ident: Ident,
    x: Option<(f64, f64, usize)>,
    v: Option<(f64, f64, usize)>,
    phase: f64,
    progress: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let (r, cfg, opts, elapsed) = util::run(
        py,
        "basins",
        progress,
        Some(Box::new(kept_basins)),
        move |ctl| {
            let mut cfg = src.config()?;
            sim.apply(&mut cfg, &src.sets)?;
            let scenario = cfg.resolve()?;
            let model = scenario.model();
            let req = BasinsRequest { x, v, phase };
            let opts = req.options(model, ident.options(&cfg)?)?;
            cfg.check_work(model, &opts.identify.sim, opts.x.n * opts.v.n, false)?;
            let t = std::time::Instant::now();
            let r = execute(&BasinsJob { model, opts: &opts }, None, ctl)?;
            Ok((r, cfg, opts, t.elapsed().as_secs_f64()))
        },
    )?;
    let d = PyDict::new(py);
    d.set_item("cells", arr2(py, r.cells.clone(), r.v.n, r.x.n)?)?;
    d.set_item(
        "x",
        arr1(py, (0..r.x.n).map(|i| r.x.value(i)).collect::<Vec<f64>>()),
    )?;
    d.set_item(
        "v",
        arr1(py, (0..r.v.n).map(|i| r.v.value(i)).collect::<Vec<f64>>()),
    )?;
    d.set_item("attractors", ser_to_py(py, &r.attractors)?)?;
    d.set_item("diverged", r.diverged)?;
    d.set_item("failed", r.failed)?;
    d.set_item("boundary_fraction", r.boundary_fraction)?;
    d.set_item("captured_early", r.captured_early)?;
    d.set_item("periods", r.periods)?;
    d.set_item("x_axis", (r.x.min, r.x.max, r.x.n))?;
    d.set_item("v_axis", (r.v.min, r.v.max, r.v.n))?;
    d.set_item("phase", phase)?;
    d.set_item("elapsed_s", elapsed)?;
    d.set_item("settings", ser_to_py(py, &opts)?)?;
    d.set_item("config", config_py(py, &cfg)?)?;
    Ok(d.into_any())
}

/// `geardyn continuation` without the files.
#[pyfunction]
#[pyo3(signature = (src, sim, ident, param, values, range, ics, seed, x0_range, v0_range, phase, progress))]
#[allow(clippy::too_many_arguments)]
fn continuation<'py>(
    py: Python<'py>,
    src: Source,
    sim: Sim,
    ident: Ident,
    param: String,
    values: Option<Vec<f64>>,
    range: Option<(f64, f64, usize)>,
    ics: usize,
    seed: u64,
    x0_range: Option<(f64, f64)>,
    v0_range: Option<(f64, f64)>,
    phase: f64,
    progress: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let (r, cfg, opts) = util::run(
        py,
        "continuation",
        progress,
        Some(Box::new(util::kept_list::<ValueAttractors>)),
        move |ctl| {
            let mut cfg = src.config()?;
            sim.apply(&mut cfg, &src.sets)?;
            let scenario = cfg.resolve()?;
            let req = ContinuationRequest {
                param,
                values: values_of(values, range)?,
                ics,
                seed,
                x0_range,
                v0_range,
                phase,
                identify: ident.request(),
            };
            let opts = req.options(&cfg, &scenario)?;
            let job = ContinuationJob {
                scenario: &scenario,
                opts: &opts,
            };
            let r = execute(&job, None, ctl)?;
            Ok((r, cfg, opts))
        },
    )?;
    let d = PyDict::new(py);
    let c = Columns::new(py);
    c.f64("value", r.points.iter().map(|p| p.value).collect())?;
    c.i64("branch", r.points.iter().map(|p| p.branch as i64).collect())?;
    c.str("label", r.points.iter().map(|p| p.label.clone()).collect())?;
    c.i64("period", r.points.iter().map(|p| p.period as i64).collect())?;
    c.boolean("healthy", r.points.iter().map(|p| p.healthy).collect())?;
    c.f64("fraction", r.points.iter().map(|p| p.fraction).collect())?;
    c.f64("max_force", r.points.iter().map(|p| p.max_force).collect())?;
    c.f64("x", r.points.iter().map(|p| p.x).collect())?;
    c.f64("v", r.points.iter().map(|p| p.v).collect())?;
    d.set_item("points", c.dict)?;
    d.set_item("events", ser_to_py(py, &r.events)?)?;
    d.set_item("intervals", ser_to_py(py, &r.intervals)?)?;
    let nl = r.lost.len();
    d.set_item(
        "lost",
        arr2(
            py,
            r.lost.iter().flat_map(|&(a, b)| [a, b]).collect(),
            nl,
            2,
        )?,
    )?;
    d.set_item("param", &r.param)?;
    d.set_item("values", arr1(py, opts.values.clone()))?;
    d.set_item("settings", ser_to_py(py, &opts)?)?;
    d.set_item("config", config_py(py, &cfg)?)?;
    Ok(d.into_any())
}

/// `geardyn map2d`: with `out`, also its folder there, resumed from that folder's checkpoint as
/// the CLI resumes it.
#[pyfunction]
#[pyo3(signature = (src, sim, x_param, x_values, x_range, y_param, y_values, y_range, metric, progress, out))]
#[allow(clippy::too_many_arguments)]
fn map2d<'py>(
    py: Python<'py>,
    src: Source,
    sim: Sim,
    x_param: String,
    x_values: Option<Vec<f64>>,
    x_range: Option<(f64, f64, usize)>,
    y_param: String,
    y_values: Option<Vec<f64>>,
    y_range: Option<(f64, f64, usize)>,
    metric: String,
    progress: bool,
    out: Option<std::path::PathBuf>,
) -> PyResult<Bound<'py, PyAny>> {
    let (cells, cfg, opts, metric) = util::run(
        py,
        "map2d",
        progress,
        Some(Box::new(util::kept_list::<MapCell>)),
        move |ctl| {
            let started = geardyn_io::run_record::now_unix_s();
            let mut cfg = src.config()?;
            sim.apply(&mut cfg, &src.sets)?;
            let scenario = cfg.resolve()?;
            let req = geardyn_exec::request::MapRequest::new(
                cfg,
                src.source(),
                &scenario,
                metric,
                (x_param, values_named("x", x_values, x_range)?),
                (y_param, values_named("y", y_values, y_range)?),
            )?;
            let job = MapJob {
                scenario: &scenario,
                opts: &req.options,
            };
            // with `out`: the store and writer of `geardyn map2d --out` (either face resumes the
            // other's folder)
            let mut store = out
                .as_deref()
                .map(|o| Checkpointed::folder(o, &req.config, false))
                .transpose()?;
            let cells = execute(
                &job,
                store.as_mut().map(|s| s as &mut dyn geardyn_exec::Store<_>),
                ctl,
            )?;
            if let Some(o) = &out {
                req.write_folder(o, &scenario, &cells, started)?;
            }
            Ok((cells, req.config, req.options, req.metric))
        },
    )?;
    let (nx, ny) = (opts.x_values.len(), opts.y_values.len());
    let d = PyDict::new(py);
    let vals: Vec<f64> = cells
        .iter()
        .map(|c| c.metric(&metric).unwrap_or(f64::NAN))
        .collect();
    d.set_item("values", arr2(py, vals, ny, nx)?)?;
    d.set_item("metric", &metric)?;
    d.set_item("x_param", &opts.x_param)?;
    d.set_item("y_param", &opts.y_param)?;
    d.set_item("x", arr1(py, opts.x_values.clone()))?;
    d.set_item("y", arr1(py, opts.y_values.clone()))?;
    // the columns of the CLI's map.csv (geardyn_io::schema::map_table)
    d.set_item(
        "cells",
        util::table(
            py,
            &geardyn_io::schema::map_table(&opts.x_param, &opts.y_param, &cells),
        )?,
    )?;
    d.set_item("settings", ser_to_py(py, &opts)?)?;
    d.set_item("config", config_py(py, &cfg)?)?;
    Ok(d.into_any())
}

/// `geardyn run-shard STORE --shard I` (`shard` None: SLURM_ARRAY_TASK_ID): computes one shard
/// of a sharded plan (geardyn_exec::shard) and returns `(shard, points, already_done)`.
#[pyfunction]
#[pyo3(signature = (store, shard))]
fn run_shard(
    py: Python<'_>,
    store: String,
    shard: Option<usize>,
) -> PyResult<(usize, usize, bool)> {
    util::run(py, "run-shard", false, None, move |_| {
        let i = shard::shard_index(shard)?;
        let r = shard::run_shard(std::path::Path::new(&store), i)?;
        Ok((r.shard, r.points, r.already))
    })
}

/// `geardyn status STORE`: `{"command", "shards", "done", "missing", "damaged"}`.
#[pyfunction]
fn shard_status<'py>(py: Python<'py>, store: String) -> PyResult<Bound<'py, PyAny>> {
    let s = shard::status(std::path::Path::new(&store)).map_err(|e| to_pyerr(e.into()))?;
    ser_to_py(py, &s)
}

/// `geardyn merge STORE [--out OUT]`: returns the folder written.
#[pyfunction]
#[pyo3(signature = (store, out))]
fn shard_merge(py: Python<'_>, store: String, out: Option<String>) -> PyResult<String> {
    util::run(py, "merge", false, None, move |_| {
        let m = shard::merge(
            std::path::Path::new(&store),
            out.as_deref().map(std::path::Path::new),
        )?;
        Ok(m.out.display().to_string())
    })
}

/// `geardyn stiffness` without the files: the stiffness.csv table.
#[pyfunction]
fn stiffness<'py>(py: Python<'py>, src: Source) -> PyResult<Bound<'py, PyAny>> {
    let (cfg, scenario) = resolve(&src).map_err(to_pyerr)?;
    let pair = match cfg.pair.as_ref() {
        Some(spec) => Some(spec.build().map_err(|e| to_pyerr(e.into()))?),
        None => None,
    };
    let model = scenario.model();
    let d = PyDict::new(py);
    if let Some(pm) = &pair {
        let (dd, ds) = (scenario.params().d_double, scenario.params().d_single);
        d.set_item(
            "table",
            util::table(
                py,
                &geardyn_io::schema::pair_stiffness_table(pm.rows.iter(), dd, ds),
            )?,
        )?;
        let info = PyDict::new(py);
        info.set_item("eps", pm.geom.eps)?;
        info.set_item("eps_b", pm.eps_b)?;
        info.set_item("k_av_n_per_m", pm.k_av)?;
        info.set_item("omega_n_rad_per_s", pm.omega_n)?;
        info.set_item("cycles", pm.cycles)?;
        info.set_item("samples_per_cycle", pm.spec.samples_per_cycle)?;
        d.set_item("pair", info)?;
    } else {
        d.set_item(
            "table",
            util::table(py, &geardyn_io::schema::model_stiffness_table(model))?,
        )?;
        d.set_item("pair", py.None())?;
    }
    d.set_item("config", config_py(py, &cfg)?)?;
    Ok(d.into_any())
}

/// `geardyn orbits` without the files: one orbit, or the branches over `range` and their
/// bifurcations (the library's `OrbitsRequest`, the CLI's columns).
#[pyfunction]
#[pyo3(signature = (src, param, start, stop, period, transient, ds, max_points, switch_up_to, rtol, progress))]
#[allow(clippy::too_many_arguments)]
fn orbits<'py>(
    py: Python<'py>,
    src: Source,
    param: Option<String>,
    start: Option<f64>,
    stop: Option<f64>,
    period: Option<u64>,
    transient: u64,
    ds: f64,
    max_points: usize,
    switch_up_to: u64,
    rtol: f64,
    progress: bool,
) -> PyResult<Bound<'py, PyAny>> {
    use geardyn_analysis::orbits::MAX_ORBIT_PERIOD;
    use geardyn_analysis::orbits_request::OrbitsRequest;
    use geardyn_io::schema::{bifurcations_table, orbit_branch_table, orbit_rows};
    let (cfg, table, bifs, ends) = util::run(py, "orbits", progress, None, move |_ctl: &Ctl| {
        let cfg = src.config()?;
        let scenario = cfg.resolve()?;
        let range = match (param, start, stop) {
            (Some(p), Some(a), Some(b)) => Some((p, a, b)),
            (None, None, None) => None,
            _ => bail!("param and range go together: param=NAME, range=(START, STOP)"),
        };
        let tau0 = cfg.simulation.tau0;
        // (a count beyond u32 is out of range as any count above the limit)
        let period = match period {
            Some(n) => Some(u32::try_from(n).map_err(|_| {
                anyhow::anyhow!("bad period {n}: allowed 1 ..= {MAX_ORBIT_PERIOD}")
            })?),
            None => None,
        };
        let switch_up_to = u32::try_from(switch_up_to).map_err(|_| {
            anyhow::anyhow!("bad switch_up_to {switch_up_to}: allowed 0 ..= {MAX_ORBIT_PERIOD}")
        })?;
        let req = OrbitsRequest {
            range: range.clone(),
            period,
            transient,
            y0: [cfg.simulation.x0, cfg.simulation.v0],
            tau0,
            ds,
            max_points,
            switch_up_to,
            rtol,
        };
        let job = geardyn_exec::OrbitsJob {
            scenario: &scenario,
            request: &req,
        };
        let c = execute(&job, None, &())?;
        let name = range.as_ref().map(|r| r.0.as_str());
        let rows = orbit_rows(&scenario, name, &c.points, tau0);
        let table = orbit_branch_table(name, &rows);
        let bifs = name.map(|n| bifurcations_table(n, &c.bifurcations));
        Ok((cfg, table, bifs, c.ends.clone()))
    })?;
    let d = PyDict::new(py);
    d.set_item("branch", util::table(py, &table)?)?;
    match bifs {
        Some(b) => d.set_item("bifurcations", util::table(py, &b)?)?,
        None => d.set_item("bifurcations", PyDict::new(py))?,
    }
    d.set_item("ends", ends)?;
    d.set_item("config", config_py(py, &cfg)?)?;
    Ok(d.into_any())
}

/// `geardyn signals` without the files: the pair and its healthy twin, their signals, spectra
/// and condition indicators (the library's `SignalsRequest`, the CLI's columns).
#[pyfunction]
#[pyo3(signature = (src, revolutions, transient, samples_per_cycle, segment_revolutions, sidebands, shaft_orders, residual, na4_reference, progress))]
#[allow(clippy::too_many_arguments)]
fn signals<'py>(
    py: Python<'py>,
    src: Source,
    revolutions: u64,
    transient: u64,
    samples_per_cycle: u64,
    segment_revolutions: u64,
    sidebands: u64,
    shaft_orders: u64,
    residual: String,
    na4_reference: String,
    progress: bool,
) -> PyResult<Bound<'py, PyAny>> {
    use geardyn_analysis::indicators::ResidualKind;
    use geardyn_analysis::signals::{Na4Reference, SignalsRequest, SAMPLES_PER_CYCLE};
    use geardyn_io::schema::{
        indicators_table, lines_table, signals_table, spectrum_table, tsa_table,
    };
    let (cfg, tables, info) = util::run(py, "signals", progress, None, move |_ctl: &Ctl| {
        let cfg = src.config()?;
        let scenario = cfg.resolve()?;
        let sim = cfg.sim_options()?;
        let spc = u32::try_from(samples_per_cycle).map_err(|_| {
            anyhow::anyhow!(
                "bad samples_per_cycle = {samples_per_cycle}: allowed {} ..= {}",
                SAMPLES_PER_CYCLE.start(),
                SAMPLES_PER_CYCLE.end()
            )
        })?;
        let small = |name: &str, v: u64| {
            usize::try_from(v)
                .ok()
                .filter(|&n| n <= geardyn_analysis::indicators::IndicatorOptions::MAX_ORDERS)
                .ok_or_else(|| {
                    anyhow::anyhow!(
                        "bad {name} = {v}: allowed 0 ..= {}",
                        geardyn_analysis::indicators::IndicatorOptions::MAX_ORDERS
                    )
                })
        };
        let req = SignalsRequest {
            revolutions,
            transient,
            samples_per_cycle: spc,
            segment_revolutions,
            sidebands: small("sidebands", sidebands)?,
            shaft_orders: small("shaft_orders", shaft_orders)?,
            residual: ResidualKind::from_name(&residual)?,
            na4_reference: Na4Reference::from_name(&na4_reference)?,
            y0: [cfg.simulation.x0, cfg.simulation.v0],
            tau0: cfg.simulation.tau0,
            method: sim.method,
        };
        let job = geardyn_exec::SignalsJob {
            scenario: &scenario,
            request: &req,
        };
        let r = execute(&job, None, &())?;
        let tables = [
            signals_table(&r),
            spectrum_table(&r),
            indicators_table(&r),
            tsa_table(&r),
            lines_table(&r),
        ];
        let info = serde_json::json!({ "request": &req, "result": &r });
        Ok((cfg, tables, info))
    })?;
    let d = PyDict::new(py);
    for (name, t) in ["signals", "spectrum", "indicators", "tsa", "lines"]
        .iter()
        .zip(&tables)
    {
        d.set_item(*name, util::table(py, t)?)?;
    }
    d.set_item("info", json_to_py(py, &info)?)?;
    d.set_item("config", config_py(py, &cfg)?)?;
    Ok(d.into_any())
}

/// The condition indicators of one signal sampled `samples_per_rev` times per revolution
/// (`geardyn.indicators`): a dict indicator name -> value. `run`: earlier records of the same
/// run (NA4/NB4's run-averaged denominator).
#[pyfunction]
#[pyo3(signature = (signal, samples_per_rev, mesh_order, sidebands, shaft_orders, residual, run))]
#[allow(clippy::too_many_arguments)]
fn indicators<'py>(
    py: Python<'py>,
    signal: Vec<f64>,
    samples_per_rev: u64,
    mesh_order: i64,
    sidebands: u64,
    shaft_orders: u64,
    residual: String,
    run: Vec<Vec<f64>>,
) -> PyResult<Bound<'py, PyAny>> {
    use geardyn_analysis::indicators::{indicators_with_run, IndicatorOptions, ResidualKind};
    let big = |v: u64| usize::try_from(v).unwrap_or(usize::MAX);
    let o = IndicatorOptions {
        samples_per_rev: big(samples_per_rev),
        // a negative order is checked as 0 (below every allowed range), so that the message
        // gives the range the sampling allows, with the value given
        mesh_order: usize::try_from(mesh_order).unwrap_or(0),
        sidebands: big(sidebands),
        shaft_orders: big(shaft_orders),
        residual: ResidualKind::from_name(&residual).map_err(|e| to_pyerr(e.into()))?,
    };
    let runs: Vec<&[f64]> = run.iter().map(|v| v.as_slice()).collect();
    let ind = indicators_with_run(&signal, &o, &runs).map_err(|e| {
        let msg = e.to_string();
        if mesh_order < 0 {
            pyo3::exceptions::PyValueError::new_err(
                msg.replace("mesh_order = 0:", &format!("mesh_order = {mesh_order}:")),
            )
        } else {
            to_pyerr(e.into())
        }
    })?;
    let d = PyDict::new(py);
    for (name, v) in ind.named() {
        d.set_item(name, v)?;
    }
    Ok(d.into_any())
}

/// `geardyn report` (run in-process; the Python wrapper runs it in a child process so that
/// Ctrl-C can stop it).
#[pyfunction]
#[pyo3(signature = (preset, sets, quick, out))]
fn report(
    py: Python<'_>,
    preset: String,
    sets: Vec<String>,
    quick: bool,
    out: String,
) -> PyResult<String> {
    util::run(py, "report", false, None, move |_ctl| {
        let mut cfg = Config::preset(&preset)?;
        for s in &sets {
            cfg.apply_set(s)?;
        }
        cfg.resolve()?;
        let index = geardyn_report::run(
            &cfg,
            &geardyn_report::ReportOptions {
                preset,
                quick,
                out: out.into(),
                decision_given: (
                    sets.iter().any(|s| assigns(s, "decision_periods")),
                    sets.iter().any(|s| assigns(s, "decision_budget")),
                ),
            },
        )?;
        Ok(index.display().to_string())
    })
}

/// The Rust half of the `geardyn` package.
/// The defaults of the keyword arguments, from the library's requests (the CLI's flags show the
/// same ones).
#[pyfunction]
fn defaults(py: Python<'_>) -> PyResult<Bound<'_, PyAny>> {
    json_to_py(py, &geardyn_exec::request::face_defaults())
}

#[pymodule]
fn _geardyn(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(defaults, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(presets, m)?)?;
    m.add_function(wrap_pyfunction!(parameter_names, m)?)?;
    m.add_function(wrap_pyfunction!(config, m)?)?;
    m.add_function(wrap_pyfunction!(derived, m)?)?;
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(lyapunov, m)?)?;
    m.add_function(wrap_pyfunction!(bifurcation, m)?)?;
    m.add_function(wrap_pyfunction!(response, m)?)?;
    m.add_function(wrap_pyfunction!(basins, m)?)?;
    m.add_function(wrap_pyfunction!(continuation, m)?)?;
    m.add_function(wrap_pyfunction!(orbits, m)?)?;
    m.add_function(wrap_pyfunction!(signals, m)?)?;
    m.add_function(wrap_pyfunction!(indicators, m)?)?;
    m.add_function(wrap_pyfunction!(map2d, m)?)?;
    m.add_function(wrap_pyfunction!(stiffness, m)?)?;
    m.add_function(wrap_pyfunction!(report, m)?)?;
    m.add_function(wrap_pyfunction!(run_shard, m)?)?;
    m.add_function(wrap_pyfunction!(shard_status, m)?)?;
    m.add_function(wrap_pyfunction!(shard_merge, m)?)?;
    Ok(())
}
