//! `geardyn continuation` of a gear train: the attractors at every value of one operating
//! parameter from the same initial states, on the plane of one mesh's deflection and rate
//! (`--mesh`, as for `basins`: each value's plane through its own static state, at the phase
//! `--phase` of its own excitation period), linked into branches with their events. A job of
//! the executor: one item per value, resumable from the folder.

use crate::global::{print_continuation, write_continuation, ContinuationArgs};
use crate::sweep::parse_range;
use crate::train::{check_work, sim_options, with_model, TrainRun};
use crate::train_basins::{mesh_index, mesh_slice, on_plane};
use anyhow::{bail, Result};
use geardyn_analysis::attractor::check_phase;
use geardyn_analysis::bifurcation::InitialBox;
use geardyn_analysis::continuation::{attractors_of, link, ContinuationOptions, ValueAttractors};
use geardyn_analysis::engine::Engine;
use geardyn_exec::{ExecError, Job};
use geardyn_model::GearSystem;
use geardyn_train::dynamics::{TrainModel, TrainOperating};
use geardyn_train::TrainSpec;
use rayon::prelude::*;
use std::collections::HashMap;

/// The continuation as a job: one item per value.
struct TrainContinuationJob<'a, const N: usize> {
    spec: &'a TrainSpec,
    op: TrainOperating,
    mesh: usize,
    opts: &'a ContinuationOptions,
}

impl<const N: usize> TrainContinuationJob<'_, N>
where
    TrainModel<N>: Engine<N>,
{
    fn model(&self, i: usize) -> Result<TrainModel<N>, ExecError> {
        let mut op = self.op;
        op.set(&self.opts.param, self.opts.values[i])
            .map_err(ExecError::analysis)?;
        TrainModel::<N>::new(self.spec, &op).map_err(ExecError::analysis)
    }

    /// The initial phase's time of the model (its own excitation period).
    fn t0(&self, m: &TrainModel<N>) -> f64 {
        self.opts.phase * m.excitation_period()
    }
}

impl<const N: usize> Job for TrainContinuationJob<'_, N>
where
    TrainModel<N>: Engine<N>,
{
    type Record = ValueAttractors<N>;
    type Id = usize;
    type Output = Vec<ValueAttractors<N>>;
    fn kind(&self) -> &str {
        "continuation"
    }
    fn settings(&self) -> serde_json::Value {
        serde_json::json!({ "options": self.opts, "mesh": self.mesh })
    }
    fn total(&self) -> usize {
        self.opts.values.len()
    }
    fn id_of(&self, r: &ValueAttractors<N>) -> Option<usize> {
        (r.index < self.total() && r.value == self.opts.values[r.index]).then_some(r.index)
    }
    fn run(
        &self,
        mut done: HashMap<usize, ValueAttractors<N>>,
        on_done: &(dyn Fn(&ValueAttractors<N>) + Sync),
    ) -> Result<Vec<ValueAttractors<N>>, ExecError> {
        let todo: Vec<usize> = (0..self.total())
            .filter(|i| !done.contains_key(i))
            .collect();
        let fresh: Vec<Result<ValueAttractors<N>, ExecError>> = todo
            .par_iter()
            .map(|&i| {
                let m = self.model(i)?;
                let slice = mesh_slice(&m, self.mesh, self.t0(&m)).map_err(ExecError::analysis)?;
                let r = attractors_of(&m, i, self.opts.values[i], self.opts, &slice);
                // a run cut by a stop request is not finished work
                if !geardyn_solvers::cancel::requested() {
                    on_done(&r);
                }
                Ok(r)
            })
            .collect();
        for r in fresh {
            let r = r?;
            done.insert(r.index, r);
        }
        Ok((0..self.total()).filter_map(|i| done.remove(&i)).collect())
    }
}

/// `geardyn continuation --preset planetary|two-stage|pair` or `--system FILE`.
pub fn continuation(t: &TrainRun, a: &ContinuationArgs) -> Result<()> {
    if !TrainOperating::FIELDS.contains(&a.param.as_str()) {
        bail!(
            "--param {}: a train continues one of {}",
            a.param,
            TrainOperating::FIELDS.join(", ")
        );
    }
    t.check_stiffness_form(&[&a.param])?;
    let values = parse_range(&a.range)?;
    for &v in &values {
        let mut op = t.op;
        op.set(&a.param, v)
            .map_err(|e| anyhow::anyhow!("--range: {e}"))?;
    }
    let (x0_range, v0_range) = a.initial.ranges()?;
    let b = InitialBox::new(a.ics, a.initial.seed, x0_range, v0_range, t.op.d)?;
    let (sim, cap) = sim_options(&a.run.sim)?;
    let opts = ContinuationOptions {
        param: a.param.clone(),
        values,
        ics: b.ics,
        seed: b.seed,
        x0_range: b.x0_range,
        v0_range: b.v0_range,
        phase: check_phase(a.phase)?,
        identify: a.ident.request().options(sim)?,
    };
    with_model!(&t.spec, &t.op, |m| {
        check_work(&m, &opts.identify.sim, opts.values.len() * opts.ics, cap)?;
        continuation_model(t, &m, a, &opts)
    })
}

fn continuation_model<const N: usize>(
    t: &TrainRun,
    first: &TrainModel<N>,
    a: &ContinuationArgs,
    opts: &ContinuationOptions,
) -> Result<()>
where
    TrainModel<N>: Engine<N>,
{
    let mesh = mesh_index(first, a.mesh.as_deref())?;
    let job = TrainContinuationJob::<N> {
        spec: &t.spec,
        op: t.op,
        mesh,
        opts,
    };
    let started = std::time::Instant::now();
    let per_value = t.execute(&job, &a.out, a.run.force.force)?;
    // branches linked on the mesh's plane, where the table and the figure show them
    let mut on_mesh = Vec::with_capacity(per_value.len());
    for va in &per_value {
        let m = job.model(va.index)?;
        let t0 = job.t0(&m);
        on_mesh.push(ValueAttractors {
            index: va.index,
            value: va.value,
            attractors: va
                .attractors
                .iter()
                .map(|d| on_plane(&m, mesh, t0, d))
                .collect(),
            assignment: va.assignment.clone(),
        });
    }
    let r = link(&opts.param, &on_mesh, opts.identify.match_tol);
    t.write_record(
        &a.out,
        "continuation",
        &[geardyn_io::run_record::Swept::of(&opts.param, &opts.values)],
        started,
    )?;
    let title = format!(
        "Attractor continuation over {} ({} initial states per value, mesh {}): {} ({}), {}",
        opts.param,
        opts.ics,
        first.mesh_name(mesh),
        t.title_name(),
        t.source,
        t.op_text(&[&opts.param])
    );
    let point = format!("deflection of {}", first.mesh_name(mesh));
    write_continuation(&a.out, (&opts.param, &point), &opts.values, &r, &title)?;
    print_continuation(&opts.param, &r, &a.out);
    Ok(())
}
