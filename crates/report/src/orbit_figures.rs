//! Orbit figures with their data: trajectories attached to time histories, orbit branches
//! followed both ways and drawn over the simulated points.

use crate::readings::f;
use crate::runner::Ctx;
use crate::Figure;
use anyhow::Result;
use geardyn_io::output::write_csv;
use std::path::Path;

use crate::shared::*;

/// Writes the trajectory samples a time-history figure draws as `NAME_trajectory.csv`
/// (`tau,x,v,mesh_force,state`: dimensionless time and state, contact state code as in
/// `simulate`'s trajectory.csv) and lists it under the figure's data.
pub fn attach_trajectory(
    ctx: &Ctx,
    dir: &Path,
    fig: &mut Figure,
    name: &str,
    samples: &[&geardyn_analysis::simulate::TrajectoryPoint],
) -> Result<()> {
    let csv = dir.join(format!("{}_trajectory.csv", safe(name)));
    let rows: Vec<Vec<String>> = samples
        .iter()
        // (shortest round-trip numbers: a tau in the thousands needs more than six significant
        // digits to resolve the sample spacing)
        .map(|p| {
            vec![
                p.tau.to_string(),
                p.x.to_string(),
                p.v.to_string(),
                p.mesh_force.to_string(),
                p.state.to_string(),
            ]
        })
        .collect();
    write_csv(&csv, &["tau", "x", "v", "mesh_force", "state"], rows)?;
    fig.data.push(crate::rel(&ctx.dir, &csv));
    Ok(())
}

/// The branch through the orbit `req` finds at `at` of `param`, followed from there down to `lo`
/// and up to `hi` (two continuations of `req`, merged).
pub fn branch_both_ways(
    base: &geardyn_scenario::Scenario,
    param: &str,
    at: f64,
    (lo, hi): (f64, f64),
    req: &geardyn_analysis::orbits_request::OrbitsRequest,
) -> Result<geardyn_analysis::orbit_branches::Continuation> {
    use geardyn_analysis::orbit_branches::Continuation;
    use geardyn_analysis::orbits_request::{run_orbits, OrbitsRequest};
    let mut c = Continuation::default();
    for stop in [lo, hi] {
        let one = OrbitsRequest {
            range: Some((param.into(), at, stop)),
            ..req.clone()
        };
        c = c.merge(run_orbits(base, &one, &|_| {})?);
    }
    Ok(c)
}

/// The figure and files of periodic-orbit branches over `param` in `[lo, hi]`: `branch.csv`
/// and `bifurcations.csv` (the CLI's `geardyn orbits` tables), the branches drawn over the
/// brute-force stroboscopic diagram from `y0` at `diagram` values of the range, and readings (orbits, unstable ones,
/// bifurcations by kind, why each branch ended).
#[allow(clippy::too_many_arguments)]
pub fn orbit_figure(
    ctx: &Ctx,
    dir: &Path,
    base: &geardyn_scenario::Scenario,
    param: &str,
    (lo, hi): (f64, f64),
    y0: [f64; 2],
    diagram: usize,
    c: &geardyn_analysis::orbit_branches::Continuation,
    title: &str,
    caption: &str,
) -> Result<(Figure, Vec<String>)> {
    use geardyn_analysis::orbit_branches::BifurcationKind;
    use geardyn_analysis::orbits_request::strobe_diagram;
    use geardyn_io::schema::{bifurcations_table, full, orbit_branch_table, orbit_rows};
    let rows = orbit_rows(base, Some(param), &c.points, 0.0);
    let branch_csv = dir.join("branch.csv");
    let bif_csv = dir.join("bifurcations.csv");
    orbit_branch_table(Some(param), &rows).write_csv(&branch_csv, full)?;
    bifurcations_table(param, &c.bifurcations).write_csv(&bif_csv, full)?;
    let diagram = strobe_diagram(base, param, lo, hi, diagram, y0, 0.0);
    let stem = dir.join(format!("orbits_{param}"));
    geardyn_io::sweep_output::plot_orbits(
        &stem,
        &format!(
            "{title} ({})",
            geardyn_io::describe::operating_point_without(base, param)
        ),
        param,
        c,
        &diagram,
    )?;
    let unstable = c.points.iter().filter(|p| !p.orbit.stable).count();
    let mut readings = vec![format!(
        "{} orbits on {} branches ({} unstable: orbits a forward simulation never shows).",
        c.points.len(),
        c.ends.len(),
        unstable
    )];
    for kind in BifurcationKind::ALL {
        let at: Vec<String> = c
            .bifurcations
            .iter()
            .filter(|b| b.kind == kind)
            .map(|b| format!("{} (period {})", f(b.param), b.orbit.period))
            .collect();
        if !at.is_empty() {
            readings.push(format!("{} at {param} = {}.", kind.name(), at.join(", ")));
        }
    }
    readings.extend(c.ends.iter().map(|e| {
        let mut s = e.clone();
        if let Some(first) = s.get(0..1) {
            s.replace_range(0..1, &first.to_uppercase());
        }
        format!("{s}.")
    }));
    Ok((ctx.fig(&stem, caption, &[branch_csv, bif_csv]), readings))
}
