//! Phase portraits and Poincaré sections at representative loads and frequencies of the broken
//! pair. Checks seed A 001 §3 (phase diagrams and Poincaré sections) and 000 ¶9–10.

use super::OMEGA_LOAD;
use crate::readings::f;
use crate::runner::{Ctx, TableSpec};
use crate::shared::portrait_figure;
use crate::Section;
use anyhow::Result;
use geardyn_analysis::simulate::{SimOptions, SimResult, Summary};
use geardyn_model::EventKind;
use geardyn_scenario::Scenario;
use std::path::Path;

/// One point of the study: its run, decided.
struct Portrait {
    /// File name suffix.
    name: &'static str,
    /// The point (omega, F).
    sets: [(&'static str, f64); 2],
    /// Revolutions drawn.
    revs: u64,
    /// The run from (0, 0), with the trajectory of the last `revs` revolutions.
    run: SimResult,
    /// Its decided classification.
    summary: Summary,
}

/// What the study computed: the runs at the four points.
pub(super) struct PortraitsData {
    /// The points, in the figures' order.
    portraits: Vec<Portrait>,
}

crate::runner::study!(Portraits { base: &'a Scenario } "portraits" PortraitsData,
    |s, ctx, dir| compute(ctx, s.base), |data| render(ctx, dir, data));

/// The broken pair from (0, 0) at two loads and two frequencies, each run decided.
pub(super) fn compute(ctx: &Ctx, base: &Scenario) -> Result<PortraitsData> {
    let points: [(&str, [(&str, f64); 2]); 4] = [
        ("F_0.02", [("omega", OMEGA_LOAD), ("F", 0.02)]),
        ("F_0.12", [("omega", OMEGA_LOAD), ("F", 0.12)]),
        ("omega_0.1", [("omega", 0.1), ("F", 0.1)]),
        ("omega_2.5", [("omega", 2.5), ("F", 0.1)]),
    ];
    let mut portraits = Vec::new();
    for (name, sets) in points {
        let s = base.with_all(&sets)?;
        let m = s.model().clone();
        // at low speed one revolution spans hundreds of natural oscillations, each drawn with
        // 32 samples or more: one revolution is shown there (the figure stays readable and the
        // CSV small)
        let revs: u64 = if sets[0].1 < 0.5 { 1 } else { 2 };
        let sim = SimOptions {
            trajectory: true,
            samples_per_cycle: 24,
            trajectory_periods: revs,
            ..ctx.sim((20, 80), (4, 12))
        };
        let (run, summary, _) = geardyn_analysis::classify::simulate_decided(
            &m,
            [0.0, 0.0],
            &sim,
            geardyn_analysis::classify::Decide::default(),
        )?;
        portraits.push(Portrait {
            name,
            sets,
            revs,
            run,
            summary,
        });
    }
    Ok(PortraitsData { portraits })
}

/// A phase portrait per point and the table of their motions.
pub(super) fn render(ctx: &Ctx, dir: &Path, data: &PortraitsData) -> Result<Section> {
    let mut figs = Vec::new();
    let mut rows = Vec::new();
    for p in &data.portraits {
        let (name, sets, revs, r, summary) = (p.name, &p.sets, p.revs, &p.run, &p.summary);
        let traj: Vec<[f64; 3]> = r
            .mesh()
            .trajectory
            .iter()
            .map(|p| [p.tau, p.x, p.v])
            .collect();
        let strobe: Vec<[f64; 3]> = r.strobe.iter().map(|p| [p.tau, p.y[0], p.y[1]]).collect();
        let impacts: Vec<[f64; 3]> = r
            .mesh()
            .events
            .iter()
            .filter(|e| e.kind == EventKind::Impact)
            .map(|e| [e.tau, e.x, e.v_before])
            .collect();
        let motion = if summary.motion.is_periodic() {
            summary.label.clone()
        } else {
            summary.motion.word().to_string()
        };
        let title = format!("{}: {motion}", crate::readings::sets(sets));
        figs.push(portrait_figure(
            ctx,
            dir,
            &format!("portrait_{name}"),
            &format!("Phase portrait, {title}"),
            [
                (
                    if revs == 1 {
                        "trajectory (last revolution)"
                    } else {
                        "trajectory (last 2 revolutions)"
                    },
                    traj,
                ),
                ("stroboscopic points", strobe),
                ("back-side impacts (state before)", impacts),
            ],
            &format!("{title}: phase portrait of the last {}, stroboscopic points of every recorded revolution and the state before each back-side impact.", if revs == 1 { "revolution" } else { "two revolutions" }),
        )?);
        rows.push(vec![
            crate::readings::sets(sets),
            motion,
            summary.mesh_period.map_or(String::new(), |m| m.to_string()),
            r.mesh().impacts.to_string(),
            f(summary.p_id),
            f(summary.max_force),
        ]);
    }
    let table = ctx.declared_table(dir, &PORTRAITS_TABLE, rows)?;
    Ok(Section {
        id: "portraits".into(),
        title: "Phase portraits and Poincaré sections at representative loads and frequencies".into(),
        seed_ref: "001 §3 (phase diagrams and Poincaré sections); 000 ¶9–10".into(),
        parameters: "omega = 1.2 with F = 0.02 and 0.12; F = 0.1 with omega = 0.1 and 2.5 (the seed's ranges; points chosen at both ends)".into(),
        method: "Dormand–Prince 5(4), decided classification; trajectories sampled from the dense output 24 times per mesh cycle, and at least 32 times per natural period (low speeds).".into(),
        figures: figs,
        readings: vec![],
        tables: vec![table],
        claims: vec![],
        alternatives: vec![],
        seconds: 0.0,
    })
}

/// The table of `portraits.csv`.
const PORTRAITS_TABLE: TableSpec = TableSpec {
    file: "portraits.csv",
    title: "The four points",
    columns: &[
        "point",
        "motion",
        "period (mesh cycles)",
        "impacts in the record",
        "P_ID",
        "max mesh force",
    ],
};
