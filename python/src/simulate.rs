//! `geardyn.SimulateRequest` (`geardyn simulate`): one run, returned, and with `out` the CLI's
//! folder too.

use geardyn_analysis::simulate::SimResult;
use geardyn_exec::execute;
use geardyn_io::Config;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::source::{config_py, Sim, Source};
use crate::util::{self, arr1, arr2, json_to_py, ser_to_py, Columns, Ctl};

/// The fields of `geardyn.SimulateRequest`, as its payload holds them.
#[derive(Clone, Debug, FromPyObject)]
#[pyo3(from_item_all)]
pub struct SimulateArgs {
    /// Where the configuration comes from.
    pub src: Source,
    /// Recorded excitation periods (default: the configuration's).
    pub periods: Option<f64>,
    /// Discarded excitation periods (default: the configuration's).
    pub transient: Option<f64>,
    /// `dopri` or `rk4` (default: the configuration's).
    pub integrator: Option<String>,
    /// Recorded periods kept in the trajectory (`None`: all).
    pub trajectory_periods: Option<u64>,
}

/// What a run leaves for its result dict.
type Ran = (
    Config,
    SimResult,
    serde_json::Value,
    f64,
    (f64, f64),
    String,
);

/// `geardyn simulate` without the files (with `out`, with them): the same run, returned.
pub fn run<'py>(
    py: Python<'py>,
    a: SimulateArgs,
    progress: bool,
    out: Option<std::path::PathBuf>,
) -> PyResult<Bound<'py, PyAny>> {
    let SimulateArgs {
        src,
        periods,
        transient,
        integrator,
        trajectory_periods,
    } = a;
    let ran: Ran = util::run(py, "simulate", progress, None, move |_ctl: &Ctl| {
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
    result(py, ran)
}

/// The result dict of a run.
fn result<'py>(py: Python<'py>, ran: Ran) -> PyResult<Bound<'py, PyAny>> {
    let (cfg, res, summary, period, levels, description) = ran;
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
