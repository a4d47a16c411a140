//! C1's frequency response with hysteresis: RMS of x and of the mesh force over omega, swept up
//! and down, and the jumps between decided periodic branches (no seed statement: the benchmark's
//! picture, docs/model.md §6).

use crate::readings::f;
use crate::runner::{sweep_options, Ctx};
use crate::Section;
use anyhow::Result;
use geardyn_analysis::bifurcation::{linspace, SweepMode, TaskResult};
use geardyn_analysis::simulate::SimOptions;
use geardyn_scenario::Scenario;
use std::path::Path;

/// What the study computed: the sweeps up and down.
#[derive(serde::Serialize, serde::Deserialize)]
pub(super) struct ResponseData {
    /// The runs of both directions.
    runs: Vec<TaskResult>,
}

crate::runner::study!(Response { base: &'a Scenario, nr: usize, sim: SimOptions } "response" ResponseData,
    |s, ctx, dir| compute(ctx, s.base, s.nr, s.sim, dir), |data| render(ctx, dir, data), serde_json::json!([s.nr]));

/// The continuation sweep over omega in [0.5, 2], upwards and downwards.
pub(super) fn compute(
    ctx: &Ctx,
    base: &Scenario,
    nr: usize,
    sim: SimOptions,
    dir: &Path,
) -> Result<ResponseData> {
    let values = linspace(0.5, 2.0, nr);
    let o = sweep_options("omega", values, (SweepMode::Sweep, sim), vec![], false);
    let runs = ctx.sweep(dir, "C1 frequency response", base, &o)?;
    Ok(ResponseData { runs })
}

/// The response figure and CSV and the jumps as readings.
pub(super) fn render(ctx: &Ctx, dir: &Path, data: &ResponseData) -> Result<Section> {
    let r = &data.runs;
    let stem = dir.join("response");
    geardyn_io::sweep_output::plot_response(
        &stem,
        "omega",
        r,
        "C1: frequency response, sweeps up and down",
    )?;
    let csv = dir.join("response.csv");
    geardyn_io::sweep_output::write_response(&csv, "omega", r)?;
    let jumps = geardyn_analysis::bifurcation::detect_jumps(r);
    let readings = if jumps.is_empty() {
        vec!["No jump between decided periodic branches.".into()]
    } else {
        jumps
            .iter()
            .map(|j| {
                format!(
                    "Jump on the {} sweep between omega = {} and {}: RMS of x {} → {}.",
                    j.branch,
                    f(j.from),
                    f(j.to),
                    f(j.rms_before),
                    f(j.rms_after)
                )
            })
            .collect()
    };
    Ok(Section {
        id: "response".into(),
        title: "C1: frequency response with hysteresis".into(),
        seed_ref: String::new(),
        parameters: "omega in [0.5, 2], continuation upwards and downwards".into(),
        method: "Each value starts from the final state of the previous one; RMS of the alternating part of x and of the mesh force; a jump is reported only between decided periodic branches.".into(),
        figures: vec![ctx.fig(&stem, "RMS of x and of the mesh force, sweep up and down.", &[csv])],
        readings,
        tables: vec![],
        claims: vec![],
        alternatives: vec![],
        seconds: 0.0,
    })
}
