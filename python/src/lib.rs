//! `geardyn._geardyn`: the Rust half of the Python package. Every analysis mirrors a `geardyn`
//! command of the CLI (crates/cli) on the same library calls and with the same defaults, so that
//! Python and the CLI give the same numbers for the same inputs.
//!
//! An analysis is run by one function, [`run`], from the payload of a typed request of the
//! pure-Python package (`geardyn.BifurcationRequest`, ... in `geardyn/_requests.py`): a dict
//! whose fields are those of the request's struct here (`sweep::BifurcationArgs`, ...), checked
//! once, by the library's own requests (`geardyn_exec::request`, `geardyn_analysis::*_request`),
//! and run through the executor (`geardyn_exec::execute`). The keyword functions of the package
//! (`geardyn.bifurcation(...)`) build such a request and run it.
//!
//! One module per analysis; [`info`] holds the functions that run none (configuration, derived
//! quantities, stiffness, defaults, the report, the sharded plans).

mod basins;
mod continuation;
mod info;
mod lyapunov;
mod map;
mod orbits;
mod signals;
mod simulate;
mod source;
mod sweep;
mod util;

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// The analyses [`run`] knows, by the request's `kind`.
const KINDS: [&str; 9] = [
    "simulate",
    "lyapunov",
    "bifurcation",
    "response",
    "basins",
    "continuation",
    "orbits",
    "signals",
    "map2d",
];

/// The analyses that write the CLI's folder with `out`.
const WITH_OUT: [&str; 3] = ["simulate", "bifurcation", "map2d"];

/// Runs the request `request` (the payload of a `geardyn.*Request`: a dict) of the analysis
/// `kind`; `progress` prints progress on `sys.stderr`, `out` also writes the CLI's folder there
/// (`simulate`, `bifurcation`, `map2d`). Returns the result as a dict (the Python side makes the
/// result object).
#[pyfunction]
#[pyo3(signature = (kind, request, progress=false, out=None))]
fn run<'py>(
    py: Python<'py>,
    kind: &str,
    request: &Bound<'py, PyAny>,
    progress: bool,
    out: Option<std::path::PathBuf>,
) -> PyResult<Bound<'py, PyAny>> {
    if !KINDS.contains(&kind) {
        return Err(PyValueError::new_err(format!(
            "unknown analysis '{kind}': allowed {}",
            KINDS.join(", ")
        )));
    }
    if out.is_some() && !WITH_OUT.contains(&kind) {
        return Err(PyValueError::new_err(format!(
            "{kind}: out is not an option (the folder of `geardyn {kind} --out` is the CLI's; \
             out= is taken by {})",
            WITH_OUT.join(", ")
        )));
    }
    match kind {
        "simulate" => simulate::run(py, request.extract()?, progress, out),
        "lyapunov" => lyapunov::run(py, request.extract()?, progress),
        "bifurcation" => sweep::bifurcation(py, request.extract()?, progress, out),
        "response" => sweep::response(py, request.extract()?, progress),
        "basins" => basins::run(py, request.extract()?, progress),
        "continuation" => continuation::run(py, request.extract()?, progress),
        "orbits" => orbits::run(py, request.extract()?, progress),
        "signals" => signals::run(py, request.extract()?, progress),
        _ => map::run(py, request.extract()?, progress, out),
    }
}

/// The Rust half of the `geardyn` package.
#[pymodule]
fn _geardyn(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(info::defaults, m)?)?;
    m.add_function(wrap_pyfunction!(info::presets, m)?)?;
    m.add_function(wrap_pyfunction!(info::parameter_names, m)?)?;
    m.add_function(wrap_pyfunction!(info::config, m)?)?;
    m.add_function(wrap_pyfunction!(info::derived, m)?)?;
    m.add_function(wrap_pyfunction!(info::stiffness, m)?)?;
    m.add_function(wrap_pyfunction!(info::report, m)?)?;
    m.add_function(wrap_pyfunction!(info::run_shard, m)?)?;
    m.add_function(wrap_pyfunction!(info::shard_status, m)?)?;
    m.add_function(wrap_pyfunction!(info::shard_merge, m)?)?;
    m.add_function(wrap_pyfunction!(signals::indicators, m)?)?;
    Ok(())
}
