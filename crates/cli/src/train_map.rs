//! `geardyn map2d` of a gear train: a decided run of the train at every cell of a grid of two
//! operating parameters, with per mesh its label, force extremes, P_ID and dynamic factor, and
//! the largest planet load-sharing factor. A job of the executor: resumable from the folder's
//! checkpoint and reported as it goes.

use crate::global::{parse_param_axis, MapArgs};

use crate::train::{check_work, dynamic_factors, load_sharing, sim_options, with_model, TrainRun};
use anyhow::{bail, Result};
use geardyn_analysis::classify::{simulate_decided, Decide};
use geardyn_analysis::engine::Engine;
use geardyn_analysis::map2d::MapCell;
use geardyn_analysis::simulate::SimOptions;
use geardyn_exec::{ExecError, Job};
use geardyn_io::schema::{self, Values};
use geardyn_io::sweep_output::MetricScale;
use geardyn_model::GearSystem;
use geardyn_train::dynamics::{TrainModel, TrainOperating};
use geardyn_train::TrainSpec;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;

/// Metrics of a train's map: the pair's ([`MapCell::metric`], forces and P_ID the largest over
/// the meshes) and the train's own.
pub const METRICS: &[&str] = &[
    "max_force",
    "min_force",
    "p_id",
    "period",
    "healthy",
    "class",
    "dynamic_factor",
    "load_sharing",
];

/// One mesh of a cell.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MeshCell {
    /// Its label (`n-p-q-r-s` read on this mesh).
    pub label: String,
    /// Largest contact force (units `k_ref b_c`).
    pub max_force: f64,
    /// Smallest contact force.
    pub min_force: f64,
    /// Its dynamic instability proportion.
    pub p_id: f64,
    /// Peak over static force (`None`: no static load).
    pub dynamic_factor: Option<f64>,
}

/// One cell of a train's map.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TrainCell {
    /// The train as a whole, in the pair's cell.
    pub cell: MapCell,
    /// Per mesh.
    pub meshes: Vec<MeshCell>,
    /// The largest planet load-sharing factor (`None`: no planets, or no result).
    pub load_sharing_max: Option<f64>,
}

impl TrainCell {
    /// The value of a metric of [`METRICS`].
    pub fn metric(&self, name: &str) -> f64 {
        let largest = |f: &dyn Fn(&MeshCell) -> Option<f64>| {
            self.meshes.iter().filter_map(f).fold(f64::NAN, f64::max)
        };
        match name {
            "dynamic_factor" => largest(&|m| m.dynamic_factor),
            "load_sharing" => self.load_sharing_max.unwrap_or(f64::NAN),
            _ => self.cell.metric(name).unwrap_or(f64::NAN),
        }
    }
}

/// The map as a job: one item per cell.
struct TrainMapJob<'a, const N: usize> {
    spec: &'a TrainSpec,
    op: TrainOperating,
    x: (&'a str, &'a [f64]),
    y: (&'a str, &'a [f64]),
    sim: SimOptions,
}

impl<const N: usize> TrainMapJob<'_, N>
where
    TrainModel<N>: Engine<N>,
{
    fn at(&self, i: usize) -> (f64, f64) {
        let nx = self.x.1.len();
        (self.x.1[i % nx], self.y.1[i / nx])
    }

    fn op_at(&self, i: usize) -> TrainOperating {
        let (x, y) = self.at(i);
        let mut op = self.op;
        // (every value of both axes is checked before the job starts)
        op.set(self.x.0, x).expect("checked");
        op.set(self.y.0, y).expect("checked");
        op
    }

    fn cell(&self, i: usize) -> TrainCell {
        let xy = self.at(i);
        let m = match TrainModel::<N>::new(self.spec, &self.op_at(i)) {
            Ok(m) => m,
            Err(e) => {
                return TrainCell {
                    cell: MapCell::invalid(i, xy, &e),
                    meshes: vec![],
                    load_sharing_max: None,
                }
            }
        };
        match simulate_decided(&m, m.static_state(), &self.sim, Decide::default()) {
            Err(e) => TrainCell {
                cell: MapCell::failed(i, xy, &e),
                meshes: vec![],
                load_sharing_max: None,
            },
            Ok((_, s, _)) => {
                let factors = dynamic_factors(&m, &s);
                let lsf = load_sharing(self.spec, &s)
                    .iter()
                    .map(|x| x.2)
                    .fold(f64::NAN, f64::max);
                let meshes = (0..m.mesh_count())
                    .map(|k| {
                        let ms = s.meshes.get(k);
                        MeshCell {
                            label: ms.map_or(s.label.clone(), |x| x.label.clone()),
                            max_force: ms.map_or(s.max_force, |x| x.max_force),
                            min_force: ms.map_or(s.min_force, |x| x.min_force),
                            p_id: ms.map_or(s.p_id, |x| x.p_id),
                            dynamic_factor: Some(factors[k].1).filter(|f| f.is_finite()),
                        }
                    })
                    .collect();
                TrainCell {
                    cell: MapCell::of_summary(i, xy, s),
                    meshes,
                    load_sharing_max: Some(lsf).filter(|f| f.is_finite()),
                }
            }
        }
    }
}

impl<const N: usize> Job for TrainMapJob<'_, N>
where
    TrainModel<N>: Engine<N>,
{
    type Record = TrainCell;
    type Id = usize;
    type Output = Vec<TrainCell>;
    fn kind(&self) -> &str {
        "map2d"
    }
    fn settings(&self) -> serde_json::Value {
        serde_json::json!({
            "x": self.x, "y": self.y, "sim": self.sim,
        })
    }
    fn total(&self) -> usize {
        self.x.1.len() * self.y.1.len()
    }
    fn id_of(&self, r: &TrainCell) -> Option<usize> {
        let i = r.cell.index;
        (i < self.total() && (r.cell.x, r.cell.y) == self.at(i)).then_some(i)
    }
    fn run(
        &self,
        mut done: HashMap<usize, TrainCell>,
        on_done: &(dyn Fn(&TrainCell) + Sync),
    ) -> Result<Vec<TrainCell>, ExecError> {
        let todo: Vec<usize> = (0..self.total())
            .filter(|i| !done.contains_key(i))
            .collect();
        let fresh: Vec<TrainCell> = todo
            .par_iter()
            .map(|&i| {
                let c = self.cell(i);
                // a run cut by a stop request is not finished work
                if !geardyn_solvers::cancel::requested() {
                    on_done(&c);
                }
                c
            })
            .collect();
        for c in fresh {
            done.insert(c.cell.index, c);
        }
        Ok((0..self.total()).filter_map(|i| done.remove(&i)).collect())
    }
}

/// The colours of a metric: ratios whose ideal is 1 cover [1, 1.05] at least (equal planets'
/// load sharing is 1 to rounding); a dynamic factor is missing where a mesh has no static load.
fn scale(metric: &str) -> MetricScale<'_> {
    match metric {
        "load_sharing" => MetricScale {
            cover: Some((1.0, 1.05)),
            ..MetricScale::of(metric)
        },
        "dynamic_factor" => MetricScale {
            cover: Some((1.0, 1.05)),
            missing: "no value (failed run, or no static load)",
            ..MetricScale::of(metric)
        },
        _ => MetricScale::of(metric),
    }
}

/// `geardyn map2d --preset planetary|two-stage|pair` or `--system FILE`.
pub fn map(t: &TrainRun, a: &MapArgs) -> Result<()> {
    let x = parse_param_axis(&a.x, "--x")?;
    let y = parse_param_axis(&a.y, "--y")?;
    for (axis, (p, vals)) in [("--x", &x), ("--y", &y)] {
        if !TrainOperating::FIELDS.contains(&p.as_str()) {
            bail!(
                "{axis} {p}: a train's map spans two of {}",
                TrainOperating::FIELDS.join(", ")
            );
        }
        for &v in vals.iter() {
            let mut op = t.op;
            op.set(p, v).map_err(|e| anyhow::anyhow!("{axis}: {e}"))?;
        }
    }
    if x.0 == y.0 {
        bail!(
            "--x and --y both sweep '{}': a map needs two different parameters (use bifurcation for one)",
            x.0
        );
    }
    t.check_stiffness_form(&[&x.0, &y.0])?;
    if !METRICS.contains(&a.metric.as_str()) {
        bail!(
            "--metric {}: a train's map draws one of {}",
            a.metric,
            METRICS.join(", ")
        );
    }
    let (sim, cap) = sim_options(&a.run.sim)?;
    with_model!(&t.spec, &t.op, |m| {
        check_work(&m, &sim, x.1.len() * y.1.len(), cap)?;
        map_model(t, &m, a, (&x.0, &x.1), (&y.0, &y.1), sim)
    })
}

fn map_model<const N: usize>(
    t: &TrainRun,
    // (fixes the state dimension)
    _first: &TrainModel<N>,
    a: &MapArgs,
    x: (&str, &[f64]),
    y: (&str, &[f64]),
    sim: SimOptions,
) -> Result<()>
where
    TrainModel<N>: Engine<N>,
{
    let job = TrainMapJob::<N> {
        spec: &t.spec,
        op: t.op,
        x,
        y,
        sim,
    };
    let started = std::time::Instant::now();
    let cells = t.execute(&job, &a.out, a.run.force.force)?;
    let (nx, ny) = (x.1.len(), y.1.len());
    t.write_record(
        &a.out,
        "map2d",
        &[
            geardyn_io::run_record::Swept::of(x.0, x.1),
            geardyn_io::run_record::Swept::of(y.0, y.1),
        ],
        started,
    )?;
    let plain: Vec<MapCell> = cells.iter().map(|c| c.cell.clone()).collect();
    let mut table = schema::map_table(x.0, y.0, &plain);
    for (k, mesh) in t.spec.meshes.iter().enumerate() {
        let col = |f: &dyn Fn(&MeshCell) -> f64| {
            Values::F64(
                cells
                    .iter()
                    .map(|c| c.meshes.get(k).map_or(f64::NAN, f))
                    .collect(),
            )
        };
        table.push(
            &format!("label {}", mesh.name),
            Values::Str(
                cells
                    .iter()
                    .map(|c| c.meshes.get(k).map_or(String::new(), |m| m.label.clone()))
                    .collect(),
            ),
        );
        table.push(&format!("max_force {}", mesh.name), col(&|m| m.max_force));
        table.push(&format!("min_force {}", mesh.name), col(&|m| m.min_force));
        table.push(&format!("p_id {}", mesh.name), col(&|m| m.p_id));
        table.push(
            &format!("dynamic_factor {}", mesh.name),
            col(&|m| m.dynamic_factor.unwrap_or(f64::NAN)),
        );
    }
    table.push(
        "load_sharing_max",
        Values::F64(
            cells
                .iter()
                .map(|c| c.load_sharing_max.unwrap_or(f64::NAN))
                .collect(),
        ),
    );
    table.write_csv(&a.out.join("map.csv"), schema::full)?;
    let vals: Vec<f64> = cells.iter().map(|c| c.metric(&a.metric)).collect();
    geardyn_io::npy::write_f64(&a.out.join("map.npy"), &[ny, nx], &vals)?;
    let title = format!(
        "{} over ({}, {}): {} ({}), {}",
        a.metric,
        x.0,
        y.0,
        t.title_name(),
        t.source,
        t.op_text(&[x.0, y.0])
    );
    let (lo, hi) = geardyn_io::sweep_output::plot_metric_map(
        &a.out.join("map"),
        &title,
        x,
        y,
        &vals,
        scale(&a.metric),
    )?;
    let mut classes = std::collections::BTreeMap::<String, usize>::new();
    for c in &cells {
        *classes.entry(c.cell.motion.word().to_string()).or_default() += 1;
    }
    let text: Vec<String> = classes.iter().map(|(c, n)| format!("{n} {c}")).collect();
    println!(
        "{}: {nx}x{ny} cells in {:.2} s ({}); {} in [{lo:.4}, {hi:.4}] -> {}",
        t.spec.name,
        started.elapsed().as_secs_f64(),
        text.join(", "),
        a.metric,
        a.out.display()
    );
    Ok(())
}
