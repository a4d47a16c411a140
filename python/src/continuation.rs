//! `geardyn.ContinuationRequest` (`geardyn continuation`): every attractor followed along a
//! parameter.

use geardyn_analysis::continuation::ValueAttractors;
use geardyn_exec::request::ContinuationRequest;
use geardyn_exec::{execute, ContinuationJob};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::source::{config_py, values_of, Ident, Sim, Source};
use crate::util::{self, arr1, arr2, ser_to_py, Columns};

/// The fields of `geardyn.ContinuationRequest`, as its payload holds them.
#[derive(Clone, Debug, FromPyObject)]
#[pyo3(from_item_all)]
pub struct ContinuationArgs {
    /// Where the configuration comes from.
    pub src: Source,
    /// Integration settings.
    pub sim: Sim,
    /// Identification settings.
    pub ident: Ident,
    /// The continued parameter.
    pub param: String,
    /// Its values (or `range`).
    pub values: Option<Vec<f64>>,
    /// `(start, stop, count)` (or `values`).
    pub range: Option<(f64, f64, usize)>,
    /// Initial states per value.
    pub ics: usize,
    /// Their seed.
    pub seed: u64,
    /// Their `x0` interval (`None`: the attractor region).
    pub x0_range: Option<(f64, f64)>,
    /// Their `v0` interval (`None`: the attractor region).
    pub v0_range: Option<(f64, f64)>,
    /// Phase of the initial states, in `[0, 1)`.
    pub phase: f64,
}

/// `geardyn continuation` without the files.
pub fn run<'py>(
    py: Python<'py>,
    a: ContinuationArgs,
    progress: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let ContinuationArgs {
        src,
        sim,
        ident,
        param,
        values,
        range,
        ics,
        seed,
        x0_range,
        v0_range,
        phase,
    } = a;
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
