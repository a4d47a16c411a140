//! B5: the mechanism of separation: the mesh force turns tensile in contact and jumps to zero
//! twice, when x reaches D_s (single-tooth zone) and D_d (double-tooth zone). Checks seed B 003
//! §3.2 and 004 §4.2 (Fig. 4.3), §6(2).

use super::{B003, B004, BACKLASH_STEP, DD_SEED, DS_SEED, F_BACKLASH};
use crate::claims::{Claim, Verdict};
use crate::readings::{f, pct, sets};
use crate::runner::Ctx;
use crate::shared::{line_figure, Line};
use crate::Section;
use anyhow::Result;
use geardyn_analysis::simulate::{simulate, SimOptions, SimResult};
use geardyn_model::{EventKind, MeshModel};
use geardyn_scenario::Scenario;
use std::path::Path;

/// What the study computed: the point shown and its run.
pub(super) struct MechanismData {
    /// Number of candidate points tried.
    candidates: usize,
    /// The point shown: the first candidate whose run shows both exits, else the last one.
    point: Vec<(&'static str, f64)>,
    /// Its model (linear contact law).
    model: MeshModel,
    /// Its run from (0, 0), with the trajectory of the last periods.
    run: SimResult,
    /// Drive-side exits at D_s with a tensile force before them.
    exits_s: usize,
    /// Drive-side exits at D_d with a tensile force before them.
    exits_d: usize,
}

crate::runner::study!(Mechanism { lin: &'a Scenario } "mechanism" MechanismData,
    |s, ctx, dir| compute(ctx, s.lin), |data| render(ctx, dir, data));

/// Runs the candidate points until one shows a tensile force before both exits.
pub(super) fn compute(ctx: &Ctx, lin: &Scenario) -> Result<MechanismData> {
    // candidate points: the backlash sweep's small-D end and the xi sweep's period-2 range
    let candidates: Vec<Vec<(&str, f64)>> = vec![
        vec![
            ("omega", 1.4),
            ("xi", 0.27),
            ("F", F_BACKLASH),
            ("D_d", 0.3 - BACKLASH_STEP),
            ("D_s", 0.3),
        ],
        vec![
            ("omega", 1.4),
            ("xi", 0.27),
            ("F", F_BACKLASH),
            ("D_d", 0.8),
            ("D_s", 1.0),
        ],
        vec![
            ("omega", 1.5),
            ("xi", 0.03),
            ("F", 0.05),
            ("D_d", DD_SEED),
            ("D_s", DS_SEED),
        ],
        vec![
            ("omega", 1.5),
            ("xi", 0.04),
            ("F", 0.05),
            ("D_d", DD_SEED),
            ("D_s", DS_SEED),
        ],
        vec![
            ("omega", 1.5),
            ("xi", 0.02),
            ("F", 0.05),
            ("D_d", DD_SEED),
            ("D_s", DS_SEED),
        ],
        vec![
            ("omega", 1.4),
            ("xi", 0.23),
            ("F", 0.07),
            ("D_d", DD_SEED),
            ("D_s", DS_SEED),
        ],
    ];
    let sim = SimOptions {
        trajectory: true,
        samples_per_cycle: 256,
        trajectory_periods: 3,
        ..ctx.sim((200, 300), (10, 10))
    };
    let mut chosen = None;
    for c in &candidates {
        let s = lin.with_all(c)?;
        let m = s.model().clone();
        let r = simulate(&m, [0.0, 0.0], &sim)?;
        let (dd, ds) = (m.params().d_double, m.params().d_single);
        let exits: Vec<(f64, f64)> = r
            .mesh()
            .events
            .iter()
            .filter(|e| e.kind == EventKind::DriveExit)
            .map(|e| (e.tau, e.x))
            .collect();
        let tensile_before = |tau: f64| {
            r.mesh()
                .trajectory
                .iter()
                .filter(|p| p.tau <= tau && p.tau > tau - 0.1 && p.state == 1)
                .any(|p| p.mesh_force < 0.0)
        };
        let at = |lvl: f64| {
            exits
                .iter()
                .filter(|e| (e.1 - lvl).abs() < 1e-6)
                .filter(|e| tensile_before(e.0))
                .count()
        };
        let (ns, nd) = (at(ds), at(dd));
        if ns > 0 && nd > 0 {
            chosen = Some((c.clone(), m, r, ns, nd));
            break;
        }
        if chosen.is_none() && c == candidates.last().unwrap_or(c) {
            chosen = Some((c.clone(), m, r, ns, nd));
        }
    }
    let (point, model, run, exits_s, exits_d) =
        chosen.ok_or_else(|| anyhow::anyhow!("no candidate"))?;
    Ok(MechanismData {
        candidates: candidates.len(),
        point,
        model,
        run,
        exits_s,
        exits_d,
    })
}

/// The figure of two mesh cycles, the reading and the claim.
pub(super) fn render(ctx: &Ctx, dir: &Path, data: &MechanismData) -> Result<Section> {
    let (c, m, r, ns, nd) = (
        &data.point,
        &data.model,
        &data.run,
        data.exits_s,
        data.exits_d,
    );
    let (dd, ds) = (m.params().d_double, m.params().d_single);
    let t_end = r.mesh().trajectory.last().map_or(0.0, |p| p.tau);
    let t0 = t_end - 2.0 * m.excitation_period();
    let cyc = m.mesh_cycle_time();
    let win: Vec<_> = r.mesh().trajectory.iter().filter(|p| p.tau >= t0).collect();
    let xs: Vec<(f64, f64)> = win.iter().map(|p| ((p.tau - t0) / cyc, p.x)).collect();
    let fs: Vec<(f64, f64)> = win
        .iter()
        .map(|p| ((p.tau - t0) / cyc, p.mesh_force))
        .collect();
    let lvl: Vec<(f64, f64)> = win
        .iter()
        .map(|p| ((p.tau - t0) / cyc, m.backlash_at(m.cycle_position(p.tau))))
        .collect();
    // what the drawn window shows: the drive-side exits in each zone
    let exits_in = |level: f64| {
        r.mesh()
            .events
            .iter()
            .filter(|e| e.kind == EventKind::DriveExit && e.tau >= t0)
            .filter(|e| (e.x - level).abs() < 1e-6)
            .count()
    };
    let (drops_s, drops_d) = (exits_in(ds), exits_in(dd));
    let mut fig = line_figure(
        ctx,
        dir,
        "separation_mechanism",
        "From drive-side contact to separation: displacement, backlash and mesh force",
        "time (mesh cycles)",
        vec![
            (
                "x".into(),
                vec![
                    Line { label: "x".into(), points: xs, dots: false },
                    Line { label: "D(t): D_s single, D_d double zone".into(), points: lvl, dots: false },
                ],
            ),
            ("F_m".into(), vec![Line { label: "F_m".into(), points: fs, dots: false }]),
        ],
        &[0.0],
        &format!("Two mesh cycles at {} (linear contact law): the mesh force turns negative while x > D and drops to zero when x falls back to the backlash. In the two cycles drawn it drops to zero {} at D_s (single-tooth zone) and {} at D_d (double-tooth zone); over the last three periods (those with a trajectory) it leaves drive-side contact after a tensile force {} at D_s and {} at D_d.", sets(c), times(drops_s), times(drops_d), times(ns), times(nd)),
        false,
    )?;
    crate::shared::attach_trajectory(ctx, dir, &mut fig, "separation_mechanism", &win)?;
    let ok = ns > 0 && nd > 0;
    Ok(Section {
        id: "mechanism".into(),
        title: "Mechanism of separation: the mesh force jumps twice".into(),
        seed_ref: "003 §3.2; 004 §4.2 (Fig. 4.3), §6(2)".into(),
        parameters: format!(
            "{} (linear contact law; the seed names no point — {})",
            sets(c),
            if ok {
                format!("the first of {} candidates that shows both exits", data.candidates)
            } else {
                format!("none of the {} candidates shows both exits; the last one is shown", data.candidates)
            }
        ),
        method: "Dormand–Prince 5(4) with exact event location; drive-side exits located at x = D_s and x = D_d; tensile force = F_m < 0 in contact within 0.05 time units before the exit.".into(),
        figures: vec![fig],
        readings: vec![format!("D_d = {}, D_s = {}; exits with a tensile force before them: {ns} at D_s, {nd} at D_d.", f(dd), f(ds))],
        tables: vec![],
        claims: vec![Claim::new(
            "Contact persists with a reversed (tensile) mesh force until x reaches D_s, where the force jumps to zero; the double-tooth force then does the same at D_d — two abrupt changes",
            format!("{B003} §3.2; {B004} §4.2, §6(2)"),
            "two jumps: at D_s and at D_d",
            format!("{ns} exits at D_s and {nd} at D_d after a tensile force"),
            if ok { Verdict::Reproduced } else if ns + nd > 0 { Verdict::Partly } else { Verdict::NotReproduced },
            format!(
                "With damping only in contact, F_m = k (x - D) + c x' < 0 before x falls to D; contact ends exactly at x = D(t). With the internal pair's contact ratio {} the single-tooth zone is {} of the mesh cycle, so exits at D_s are rare.",
                f(m.params().eps),
                pct((2.0 - m.params().eps).max(0.0))
            ),
        )],
        alternatives: vec![],
        seconds: 0.0,
    })
}

/// `n` as words: `once`, `twice`, `3 times`, `never`.
fn times(n: usize) -> String {
    match n {
        0 => "never".into(),
        1 => "once".into(),
        2 => "twice".into(),
        n => format!("{n} times"),
    }
}
