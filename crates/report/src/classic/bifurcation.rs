//! C1's bifurcation diagram and top Lyapunov exponent over omega from the fixed initial state:
//! period 1, the period doubling near omega = 0.9 and the chaotic band around 1.1–1.65. Checks
//! docs/model.md §6 (the benchmark, not a seed figure).

use crate::claims::{Claim, Verdict};
use crate::classes::{self, tolerant, Class};
use crate::readings::{f, interval_header, interval_rows, range};
use crate::runner::{sweep_options, Ctx};
use crate::shared::{sweep_figure, SweepPanels};
use crate::Section;
use anyhow::Result;
use geardyn_analysis::bifurcation::{linspace, Section as Sec, SweepMode, TaskResult};
use geardyn_analysis::simulate::SimOptions;
use geardyn_scenario::Scenario;
use std::ops::Range;
use std::path::Path;

/// The first period 2 must lie here ("period doubling near omega = 0.9").
const DOUBLING: Range<f64> = 0.8..1.0;
/// The main chaotic band must start here ...
const CHAOS_START: Range<f64> = 1.0..1.25;
/// ... and end here ("chaos around 1.1–1.65").
const CHAOS_END: Range<f64> = 1.5..1.8;
/// One chaotic band: periodic windows of up to this many sweep values inside it are windows.
const WINDOW_VALUES: usize = 3;

/// What the study computed: the sweep over omega.
#[derive(serde::Serialize, serde::Deserialize)]
pub(super) struct BifurcationData {
    /// Values of omega.
    n: usize,
    /// Integration settings.
    sim: SimOptions,
    /// (F, xi, c) of the scenario.
    params: (f64, f64, f64),
    /// The runs from (0, 0), with the TLE.
    runs: Vec<TaskResult>,
}

crate::runner::study!(Bifurcation { base: &'a Scenario, n: usize, sim: SimOptions } "bifurcation" BifurcationData,
    |s, ctx, dir| compute(ctx, s.base, s.n, s.sim, dir), |data| render(ctx, dir, data), serde_json::json!([s.n]));

/// The sweep over omega in [0.5, 2] from (0, 0) with the TLE.
pub(super) fn compute(
    ctx: &Ctx,
    base: &Scenario,
    n: usize,
    sim: SimOptions,
    dir: &Path,
) -> Result<BifurcationData> {
    let values = linspace(0.5, 2.0, n);
    let o = sweep_options(
        "omega",
        values,
        (SweepMode::Fixed, sim),
        vec![Sec::Strobe],
        true,
    );
    let runs = ctx.sweep(dir, "C1 omega sweep", base, &o)?;
    let p = base.params();
    Ok(BifurcationData {
        n,
        sim,
        params: (p.load, p.xi, p.c),
        runs,
    })
}

/// The diagram, the interval table, the TLE reading and the claim.
pub(super) fn render(ctx: &Ctx, dir: &Path, data: &BifurcationData) -> Result<Section> {
    let (n, sim, r) = (data.n, data.sim, &data.runs);
    let fig = sweep_figure(
        ctx,
        dir,
        "bif_omega",
        "omega",
        r,
        &[Sec::Strobe],
        &SweepPanels {
            tle: true,
            ..Default::default()
        },
        "C1: bifurcation over omega with the TLE",
        "Stroboscopic x over omega from the fixed initial state (0, 0), coloured by the decided motion, and the top Lyapunov exponent.",
    )?;
    let pts = classes::fixed_points(r);
    let iv = classes::intervals(&pts);
    let table = ctx.table(
        &dir.join("intervals_omega.csv"),
        "Motion over omega (intervals of equal label)",
        &interval_header("omega"),
        interval_rows(&iv),
    )?;
    let t = tolerant(&pts);
    let first_p2 = t
        .iter()
        .find(|p| p.class == Class::Periodic(2))
        .map(|p| p.value);
    let chaos = classes::bands(&t, |p| p.class == Class::Chaotic, WINDOW_VALUES);
    let main = chaos.iter().max_by_key(|c| c.2).cloned();
    let ok_p2 = first_p2.is_some_and(|v| DOUBLING.contains(&v));
    let ok_ch = main
        .as_ref()
        .is_some_and(|c| CHAOS_START.contains(&c.0) && CHAOS_END.contains(&c.1));
    let agree = pts
        .iter()
        .filter(|p| p.tle.is_some())
        .filter(|p| (p.tle.unwrap_or(0.0) > 1e-3) == (p.class == Class::Chaotic))
        .count();
    let (load, xi, c) = data.params;
    Ok(Section {
        id: "bifurcation".into(),
        title: "C1: bifurcation diagram and top Lyapunov exponent over omega".into(),
        seed_ref: "docs/model.md §6 (benchmark, not a seed figure)".into(),
        parameters: format!(
            "omega in [0.5, 2] ({n} values), F = {}, xi = {}, c = {}",
            f(load),
            f(xi),
            f(c)
        ),
        method: format!(
            "Dormand–Prince 5(4), {} + {} excitation periods from (0, 0); decided classification; TLE by the variational equation with saltation matrices.",
            sim.transient_periods, sim.record_periods
        ),
        figures: vec![fig],
        readings: vec![format!(
            "The sign of the TLE agrees with the decided class (chaotic iff TLE > 0.001) at {agree} of {} values.",
            pts.iter().filter(|p| p.tle.is_some()).count()
        )],
        tables: vec![table],
        claims: vec![Claim::new(
            "C1 shows period 1, period doubling near omega = 0.9 and chaos around 1.1–1.65",
            "docs/model.md §6",
            "doubling ≈ 0.9; chaos 1.1–1.65",
            format!(
                "first period 2 at {}; chaos {}",
                first_p2.map_or("none".into(), f),
                main.as_ref().map_or("none".into(), |c| {
                    let windows: Vec<String> = c.3.iter().map(|w| range(w.0, w.1)).collect();
                    if windows.is_empty() {
                        range(c.0, c.1)
                    } else {
                        format!("{} with periodic windows at {}", range(c.0, c.1), windows.join(", "))
                    }
                })
            ),
            Verdict::of_parts(&[ok_p2, ok_ch]),
            "Fixed-initial-state sweep, decided classification; single values at bifurcation points ignored; a chaotic band is one band across periodic windows of up to three sweep values (listed).",
        )],
        alternatives: vec![],
        seconds: 0.0,
    })
}
