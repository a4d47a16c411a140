//! `geardyn.OrbitsRequest` (`geardyn orbits`): one periodic orbit, or its branches over a
//! parameter and their bifurcations.

use anyhow::bail;
use geardyn_exec::execute;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::source::{config_py, Source};
use crate::util::{self, Ctl};

/// The fields of `geardyn.OrbitsRequest`, as its payload holds them.
#[derive(Clone, Debug, FromPyObject)]
#[pyo3(from_item_all)]
pub struct OrbitsArgs {
    /// Where the configuration comes from.
    pub src: Source,
    /// The continued parameter (`None`: one orbit).
    pub param: Option<String>,
    /// Start of the range (with `param`).
    pub start: Option<f64>,
    /// Its end (with `param`).
    pub stop: Option<f64>,
    /// Excitation periods of the orbit (`None`: the motion's).
    pub period: Option<u64>,
    /// Periods simulated before Newton's method starts.
    pub transient: u64,
    /// Largest arclength step.
    pub ds: f64,
    /// Most branch points.
    pub max_points: usize,
    /// Branch switching at doublings up to this period.
    pub switch_up_to: u64,
    /// Relative tolerance of the integration.
    pub rtol: f64,
}

/// `geardyn orbits` without the files: one orbit, or the branches over `range` and their
/// bifurcations (the library's `OrbitsRequest`, the CLI's columns).
pub fn run<'py>(py: Python<'py>, a: OrbitsArgs, progress: bool) -> PyResult<Bound<'py, PyAny>> {
    let OrbitsArgs {
        src,
        param,
        start,
        stop,
        period,
        transient,
        ds,
        max_points,
        switch_up_to,
        rtol,
    } = a;
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
