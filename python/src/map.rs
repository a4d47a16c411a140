//! `geardyn.MapRequest` (`geardyn map2d`): a two-parameter map of a response.

use geardyn_analysis::map2d::MapCell;
use geardyn_exec::{execute, Checkpointed, MapJob};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::source::{config_py, values_named, Sim, Source};
use crate::util::{self, arr1, arr2, ser_to_py};

/// The fields of `geardyn.MapRequest`, as its payload holds them.
#[derive(Clone, Debug, FromPyObject)]
#[pyo3(from_item_all)]
pub struct MapArgs {
    /// Where the configuration comes from.
    pub src: Source,
    /// Integration settings.
    pub sim: Sim,
    /// The `x` axis' parameter.
    pub x_param: String,
    /// Its values (or `x_range`).
    pub x_values: Option<Vec<f64>>,
    /// `(start, stop, count)` (or `x_values`).
    pub x_range: Option<(f64, f64, usize)>,
    /// The `y` axis' parameter.
    pub y_param: String,
    /// Its values (or `y_range`).
    pub y_values: Option<Vec<f64>>,
    /// `(start, stop, count)` (or `y_values`).
    pub y_range: Option<(f64, f64, usize)>,
    /// The metric of `values`.
    pub metric: String,
}

/// `geardyn map2d`: with `out`, also its folder there, resumed from that folder's checkpoint as
/// the CLI resumes it.
pub fn run<'py>(
    py: Python<'py>,
    a: MapArgs,
    progress: bool,
    out: Option<std::path::PathBuf>,
) -> PyResult<Bound<'py, PyAny>> {
    let MapArgs {
        src,
        sim,
        x_param,
        x_values,
        x_range,
        y_param,
        y_values,
        y_range,
        metric,
    } = a;
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
