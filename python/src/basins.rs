//! `geardyn.BasinsRequest` (`geardyn basins`): basins of attraction on a grid of initial
//! states.

use geardyn_analysis::attractor::Outcome;
use geardyn_analysis::basins::BasinsRequest;
use geardyn_exec::{execute, BasinsJob};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::source::{config_py, Ident, Sim, Source};
use crate::util::{self, arr1, arr2, ser_to_py, Columns};

/// The fields of `geardyn.BasinsRequest`, as its payload holds them.
#[derive(Clone, Debug, FromPyObject)]
#[pyo3(from_item_all)]
pub struct BasinsArgs {
    /// Where the configuration comes from.
    pub src: Source,
    /// Integration settings.
    pub sim: Sim,
    /// Identification settings.
    pub ident: Ident,
    /// Displacement axis `(min, max, n)` (`None`: the default).
    pub x: Option<(f64, f64, usize)>,
    /// Velocity axis `(min, max, n)` (`None`: the default).
    pub v: Option<(f64, f64, usize)>,
    /// Phase of the initial states, in `[0, 1)`.
    pub phase: f64,
}

/// The partial result of interrupted basins, as columns (a grid may hold millions of cells):
/// `cell` (row-major index, `iv * nx + ix`), `kind` (0 captured by a known attractor, 1 recorded
/// to the end, 2 diverged, 3 failed, 4 inadmissible) and `attractor` (the capturing attractor's index among those
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
            Outcome::Inadmissible => (4, -1),
        })
        .unzip();
    c.i64("kind", kind)?;
    c.i64("attractor", attractor)?;
    Ok(Some(c.dict.into_any().unbind()))
}

/// `geardyn basins` without the files.
/// `geardyn basins` without the files.
pub fn run<'py>(py: Python<'py>, a: BasinsArgs, progress: bool) -> PyResult<Bound<'py, PyAny>> {
    let BasinsArgs {
        src,
        sim,
        ident,
        x,
        v,
        phase,
    } = a;
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
    d.set_item("inadmissible", r.inadmissible)?;
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
