//! C1's basins of attraction at omega = 1.8, where two attractors coexist (no seed statement:
//! the benchmark's picture, docs/model.md §6).

use crate::runner::Ctx;
use crate::shared::{basin_grid, basin_render, BasinGrid};
use crate::Section;
use anyhow::Result;
use geardyn_analysis::basins::BasinResult;
use geardyn_scenario::Scenario;
use std::path::Path;

/// The box of initial states (x0, x0').
const BOX: ((f64, f64), (f64, f64)) = ((-2.0, 2.0), (-1.5, 1.5));

/// What the study computed: the basins.
pub(super) struct BasinsData {
    /// Cells per axis.
    nb: usize,
    /// The basins on [`BOX`].
    basins: BasinResult,
}

crate::runner::study!(Basins { base: &'a Scenario, nb: usize } "basins" BasinsData,
    |s, ctx, dir| compute(ctx, s.base, s.nb, dir), |data| render(ctx, dir, data), serde_json::json!([s.nb]));

/// The grid of the basins: `nb` x `nb` initial states on [`BOX`].
fn grid(nb: usize) -> BasinGrid<'static> {
    BasinGrid {
        name: "basins_omega_1.8",
        n: nb,
        x: BOX.0,
        v: BOX.1,
    }
}

/// The basins at omega = 1.8 on an `nb` x `nb` grid.
pub(super) fn compute(ctx: &Ctx, base: &Scenario, nb: usize, dir: &Path) -> Result<BasinsData> {
    let m = base.with("omega", 1.8)?.model().clone();
    let basins = basin_grid(
        ctx,
        dir,
        &grid(nb),
        &m,
        crate::shared::identify_options(300, 32),
    )?;
    Ok(BasinsData { nb, basins })
}

/// The basin figure and its attractor table.
pub(super) fn render(ctx: &Ctx, dir: &Path, data: &BasinsData) -> Result<Section> {
    let nb = data.nb;
    let (fig, table) = basin_render(
        ctx,
        dir,
        &grid(nb),
        "C1 basins at omega = 1.8",
        &data.basins,
    )?;
    Ok(Section {
        id: "basins".into(),
        title: "C1: basins of attraction at omega = 1.8, where two attractors coexist".into(),
        seed_ref: String::new(),
        parameters: format!("omega = 1.8, {nb} x {nb} initial states"),
        method: "Automatic attractor identification with early capture.".into(),
        figures: vec![fig],
        readings: vec![],
        tables: vec![table],
        claims: vec![],
        alternatives: vec![],
        seconds: 0.0,
    })
}
