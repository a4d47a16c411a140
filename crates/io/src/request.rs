//! The resolved requests of the grid-shaped commands (`geardyn map2d`, `geardyn bifurcation`)
//! and the folder each writes from its results: one home shared by the single command and by
//! `geardyn merge` of a sharded plan ([`crate::shard`]), so that both write the same files with
//! the same bytes.
//!
//! A request is everything a command's results depend on, resolved: the configuration with every
//! override applied, the analysis options (axes or values, simulation and decision settings),
//! and what the titles name. It serialises to JSON exactly (every float round-trips), which is
//! how a plan carries it to the machines that compute its shards.

use crate::figure::{colormap, write_raster, LabelColors, LegendEntry, RasterFigure, UNSETTLED};
use crate::output::{write_text, OutputError};
use crate::{npy, run_record, schema, sweep_output, Config};
use geardyn_analysis::bifurcation::{SweepOptions, TaskResult};
use geardyn_analysis::map2d::{MapCell, MapOptions};
use geardyn_scenario::Scenario;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Why a folder could not be written.
#[derive(Debug, thiserror::Error)]
pub enum FolderWriteError {
    /// A data file.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// A figure.
    #[error(transparent)]
    Figure(#[from] crate::figure::FigureError),
}

/// A two-parameter map (`geardyn map2d`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MapRequest {
    /// The configuration, every override applied.
    pub config: Config,
    /// What the model comes from, for titles (`preset classic`, `config my.toml`).
    pub source: String,
    /// Metric of the heatmap and of `map.npy` ([`geardyn_analysis::map2d::METRICS`]).
    pub metric: String,
    /// Axes and simulation settings.
    pub options: MapOptions,
}

/// A bifurcation diagram (`geardyn bifurcation`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BifurcationRequest {
    /// The configuration, every override applied.
    pub config: Config,
    /// What the model comes from, for titles.
    pub source: String,
    /// The mode's name as given (`fixed`, `sweep`, `multi`), for the title.
    pub mode: String,
    /// Values, mode, sections and simulation settings.
    pub options: SweepOptions,
}

/// The request of one grid-shaped command.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "command", rename_all = "snake_case")]
pub enum Request {
    /// `geardyn map2d`.
    Map2d(MapRequest),
    /// `geardyn bifurcation`.
    Bifurcation(BifurcationRequest),
}

impl Request {
    /// The command's name (`map2d`, `bifurcation`): the `kind` of its folder.
    pub fn command(&self) -> &'static str {
        match self {
            Request::Map2d(_) => "map2d",
            Request::Bifurcation(_) => "bifurcation",
        }
    }

    /// The configuration.
    pub fn config(&self) -> &Config {
        match self {
            Request::Map2d(r) => &r.config,
            Request::Bifurcation(r) => &r.config,
        }
    }
}

/// The range of the finite values (`(inf, -inf)` when none).
fn finite_range(vals: &[f64]) -> (f64, f64) {
    vals.iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        })
}

impl MapRequest {
    /// Writes the folder of `geardyn map2d` into `out`: `config.toml`, `run.json`, `map.csv`
    /// ([`schema::map_table`]), `map.npy` (the metric, `ny x nx`) and the heatmap `map.png`/`.svg`.
    /// Returns the finite range of the metric.
    pub fn write_folder(
        &self,
        out: &Path,
        scenario: &Scenario,
        cells: &[MapCell],
        started_unix_s: f64,
    ) -> Result<(f64, f64), FolderWriteError> {
        let o = &self.options;
        let (xp, yp) = (o.x_param.as_str(), o.y_param.as_str());
        let (xv, yv) = (&o.x_values, &o.y_values);
        write_text(&out.join("config.toml"), &self.config.to_toml())?;
        run_record::write_sweep_record(
            out,
            "map2d",
            &self.config,
            scenario,
            &[run_record::Swept::of(xp, xv), run_record::Swept::of(yp, yv)],
            started_unix_s,
            run_record::now_unix_s() - started_unix_s,
        )?;
        schema::map_table(xp, yp, cells).write_csv(&out.join("map.csv"), schema::full)?;
        let vals: Vec<f64> = cells
            .iter()
            .map(|c| c.metric(&self.metric).unwrap_or(f64::NAN))
            .collect();
        npy::write_f64(&out.join("map.npy"), &[yv.len(), xv.len()], &vals)?;
        let (lo, hi) = finite_range(&vals);
        let span = if hi > lo { hi - lo } else { 1.0 };
        let colors: Vec<_> = vals
            .iter()
            .map(|v| {
                if v.is_finite() {
                    colormap((v - lo) / span)
                } else {
                    UNSETTLED
                }
            })
            .collect();
        let cell = |v: &[f64]| {
            if v.len() > 1 {
                (v[1] - v[0]).abs()
            } else {
                1.0
            }
        };
        let (dx, dy) = (cell(xv), cell(yv));
        let title = format!(
            "{} over ({}, {}): {}",
            self.metric,
            xp,
            yp,
            sweep_output::operating_point(&self.source, scenario.params(), &[xp, yp])
        );
        write_raster(
            &out.join("map"),
            &RasterFigure {
                title,
                x_label: xp.to_string(),
                y_label: yp.to_string(),
                x: (xv[0] - dx / 2.0, xv[xv.len() - 1] + dx / 2.0, xv.len()),
                y: (yv[0] - dy / 2.0, yv[yv.len() - 1] + dy / 2.0, yv.len()),
                colors,
                legend: if vals.iter().any(|v| !v.is_finite()) {
                    vec![LegendEntry::dot("no value (failed run)", UNSETTLED)]
                } else {
                    vec![]
                },
                legend_title: String::new(),
                colorbar: Some((
                    if lo.is_finite() { lo } else { 0.0 },
                    if hi.is_finite() { hi } else { 1.0 },
                    self.metric.clone(),
                )),
                marks: vec![],
            },
        )?;
        Ok((lo, hi))
    }
}

impl BifurcationRequest {
    /// Writes the folder of `geardyn bifurcation` into `out`: `config.toml`, `run.json`,
    /// `bifurcation.csv`, `runs.csv`, `impact_force.csv` and the diagram `bifurcation.png`/`.svg`.
    pub fn write_folder(
        &self,
        out: &Path,
        scenario: &Scenario,
        results: &[TaskResult],
        started_unix_s: f64,
    ) -> Result<(), FolderWriteError> {
        let o = &self.options;
        let param = o.param.as_str();
        write_text(&out.join("config.toml"), &self.config.to_toml())?;
        run_record::write_sweep_record(
            out,
            "bifurcation",
            &self.config,
            scenario,
            &[run_record::Swept::of(param, &o.values)],
            started_unix_s,
            run_record::now_unix_s() - started_unix_s,
        )?;
        sweep_output::write_bifurcation(&out.join("bifurcation.csv"), param, results)?;
        sweep_output::write_runs(&out.join("runs.csv"), param, results)?;
        sweep_output::write_impact_force(&out.join("impact_force.csv"), param, results)?;
        let title = format!(
            "Bifurcation diagram over {} ({} mode): {}",
            param,
            self.mode,
            sweep_output::operating_point(&self.source, scenario.params(), &[param])
        );
        sweep_output::plot_bifurcation(
            &out.join("bifurcation"),
            param,
            results,
            &o.sections,
            &title,
            &mut LabelColors::default(),
        )?;
        Ok(())
    }
}
