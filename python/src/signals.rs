//! `geardyn.SignalsRequest` (`geardyn signals`): a broken pair and its healthy twin, their
//! signals, spectra and condition indicators; and the indicators of one signal
//! (`geardyn.indicators`).

use geardyn_exec::execute;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::source::{config_py, Source};
use crate::util::{self, json_to_py, to_pyerr, Ctl};

/// The fields of `geardyn.SignalsRequest`, as its payload holds them.
#[derive(Clone, Debug, FromPyObject)]
#[pyo3(from_item_all)]
pub struct SignalsArgs {
    /// Where the configuration comes from.
    pub src: Source,
    /// Pinion revolutions recorded.
    pub revolutions: u64,
    /// Pinion revolutions discarded first.
    pub transient: u64,
    /// Samples per mesh cycle.
    pub samples_per_cycle: u64,
    /// Revolutions per Welch segment.
    pub segment_revolutions: u64,
    /// Shaft sidebands of each mesh harmonic removed.
    pub sidebands: u64,
    /// Shaft orders removed.
    pub shaft_orders: u64,
    /// `mesh_and_shaft` or `mesh`.
    pub residual: String,
    /// `run` or `own`.
    pub na4_reference: String,
}

/// `geardyn signals` without the files: the pair and its healthy twin, their signals, spectra
/// and condition indicators (the library's `SignalsRequest`, the CLI's columns).
pub fn run<'py>(py: Python<'py>, a: SignalsArgs, progress: bool) -> PyResult<Bound<'py, PyAny>> {
    let SignalsArgs {
        src,
        revolutions,
        transient,
        samples_per_cycle,
        segment_revolutions,
        sidebands,
        shaft_orders,
        residual,
        na4_reference,
    } = a;
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
pub fn indicators<'py>(
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
