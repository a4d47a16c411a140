//! The functions that run no analysis: presets, parameter names, the resolved configuration and
//! its derived quantities (`geardyn show`), the stiffness table (`geardyn stiffness`), the
//! keyword defaults, the report (`geardyn report`) and the sharded plans (`geardyn run-shard`,
//! `status`, `merge`).

use geardyn_exec::shard;
use geardyn_io::config::assigns;
use geardyn_io::Config;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::source::{config_py, resolve, Source};
use crate::util::{self, json_to_py, ser_to_py, to_pyerr};

/// `geardyn presets`: `[(name, description)]`.
#[pyfunction]
pub fn presets() -> Vec<(String, String)> {
    geardyn_model::presets::PRESETS
        .iter()
        .map(|(n, w)| (n.to_string(), w.to_string()))
        .collect()
}

/// Names accepted as parameters (`--set` names besides `pair.*`).
#[pyfunction]
pub fn parameter_names() -> Vec<String> {
    geardyn_model::PARAMETER_NAMES
        .iter()
        .chain(geardyn_io::config::SIMULATION_NAMES)
        .map(|s| s.to_string())
        .collect()
}

/// `geardyn show` (the TOML part): the resolved configuration as a dict, or as the TOML text.
#[pyfunction]
pub fn config<'py>(py: Python<'py>, src: Source, as_toml: bool) -> PyResult<Bound<'py, PyAny>> {
    let (cfg, _) = resolve(&src).map_err(to_pyerr)?;
    if as_toml {
        Ok(pyo3::types::PyString::new(py, &cfg.to_toml()).into_any())
    } else {
        config_py(py, &cfg)
    }
}

/// `geardyn show` (the comment part): derived quantities.
#[pyfunction]
pub fn derived<'py>(py: Python<'py>, src: Source) -> PyResult<Bound<'py, PyAny>> {
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

/// `geardyn run-shard STORE --shard I` (`shard` None: SLURM_ARRAY_TASK_ID): computes one shard
/// of a sharded plan (geardyn_exec::shard) and returns `(shard, points, already_done)`.
#[pyfunction]
#[pyo3(signature = (store, shard))]
pub fn run_shard(
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
pub fn shard_status<'py>(py: Python<'py>, store: String) -> PyResult<Bound<'py, PyAny>> {
    let s = shard::status(std::path::Path::new(&store)).map_err(|e| to_pyerr(e.into()))?;
    ser_to_py(py, &s)
}

/// `geardyn merge STORE [--out OUT]`: returns the folder written.
#[pyfunction]
#[pyo3(signature = (store, out))]
pub fn shard_merge(py: Python<'_>, store: String, out: Option<String>) -> PyResult<String> {
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
pub fn stiffness<'py>(py: Python<'py>, src: Source) -> PyResult<Bound<'py, PyAny>> {
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

/// `geardyn report` (run in-process; the Python wrapper runs it in a child process so that
/// Ctrl-C can stop it).
#[pyfunction]
#[pyo3(signature = (preset, sets, quick, out))]
pub fn report(
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

/// The defaults of the keyword arguments, from the library's requests (the CLI's flags show the
/// same ones).
#[pyfunction]
pub fn defaults(py: Python<'_>) -> PyResult<Bound<'_, PyAny>> {
    json_to_py(py, &geardyn_exec::request::face_defaults())
}
