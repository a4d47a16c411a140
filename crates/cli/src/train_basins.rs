//! `geardyn basins` of a gear train: basins of attraction on the plane of one mesh's deflection
//! and deflection rate (`--mesh`), through the train's static state.
//!
//! The train's state is its elastic coordinates; a grid cell `(a, b)` is the static state moved
//! along the least-inertia displacement that sets mesh `k`'s deflection to `a` and its rate to
//! `b` at the initial phase ([`TrainModel::mesh_coordinate`]): the other meshes follow that motion,
//! the modes it does not touch stay at rest. For the single pair written as a train this is the
//! pair's own `(x0, x0')` plane. Attractors are drawn and written in the same coordinates (their
//! stroboscopic points as the mesh's deflection and rate).

use crate::global::{print_basins, write_basins, BasinArgs};

use crate::train::{check_work, sim_options, with_model, TrainRun};
use anyhow::{bail, Result};
use geardyn_analysis::attractor::{check_phase, Descriptor};
use geardyn_analysis::basins::{BasinAttractor, BasinOptions, BasinResult, Slice, SliceError};
use geardyn_analysis::engine::Engine;
use geardyn_exec::BasinsJob;
use geardyn_model::GearSystem;
use geardyn_train::dynamics::{elastic_dof, TrainModel};

/// `geardyn basins --preset planetary|two-stage|pair` or `--system FILE`.
pub fn basins(t: &TrainRun, a: &BasinArgs) -> Result<()> {
    let (sim, cap) = sim_options(&a.run.sim)?;
    with_model!(&t.spec, &t.op, |m| basins_model(t, &m, a, sim, cap))
}

/// The mesh `--mesh` names: a mesh's name or its number from 1 (default the first).
pub fn mesh_index<const N: usize>(m: &TrainModel<N>, given: Option<&str>) -> Result<usize> {
    let Some(g) = given else { return Ok(0) };
    let names: Vec<String> = (0..m.mesh_count()).map(|k| m.mesh_name(k)).collect();
    if let Some(k) = names.iter().position(|n| n == g.trim()) {
        return Ok(k);
    }
    match g.trim().parse::<usize>() {
        Ok(n) if (1..=names.len()).contains(&n) => Ok(n - 1),
        _ => bail!(
            "--mesh {g}: allowed a mesh's name ({}) or its number from 1 to {}",
            names
                .iter()
                .map(|n| format!("'{n}'"))
                .collect::<Vec<_>>()
                .join(", "),
            names.len()
        ),
    }
}

/// The plane of mesh `k`'s deflection and rate at `t0` through the static state.
pub fn mesh_slice<const N: usize>(
    m: &TrainModel<N>,
    k: usize,
    t0: f64,
) -> Result<Slice<N>, SliceError> {
    let y_s = m.static_state();
    let [d_s, r_s] = m.mesh_state(t0, &y_s, k);
    let u = m.mesh_coordinate(k);
    let h = N / 2;
    let (mut dx, mut dv, mut base) = ([0.0; N], [0.0; N], y_s);
    let dof = m.dof();
    dx[..dof].copy_from_slice(&u[..dof]);
    dv[h..h + dof].copy_from_slice(&u[..dof]);
    for (i, u) in u[..dof].iter().enumerate() {
        base[i] -= d_s * u;
        base[h + i] -= r_s * u;
    }
    Slice::along(base, dx, dv)
}

fn basins_model<const N: usize>(
    t: &TrainRun,
    m: &TrainModel<N>,
    a: &BasinArgs,
    sim: geardyn_analysis::simulate::SimOptions,
    cap: f64,
) -> Result<()>
where
    TrainModel<N>: Engine<N>,
{
    debug_assert_eq!(m.dof(), elastic_dof(&t.spec));
    let k = mesh_index(m, a.mesh.as_deref())?;
    let req = a.request()?;
    let phase = check_phase(req.phase)?;
    let (x, v) = req.axes(t.op.d)?;
    a.note_default_axis(&req, x, v);
    let mut identify = a.ident.request().options(sim)?;
    identify.sim.tau0 = phase * m.excitation_period();
    let t0 = identify.sim.tau0;
    let opts = BasinOptions {
        x,
        v,
        identify,
        slice: mesh_slice(m, k, t0)?,
    };
    check_work(m, &opts.identify.sim, x.n * v.n, cap)?;
    let mesh = m.mesh_name(k);
    let started = std::time::Instant::now();
    let r = t.execute(
        &BasinsJob {
            model: m,
            opts: &opts,
        },
        &a.out,
        a.run.force.force,
    )?;
    let elapsed = started.elapsed().as_secs_f64();
    t.write_record(&a.out, "basins", &[], started)?;
    let on_plane = on_mesh_plane(m, k, t0, r);
    let mut extra = serde_json::Map::new();
    extra.insert("system".into(), t.spec.name.clone().into());
    extra.insert("source".into(), t.source.clone().into());
    extra.insert("operating".into(), serde_json::to_value(t.op)?);
    extra.insert("mesh".into(), mesh.clone().into());
    extra.insert(
        "plane".into(),
        format!(
            "x0, v0: the deflection of mesh '{mesh}' and its rate at the initial phase (units b_c, dimensionless time); the other coordinates in the static state, moved along the least-inertia displacement of that mesh"
        )
        .into(),
    );
    let title = format!(
        "Basins of attraction on the plane of mesh '{mesh}' (initial phase {}): {}, {}",
        a.phase,
        t.title_name(),
        t.op_text(&[])
    );
    let labels = (
        format!("deflection of {mesh} (b_c)"),
        format!("deflection rate of {mesh}"),
    );
    write_basins(&a.out, &on_plane, &title, (&labels.0, &labels.1), extra)?;
    print_basins(&on_plane, elapsed, &a.out);
    Ok(())
}

/// The result with every attractor's stroboscopic points as mesh `k`'s deflection and rate (the
/// grid's coordinates; the points are at `t0` plus whole excitation periods, where the meshes'
/// phases are those of `t0`).
fn on_mesh_plane<const N: usize>(
    m: &TrainModel<N>,
    k: usize,
    t0: f64,
    r: BasinResult<N>,
) -> BasinResult {
    let attractors = r
        .attractors
        .into_iter()
        .map(|at| BasinAttractor {
            id: at.id,
            descriptor: on_plane(m, k, t0, &at.descriptor),
            cells: at.cells,
            fraction: at.fraction,
        })
        .collect();
    BasinResult {
        x: r.x,
        v: r.v,
        cells: r.cells,
        attractors,
        diverged: r.diverged,
        failed: r.failed,
        inadmissible: r.inadmissible,
        boundary_fraction: r.boundary_fraction,
        captured_early: r.captured_early,
        periods: r.periods,
    }
}

/// A descriptor of the train with its stroboscopic points (at `t0` plus whole excitation periods)
/// as mesh `k`'s deflection and rate.
pub fn on_plane<const N: usize>(
    m: &TrainModel<N>,
    k: usize,
    t0: f64,
    d: &Descriptor<N>,
) -> Descriptor {
    let pts: Vec<[f64; 2]> = d.points.iter().map(|p| m.mesh_state(t0, p, k)).collect();
    let mut out = Descriptor::new(
        d.period,
        d.label.clone(),
        d.healthy,
        &pts,
        d.max_force,
        d.p_id,
    );
    out.motion = d.motion.clone();
    out.mesh_period = d.mesh_period;
    out
}
