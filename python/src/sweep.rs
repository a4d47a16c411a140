//! `geardyn.BifurcationRequest` and `geardyn.ResponseRequest` (`geardyn bifurcation`,
//! `geardyn response`): one-parameter sweeps, with the CLI's tables.

use anyhow::Result;
use geardyn_analysis::bifurcation::{detect_jumps, SweepOptions, TaskResult};
use geardyn_exec::request::{BifurcationRequest, SweepSpec};
use geardyn_exec::{execute, Checkpointed, SweepJob};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::source::{config_py, values_of, Sim, Source};
use crate::util::{self, arr1, ser_to_py, Ctl};

/// The fields of `geardyn.BifurcationRequest`, as its payload holds them.
#[derive(Clone, Debug, FromPyObject)]
#[pyo3(from_item_all)]
pub struct BifurcationArgs {
    /// Where the configuration comes from.
    pub src: Source,
    /// Integration settings.
    pub sim: Sim,
    /// The swept parameter.
    pub param: String,
    /// Its values (or `range`).
    pub values: Option<Vec<f64>>,
    /// `(start, stop, count)` (or `values`).
    pub range: Option<(f64, f64, usize)>,
    /// `fixed`, `sweep` or `multi`.
    pub mode: String,
    /// Initial states per value (`multi`).
    pub ics: usize,
    /// Their seed.
    pub seed: u64,
    /// Their `x0` interval (`None`: the attractor region).
    pub x0_range: Option<(f64, f64)>,
    /// Their `v0` interval (`None`: the attractor region).
    pub v0_range: Option<(f64, f64)>,
    /// Section names.
    pub sections: Vec<String>,
    /// Also the TLE of every run.
    pub lyapunov: bool,
}

/// The fields of `geardyn.ResponseRequest`, as its payload holds them.
#[derive(Clone, Debug, FromPyObject)]
#[pyo3(from_item_all)]
pub struct ResponseArgs {
    /// Where the configuration comes from.
    pub src: Source,
    /// Integration settings.
    pub sim: Sim,
    /// The swept parameter.
    pub param: String,
    /// Its values (or `range`).
    pub values: Option<Vec<f64>>,
    /// `(start, stop, count)` (or `values`).
    pub range: Option<(f64, f64, usize)>,
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
pub fn bifurcation<'py>(
    py: Python<'py>,
    a: BifurcationArgs,
    progress: bool,
    out: Option<std::path::PathBuf>,
) -> PyResult<Bound<'py, PyAny>> {
    let BifurcationArgs {
        src,
        sim,
        param,
        values,
        range,
        mode,
        ics,
        seed,
        x0_range,
        v0_range,
        sections: sections_,
        lyapunov,
    } = a;
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
pub fn response<'py>(
    py: Python<'py>,
    a: ResponseArgs,
    progress: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let ResponseArgs {
        src,
        sim,
        param,
        values,
        range,
    } = a;
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
