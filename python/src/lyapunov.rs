//! `geardyn.LyapunovRequest` (`geardyn lyapunov`): the top Lyapunov exponent.

use geardyn_analysis::lyapunov_request::{LyapunovRequest, TleMethod};
use geardyn_exec::execute;
use pyo3::prelude::*;

use crate::source::{Sim, Source};
use crate::util::{self, json_to_py, Ctl};

/// The fields of `geardyn.LyapunovRequest`, as its payload holds them.
#[derive(Clone, Debug, FromPyObject)]
#[pyo3(from_item_all)]
pub struct LyapunovArgs {
    /// Where the configuration comes from.
    pub src: Source,
    /// Integration settings.
    pub sim: Sim,
    /// `both`, `variational` or `two-trajectory`.
    pub method: String,
    /// Cap of the converging runs.
    pub max_periods: u64,
    /// Initial distance of the two-trajectory method.
    pub d0: f64,
}

/// `geardyn lyapunov`: the estimates as a dict (the Python side makes the result).
pub fn run<'py>(py: Python<'py>, a: LyapunovArgs, progress: bool) -> PyResult<Bound<'py, PyAny>> {
    let LyapunovArgs {
        src,
        sim,
        method,
        max_periods,
        d0,
    } = a;
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
