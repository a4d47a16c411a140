//! The five meshing-impact states of seed A (double-tooth drive, single-tooth zones, separation,
//! back side) along a trajectory of the broken pair, and the contact force in each. Checks seed A
//! 000 ¶5 (list of states), 001 §2.3 and 002 §2.2, §5.1 (table of the contact force).

use super::{A000, A001, A002, OMEGA_LOAD};
use crate::claims::{Claim, Verdict};
use crate::readings::{f, pct};
use crate::runner::{hdr, Ctx};
use crate::shared::{line_figure, Line};
use crate::Section;
use anyhow::Result;
use geardyn_analysis::simulate::{simulate, SimOptions, SimResult};
use geardyn_model::{EventKind, MeshModel};
use geardyn_physics::PairModel;
use geardyn_scenario::Scenario;
use std::path::Path;

/// Contact state and zone of a trajectory sample: 0 double drive, 1 single I, 2 single II,
/// 3 separation, 4 back side.
fn state_of(model: &MeshModel, pm: &PairModel, tau: f64, state: i8) -> usize {
    if state == 0 {
        return 3;
    }
    if state < 0 {
        return 4;
    }
    let u = model.cycle_position(tau);
    let n = u.floor();
    let phase = u - n;
    let nb = pm.spec.breakage.map_or(0, |b| b.broken_cycle) as f64;
    let eps = pm.geom.eps;
    let eb = pm.eps_b.unwrap_or(eps);
    if n == nb {
        if phase < eb - 1.0 {
            0
        } else if phase < eps - 1.0 {
            2
        } else {
            1
        }
    } else if phase < eps - 1.0 {
        0
    } else {
        1
    }
}

const STATES: [&str; 5] = [
    "double-tooth drive-side meshing",
    "single-tooth drive-side meshing I",
    "single-tooth drive-side meshing II",
    "tooth separation",
    "back-side impact / contact",
];

/// The contact force is reproduced when it is positive at this share of the drive-side samples
/// (the rest: the damping term just before contact ends) ...
const DRIVE_POSITIVE: f64 = 0.97;
/// ... and partly above this share.
const DRIVE_POSITIVE_PARTLY: f64 = 0.8;

/// What the study computed: one run of the broken pair, sorted into the five states.
pub(super) struct StatesData {
    /// The point (omega, F).
    sets: [(&'static str, f64); 2],
    /// Its scenario.
    scenario: Scenario,
    /// Integration settings.
    sim: SimOptions,
    /// Its model.
    model: MeshModel,
    /// The run from (0, 0), with trajectory.
    run: SimResult,
    /// Time in each state.
    time: [f64; 5],
    /// Samples with a positive, negative and zero mesh force, per state.
    signs: [[usize; 5]; 3],
    /// Back-side impacts.
    impacts: usize,
    /// The recorded revolution shown (the one showing the most states, from 0).
    best: u64,
    /// Its start and the window of four mesh cycles around the broken one (times).
    window: (f64, f64, f64),
}

crate::runner::study!(States { pm: &'a PairModel, base: &'a Scenario } "states" StatesData,
    |s, ctx, dir| compute(ctx, s.pm, s.base), |data| render(ctx, dir, s.pm, s.base, data));

/// Runs the broken pair at a point with chaos and impacts and sorts its samples into the states.
pub(super) fn compute(ctx: &Ctx, pm: &PairModel, base: &Scenario) -> Result<StatesData> {
    let sets = [("omega", OMEGA_LOAD), ("F", 0.05)];
    let s = base.with_all(&sets)?;
    let m = s.model().clone();
    let sim = SimOptions {
        trajectory: true,
        samples_per_cycle: 64,
        ..ctx.sim((60, 150), (4, 10))
    };
    let r = simulate(&m, [0.0, 0.0], &sim)?;
    let mut time = [0.0f64; 5];
    let mut pos = [0usize; 5];
    let mut neg = [0usize; 5];
    let mut zero = [0usize; 5];
    for w in r.mesh().trajectory.windows(2) {
        let k = state_of(&m, pm, w[0].tau, w[0].state);
        time[k] += w[1].tau - w[0].tau;
        if w[0].mesh_force > 1e-12 {
            pos[k] += 1;
        } else if w[0].mesh_force < -1e-12 {
            neg[k] += 1;
        } else {
            zero[k] += 1;
        }
    }
    let impacts = r
        .mesh()
        .events
        .iter()
        .filter(|e| e.kind == EventKind::Impact)
        .count();
    // a window of four mesh cycles around the broken one, in the recorded revolution that
    // shows the most states
    let nb = pm.spec.breakage.map_or(0, |b| b.broken_cycle) as f64;
    let period = m.excitation_period();
    let cyc = m.mesh_cycle_time();
    let t_rec = r.mesh().trajectory.first().map_or(0.0, |p| p.tau);
    let imp_t = impacts_of(&r);
    let window = |k: u64| {
        let t_start = t_rec + k as f64 * period;
        (
            t_start,
            t_start + (nb - 1.0) * cyc,
            t_start + (nb + 3.0) * cyc,
        )
    };
    let score = |k: u64| {
        let (_, w0, w1) = window(k);
        let mut seen = [false; 5];
        for p in r
            .mesh()
            .trajectory
            .iter()
            .filter(|p| p.tau >= w0 && p.tau <= w1)
        {
            seen[state_of(&m, pm, p.tau, p.state)] = true;
        }
        if imp_t.iter().any(|t| t.0 >= w0 && t.0 <= w1) {
            seen[4] = true;
        }
        seen.iter().filter(|&&b| b).count()
    };
    let best = (1..sim.record_periods.max(1))
        .max_by_key(|&k| (score(k), std::cmp::Reverse(k)))
        .unwrap_or(0);
    Ok(StatesData {
        sets,
        window: window(best),
        scenario: s,
        sim,
        model: m,
        run: r,
        time,
        signs: [pos, neg, zero],
        impacts,
        best,
    })
}

/// The table of the states, the window figure and the claims.
pub(super) fn render(
    ctx: &Ctx,
    dir: &Path,
    pm: &PairModel,
    base: &Scenario,
    data: &StatesData,
) -> Result<Section> {
    let (sets, s, sim, m, r) = (&data.sets, &data.scenario, data.sim, &data.model, &data.run);
    let (time, impacts, best) = (data.time, data.impacts, data.best);
    let [pos, neg, zero] = data.signs;
    let (t_start, w0, w1) = data.window;
    let cyc = m.mesh_cycle_time();
    let imp_t = impacts_of(r);
    let total: f64 = time.iter().sum::<f64>().max(1e-12);
    let rows: Vec<Vec<String>> = (0..5)
        .map(|k| {
            let n = pos[k] + neg[k] + zero[k];
            vec![
                STATES[k].to_string(),
                if k == 4 {
                    format!("{impacts} impacts")
                } else {
                    pct(time[k] / total)
                },
                if n == 0 {
                    "–".into()
                } else {
                    format!(
                        "{} > 0, {} = 0, {} < 0",
                        pct(pos[k] as f64 / n as f64),
                        pct(zero[k] as f64 / n as f64),
                        pct(neg[k] as f64 / n as f64)
                    )
                },
            ]
        })
        .collect();
    let table = ctx.table(
        &dir.join("states.csv"),
        "Time share of each meshing-impact state and the sign of the mesh force in it",
        &hdr(&["state", "time share", "mesh force F_m (samples)"]),
        rows,
    )?;
    let win: Vec<_> = r
        .mesh()
        .trajectory
        .iter()
        .filter(|p| p.tau >= w0 && p.tau <= w1)
        .collect();
    let at = |t: f64| (t - t_start) / cyc;
    let xs: Vec<(f64, f64)> = win.iter().map(|p| (at(p.tau), p.x)).collect();
    let fs: Vec<(f64, f64)> = win.iter().map(|p| (at(p.tau), p.mesh_force)).collect();
    let mut sts: Vec<(f64, f64)> = win
        .iter()
        .map(|p| (at(p.tau), state_of(m, pm, p.tau, p.state) as f64))
        .collect();
    sts.extend(
        imp_t
            .iter()
            .filter(|t| t.0 >= w0 && t.0 <= w1)
            .map(|t| (at(t.0), 4.0)),
    );
    let d = m.params().d_single;
    let dl = |v: f64| -> Vec<(f64, f64)> { vec![(at(w0), v), (at(w1), v)] };
    let mut fig = line_figure(
        ctx,
        dir,
        "states_window",
        "Displacement, mesh force and meshing-impact state around the broken cycle",
        "mesh cycles from the start of the revolution (the chipped tooth meshes in cycle 0)",
        vec![
            (
                "x".into(),
                vec![
                    Line { label: "x".into(), points: xs, dots: false },
                    Line { label: "±D".into(), points: dl(d), dots: false },
                    Line { label: "±D".into(), points: dl(-d), dots: false },
                ],
            ),
            (
                "F_m".into(),
                vec![Line { label: "F_m".into(), points: fs, dots: false }],
            ),
            (
                "state (caption)".into(),
                vec![Line { label: "state".into(), points: sts, dots: true }],
            ),
        ],
        &[],
        &format!("Four mesh cycles around the broken one (revolution {} of the record, the one showing the most states): displacement with the backlash ±D, the dynamic mesh force and the state: 0 double-tooth, 1 single-tooth I, 2 single-tooth II (breakage), 3 separation, 4 back-side impact.", best + 1),
        false,
    )?;
    crate::shared::attach_trajectory(ctx, dir, &mut fig, "states_window", &win)?;
    let seen: Vec<bool> = (0..5)
        .map(|k| if k == 4 { impacts > 0 } else { time[k] > 0.0 })
        .collect();
    let drive_pos = (pos[0] + pos[1] + pos[2]) as f64
        / (pos[0] + pos[1] + pos[2] + neg[0] + neg[1] + neg[2] + zero[0] + zero[1] + zero[2]).max(1)
            as f64;
    let sep_zero = zero[3] == pos[3] + neg[3] + zero[3];
    Ok(Section {
        id: "states".into(),
        title: "The five meshing-impact states".into(),
        seed_ref: "000 ¶5 (list of states); 001 §2.3; 002 §2.2 and §5.1 (table of the contact force)".into(),
        parameters: format!(
            "{} (a point with chaos and back-side impacts; the seed names no point), xi = {}, R = {}",
            crate::readings::sets(sets),
            f(s.params().xi),
            f(base.get("R").unwrap_or(f64::NAN))
        ),
        method: format!(
            "Dormand–Prince 5(4), {} excitation periods (revolutions) of transient, {} recorded; every trajectory sample assigned to a state from its contact state and its zone in the revolution.",
            sim.transient_periods, sim.record_periods
        ),
        figures: vec![fig],
        readings: vec![],
        tables: vec![table],
        claims: vec![
            Claim::new(
                "The pair passes through five meshing-impact states: double-tooth, single-tooth I, single-tooth II (from the breakage), separation, back-side impact",
                format!("{A000} ¶5; {A001} §2.3; {A002} §2.2"),
                "five states",
                format!("{} of 5 states occur", seen.iter().filter(|&&b| b).count()),
                Verdict::of(seen.iter().all(|&b| b)),
                format!("Time shares: {}; {impacts} impacts.", (0..4).map(|k| format!("{} {}", STATES[k], pct(time[k] / total))).collect::<Vec<_>>().join(", ")),
            ),
            Claim::new(
                "Contact force: F_m > 0 in tooth-surface meshing, F_m = 0 in separation, F_m < 0 at back-side impact",
                format!("{A002} §5.1 (table)"),
                "> 0 / = 0 / < 0",
                format!("drive contact: F_m > 0 at {} of samples; separation: F_m = 0 at all samples: {}; back side: impact forces act in the negative direction ({impacts} impacts)", pct(drive_pos), sep_zero),
                if sep_zero && drive_pos > DRIVE_POSITIVE { Verdict::Reproduced } else if sep_zero && drive_pos > DRIVE_POSITIVE_PARTLY { Verdict::Partly } else { Verdict::NotReproduced },
                "The few negative drive-side samples are the damping term c x' just before contact ends (x > D with x' < 0), the mechanism seed B describes; the impact force is the Lankarani–Nikravesh peak of each impact (model §8).",
            ),
        ],
        alternatives: vec![],
        seconds: 0.0,
    })
}

/// The back-side impacts of a run: (time, x).
fn impacts_of(r: &SimResult) -> Vec<(f64, f64)> {
    r.mesh()
        .events
        .iter()
        .filter(|e| e.kind == EventKind::Impact)
        .map(|e| (e.tau, e.x))
        .collect()
}
