//! Two-parameter maps of scalar responses (maximum mesh force, P_ID, period, label class, TLE)
//! over a grid of two model parameters (docs/model.md §5), in parallel, deterministic and resumable.

use crate::classify::{simulate_decided, Decide, DecidedBy, Motion};
use crate::lanes_decide::Decided;
use crate::simulate::{SimOptions, Summary};
use geardyn_model::MeshModel;
use geardyn_scenario::{Scenario, ScenarioError};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;

/// Settings of a map.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MapOptions {
    /// Parameter on the x axis.
    pub x_param: String,
    /// Its values.
    pub x_values: Vec<f64>,
    /// Parameter on the y axis.
    pub y_param: String,
    /// Its values.
    pub y_values: Vec<f64>,
    /// Simulation settings.
    pub sim: SimOptions,
    /// Initial state.
    pub y0: [f64; 2],
    /// Also compute the TLE of each cell.
    pub lyapunov: bool,
}

/// One cell of a map.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MapCell {
    /// Cell index `iy * nx + ix`.
    pub index: usize,
    /// x value.
    pub x: f64,
    /// y value.
    pub y: f64,
    /// Label (`failed: ...` or `invalid: ...` when no result).
    pub label: String,
    /// Period (0 chaotic / failed).
    pub period: usize,
    /// Healthy attractor.
    pub healthy: bool,
    /// Maximum mesh force.
    pub max_force: f64,
    /// Minimum mesh force.
    pub min_force: f64,
    /// Dynamic instability proportion.
    pub p_id: f64,
    /// Back-side impacts in the record.
    pub impacts: u64,
    /// TLE, if computed.
    pub tle: Option<f64>,
    /// Decided class of the motion.
    #[serde(default)]
    pub motion: Motion,
    /// Excitation periods the run was followed in all ([`crate::simulate::Summary::periods_integrated`]; 0 for
    /// an invalid model).
    #[serde(default)]
    pub periods_integrated: u64,
    /// The evidence of the verdict ([`crate::simulate::Summary::decided_by`]).
    #[serde(default)]
    pub decided_by: DecidedBy,
}

impl MapCell {
    /// A cell with no result yet (label empty, [`DecidedBy::Error`]).
    pub fn empty(index: usize, (x, y): (f64, f64)) -> MapCell {
        MapCell {
            index,
            x,
            y,
            label: String::new(),
            period: 0,
            healthy: false,
            max_force: 0.0,
            min_force: 0.0,
            p_id: 0.0,
            impacts: 0,
            tle: None,
            motion: Motion::default(),
            periods_integrated: 0,
            decided_by: DecidedBy::Error,
        }
    }

    /// The cell of a decided run's summary (any gear system: a train's label is its meshes'
    /// labels, its forces and P_ID the largest over its meshes).
    pub fn of_summary(index: usize, xy: (f64, f64), s: Summary) -> MapCell {
        MapCell {
            label: s.label,
            motion: s.motion,
            period: s.period,
            healthy: s.healthy,
            max_force: s.max_force,
            min_force: s.min_force,
            p_id: s.p_id,
            impacts: s.impacts,
            periods_integrated: s.periods_integrated,
            decided_by: s.decided_by,
            ..MapCell::empty(index, xy)
        }
    }

    /// The cell of a parameter point the model refuses (`invalid: ...`, class failed).
    pub fn invalid(index: usize, xy: (f64, f64), e: &impl std::fmt::Display) -> MapCell {
        MapCell {
            label: format!("invalid: {e}"),
            motion: Motion::Failed {
                reason: e.to_string(),
            },
            ..MapCell::empty(index, xy)
        }
    }

    /// Whether the cell has no result (a failed run or an invalid point): its forces, P_ID and
    /// period mean nothing.
    pub fn no_result(&self) -> bool {
        self.label.starts_with("failed") || self.label.starts_with("invalid")
    }

    /// The cell of a run that failed (`failed: ...`).
    pub fn failed(index: usize, xy: (f64, f64), e: &impl std::fmt::Display) -> MapCell {
        MapCell {
            label: format!("failed: {e}"),
            motion: Motion::Failed {
                reason: e.to_string(),
            },
            ..MapCell::empty(index, xy)
        }
    }

    /// Value of a metric by name: `max_force`, `min_force`, `p_id`, `period`, `tle`,
    /// `healthy` (1/0), `class` (0 healthy periodic, 1 non-healthy periodic, 2 chaotic,
    /// 3 failed or diverged, 4 quasi-periodic, 5 unsettled, 6 transient chaos).
    pub fn metric(&self, name: &str) -> Option<f64> {
        let failed = self.no_result();
        Some(match name {
            _ if failed && name != "class" => f64::NAN,
            "max_force" => self.max_force,
            "min_force" => self.min_force,
            "p_id" => self.p_id,
            "period" => self.period as f64,
            "tle" => self.tle.unwrap_or(f64::NAN),
            "healthy" => f64::from(u8::from(self.healthy)),
            "class" => match &self.motion {
                _ if failed => 3.0,
                Motion::Periodic { .. } if self.healthy => 0.0,
                Motion::Periodic { .. } => 1.0,
                Motion::Chaotic { .. } => 2.0,
                Motion::Failed { .. } | Motion::Diverged { .. } => 3.0,
                Motion::QuasiPeriodic { .. } => 4.0,
                Motion::Unsettled { .. } => 5.0,
                Motion::TransientChaos { .. } => 6.0,
            },
            _ => return None,
        })
    }
}

/// Metric names accepted by [`MapCell::metric`].
pub const METRICS: &[&str] = &[
    "max_force",
    "min_force",
    "p_id",
    "period",
    "tle",
    "healthy",
    "class",
];

/// Most cells of a map (each is a decided simulation: a million take hours already).
pub const MAX_CELLS: usize = 1_000_000;

/// Why a map cannot be computed.
#[derive(Debug, thiserror::Error)]
pub enum MapError {
    /// A parameter value the scenario's builder refuses.
    #[error(transparent)]
    Scenario(#[from] ScenarioError),
    /// Axes that do not make a map.
    #[error("{0}")]
    Axes(String),
}

impl MapOptions {
    /// Checks the axes: two different parameters, at least one value each, at most
    /// [`MAX_CELLS`] cells.
    pub fn check_axes(&self) -> Result<(), MapError> {
        let (nx, ny) = (self.x_values.len(), self.y_values.len());
        if self.x_param == self.y_param {
            return Err(MapError::Axes(format!(
                "--x and --y both sweep '{}': a map needs two different parameters (use bifurcation for one)",
                self.x_param
            )));
        }
        if nx == 0 || ny == 0 || nx.saturating_mul(ny) > MAX_CELLS {
            return Err(MapError::Axes(format!(
                "a map of {nx} x {ny} cells: allowed 1 to {MAX_CELLS} cells in all"
            )));
        }
        Ok(())
    }
}

/// Cells per thread in a batch of the lanes path of [`map2d`].
const BATCH_PER_THREAD: usize = 64;

/// A cell from its model (or the error building it) and the decided run of that model.
fn cell_of(
    index: usize,
    (x, y): (f64, f64),
    model: Result<&MeshModel, &ScenarioError>,
    decided: Option<Decided>,
    o: &MapOptions,
) -> MapCell {
    let m = match model {
        Err(e) => return MapCell::invalid(index, (x, y), e),
        Ok(m) => m,
    };
    match decided.expect("a decided run for every valid model") {
        Err(e) => MapCell::failed(index, (x, y), &e),
        Ok((r, s, _)) => {
            let mut cell = MapCell::of_summary(index, (x, y), s);
            if o.lyapunov {
                let (t, y) = r.final_state;
                let start = (m, t, y, r.final_memory);
                cell.tle = crate::lanes_tle::tle_many(&[start], &o.sim, o.sim.record_periods)
                    .pop()
                    .flatten()
                    .map(|l| l.tle);
            }
            cell
        }
    }
}

/// The model at one map point, through the scenario's builder.
fn model_at(base: &Scenario, o: &MapOptions, x: f64, y: f64) -> Result<MeshModel, ScenarioError> {
    base.with_all(&[(o.x_param.as_str(), x), (o.y_param.as_str(), y)])
        .map(|s| s.model().clone())
}

/// Checks the axes ([`MapOptions::check_axes`]) and the parameter values along both, before any
/// work; the number of cells of the map.
fn check_map(base: &Scenario, o: &MapOptions) -> Result<usize, MapError> {
    o.check_axes()?;
    for &x in &o.x_values {
        model_at(base, o, x, o.y_values[0])?;
    }
    for &y in &o.y_values {
        model_at(base, o, o.x_values[0], y)?;
    }
    Ok(o.x_values.len() * o.y_values.len())
}

/// Computes the map. The axes ([`MapOptions::check_axes`]) and the parameter values along both
/// are validated before any work; `done`
/// holds cells of an interrupted run, `on_done` receives each newly finished cell.
pub fn map2d<F>(
    base: &Scenario,
    o: &MapOptions,
    done: &HashMap<usize, MapCell>,
    on_done: F,
) -> Result<Vec<MapCell>, MapError>
where
    F: Fn(&MapCell) + Sync,
{
    let total = o.x_values.len() * o.y_values.len();
    let todo: Vec<usize> = (0..total).filter(|i| !done.contains_key(i)).collect();
    let mut fresh = map2d_cells(base, o, &todo, on_done)?.into_iter();
    let cells = (0..total)
        .map(|i| match done.get(&i) {
            Some(c) => c.clone(),
            None => fresh.next().expect("every cell computed"),
        })
        .collect();
    Ok(cells)
}

/// The cells `indices` (`iy * nx + ix`, each below `nx * ny`) of the map, in that order: the
/// part of [`map2d`] a shard of a distributed plan computes. A cell's result depends on nothing
/// but its cell (the lanes decide each run alone: `crate::lanes`), so any grouping of the cells
/// gives the same cells. Validates like [`map2d`].
pub fn map2d_cells<F>(
    base: &Scenario,
    o: &MapOptions,
    indices: &[usize],
    on_done: F,
) -> Result<Vec<MapCell>, MapError>
where
    F: Fn(&MapCell) + Sync,
{
    let total = check_map(base, o)?;
    if let Some(&i) = indices.iter().find(|&&i| i >= total) {
        return Err(MapError::Axes(format!(
            "cell {i} is outside the map of {total} cells"
        )));
    }
    Ok(map_cells(base, o, indices, &on_done))
}

/// The cells `todo` of a checked map, in that order (compiled once: not generic over the
/// callback).
fn map_cells(
    base: &Scenario,
    o: &MapOptions,
    todo: &[usize],
    on_done: &(dyn Fn(&MapCell) + Sync),
) -> Vec<MapCell> {
    // a run cut by a stop request (geardyn_solvers::cancel) is not finished work
    let on_done = |c: &MapCell| {
        if !geardyn_solvers::cancel::requested() {
            on_done(c)
        }
    };
    let nx = o.x_values.len();
    let value = |index: usize| (o.x_values[index % nx], o.y_values[index / nx]);
    if let Ok(lane) = crate::lanes::LaneSim::new(&o.sim) {
        // fixed-step RK4: the cells' runs in lockstep lanes and their decisions batched
        // (crate::lanes_decide::simulate_decided_lanes), in batches so that an interruption loses at
        // most one batch
        let batch = BATCH_PER_THREAD * rayon::current_num_threads().max(1);
        let mut out = Vec::with_capacity(todo.len());
        for chunk in todo.chunks(batch) {
            let models: Vec<Result<MeshModel, ScenarioError>> = chunk
                .par_iter()
                .map(|&i| {
                    let (x, y) = value(i);
                    model_at(base, o, x, y)
                })
                .collect();
            let runs: Vec<(&MeshModel, [f64; 2])> = models
                .iter()
                .filter_map(|m| m.as_ref().ok().map(|m| (m, o.y0)))
                .collect();
            let mut decided = crate::lanes_decide::simulate_decided_lanes(&runs, &lane).into_iter();
            let pairs: Vec<(usize, Result<&MeshModel, &ScenarioError>, Option<Decided>)> = chunk
                .iter()
                .zip(&models)
                .map(|(&i, m)| match m {
                    Ok(m) => (i, Ok(m), decided.next()),
                    Err(e) => (i, Err(e), None),
                })
                .collect();
            out.extend(
                pairs
                    .into_par_iter()
                    .map(|(i, m, d)| {
                        let c = cell_of(i, value(i), m, d, o);
                        on_done(&c);
                        c
                    })
                    .collect::<Vec<_>>(),
            );
        }
        out
    } else {
        todo.par_iter()
            .map(|&i| {
                let (x, y) = value(i);
                let m = model_at(base, o, x, y);
                let d = m
                    .as_ref()
                    .ok()
                    .map(|m| simulate_decided(m, o.y0, &o.sim, Decide::default()));
                let c = cell_of(i, (x, y), m.as_ref(), d, o);
                on_done(&c);
                c
            })
            .collect()
    }
}
