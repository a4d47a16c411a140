//! Periodic-orbit branches over xi at the seed's F = 0.05, omega = 1.5 (linear law): the
//! period-1 branch from rest and the branch of the period-2 attractor, which explain the
//! multi-initial diagram's coexistence of 1-0-0-1-0 with a period 2 (incomplete bifurcation A).
//! Checks seed B 003 §4 (xi study) and 004 §4.4 (point A).

use super::{B003, B004, DD_SEED, DS_SEED};
use crate::claims::{Claim, Verdict};
use crate::readings::f;
use crate::runner::Ctx;
use crate::Section;
use anyhow::Result;
use geardyn_analysis::orbit_branches::{BifurcationKind, Continuation};
use geardyn_analysis::orbits_request::{run_orbits, OrbitsRequest};
use geardyn_scenario::Scenario;
use std::path::Path;

/// Arclength step of the continuations (a quarter of the default: the branches span a narrow
/// range of xi).
const ORBIT_DS: f64 = 0.005;
/// The period-2 branch turns at the lowest stable period-2 orbit when a fold or grazing of the
/// branch lies within this distance (in xi) of it.
const TURN_NEAR: f64 = 0.005;
/// ... and its unstable twin lies within this distance above it.
const TWIN_WITHIN: f64 = 0.01;

/// What the study computed: the branches over xi.
pub(super) struct OrbitsXiData {
    /// The scenario of the branches (linear law, F = 0.05, omega = 1.5, the nominal backlash).
    scenario: Scenario,
    /// The range of xi followed.
    range: (f64, f64),
    /// The period-2 attractor's state at xi = 0.02 (none: not reached from the grid).
    start: Option<[f64; 2]>,
    /// The period-1 branch from rest, merged with the period-2 branch.
    branches: Continuation,
    /// The branch of the period-3 orbit reached from rest at [`P3_AT`], followed over
    /// [`P3_RANGE`] (none: no period-3 orbit reached there).
    p3: Option<Continuation>,
}

/// Where the period-3 orbit of the large error amplitudes (the seed's final stable period 3) is
/// reached from rest ...
const P3_AT: f64 = 0.14;
/// ... and the range it is followed over: down through the seed's chaotic band (0.044, 0.126).
const P3_RANGE: (f64, f64) = (0.044, 0.15);

crate::runner::study!(OrbitsXi { lin: &'a Scenario } "orbits_xi" OrbitsXiData,
    |s, ctx, dir| compute(s.lin), |data| render(ctx, dir, data));

/// The period-1 branch from rest and the branch of the period-2 attractor found at xi = 0.02.
pub(super) fn compute(lin: &Scenario) -> Result<OrbitsXiData> {
    let set = [
        ("F", 0.05),
        ("omega", 1.5),
        ("D_d", DD_SEED),
        ("D_s", DS_SEED),
    ];
    let b = lin.with_all(&set)?;
    let (lo, hi) = (0.001, 0.045);
    let p1 = run_orbits(
        &b,
        &OrbitsRequest {
            range: Some(("xi".into(), lo, hi)),
            ds: ORBIT_DS,
            ..Default::default()
        },
        &|_| {},
    )?;
    // the period-2 attractor at xi = 0.02, reached from the first initial state of a small
    // grid that leads to it, followed down and up from there
    let at = 0.02;
    let mut start = None;
    'grid: for x0 in [0.5, 1.5, 0.0, 1.0, 2.0, -0.5] {
        for v0 in [-0.5, 0.5, 0.0, -1.0, 1.0] {
            let one = OrbitsRequest {
                range: None,
                y0: [x0, v0],
                ..Default::default()
            };
            if let Ok(c) = run_orbits(&b.with("xi", at)?, &one, &|_| {}) {
                if let Some(p) = c.points.first().filter(|p| p.orbit.period == 2) {
                    start = Some(p.orbit.y);
                    break 'grid;
                }
            }
        }
    }
    let mut c: Continuation = p1;
    if let Some(y0) = start {
        let req = OrbitsRequest {
            period: Some(2),
            transient: 0,
            y0,
            ds: ORBIT_DS,
            ..Default::default()
        };
        c = c.merge(crate::shared::branch_both_ways(
            &b,
            "xi",
            at,
            (lo, hi),
            &req,
        )?);
    }
    // the period-3 orbit of the large amplitudes, followed down into the chaotic band: where it
    // stays stable, it coexists with the chaos there
    let p3_start = run_orbits(&b.with("xi", P3_AT)?, &OrbitsRequest::default(), &|_| {})
        .ok()
        .and_then(|c| {
            c.points
                .first()
                .filter(|p| p.orbit.period == 3)
                .map(|p| p.orbit.y)
        });
    let p3 = match p3_start {
        Some(y0) => Some(crate::shared::branch_both_ways(
            &b,
            "xi",
            P3_AT,
            P3_RANGE,
            &OrbitsRequest {
                period: Some(3),
                transient: 0,
                y0,
                ds: ORBIT_DS,
                ..Default::default()
            },
        )?),
        None => None,
    };
    Ok(OrbitsXiData {
        scenario: b,
        range: (lo, hi),
        start,
        branches: c,
        p3,
    })
}

/// The orbit figure over the simulated points, the readings and the claim.
pub(super) fn render(ctx: &Ctx, dir: &Path, data: &OrbitsXiData) -> Result<Section> {
    let (b, (lo, hi), start, c) = (&data.scenario, data.range, data.start, &data.branches);
    let (fig, mut readings) = crate::shared::orbit_figure(
        ctx,
        dir,
        b,
        "xi",
        (lo, hi),
        [0.0, 0.0],
        ctx.n(40, 60),
        c,
        "Seed B: periodic orbits over xi",
        "Linear contact law at F = 0.05, omega = 1.5, D_d = 0.9, D_s = 1: the period-1 branch from rest and the branch of the period-2 attractor found at xi = 0.02, stable orbits as lines and unstable ones as dots, bifurcation points marked, over the stroboscopic points simulated from rest (grey).",
    )?;
    // the period-1 orbit's stable range; the period-2 branch's turn (a fold, smooth or at a
    // grazing: the stable orbit turns back into an unstable one of the same period) and its
    // stable range
    let p1_end = c
        .bifurcations
        .iter()
        .filter(|x| x.orbit.period == 1 && x.kind == BifurcationKind::PeriodDoubling)
        .map(|x| x.param)
        .reduce(f64::min);
    let p2 = |stable: bool| {
        c.points
            .iter()
            .filter(move |p| p.orbit.period == 2 && p.orbit.stable == stable)
    };
    let born = p2(true).map(|p| p.param).reduce(f64::min);
    let last = p2(true).map(|p| p.param).reduce(f64::max);
    // the turn: a fold or grazing of a period-2 branch beside the lowest stable orbit (the
    // branch points bracket it), with the unstable twin beside it
    let turn = born.and_then(|a| {
        let twin = p2(false).any(|p| p.param >= a && p.param <= a + TWIN_WITHIN);
        c.bifurcations
            .iter()
            .filter(|x| {
                x.orbit.period == 2
                    && matches!(x.kind, BifurcationKind::Fold | BifurcationKind::Grazing)
                    && (x.param - a).abs() < TURN_NEAR
            })
            .map(|x| x.param)
            .reduce(f64::min)
            .filter(|_| twin)
    });
    // how the branch turns there: a smooth fold (a multiplier at +1) or at a grazing
    let turn_kind = |t: f64| {
        let at = c
            .bifurcations
            .iter()
            .find(|x| x.orbit.period == 2 && x.param == t);
        match at {
            Some(x) if x.kind == BifurcationKind::Fold => format!(
                "a fold: a multiplier is {} there",
                f(x.orbit.multipliers[0].re)
            ),
            _ => "at a grazing".to_string(),
        }
    };
    let p1_stable = |xi: f64| {
        c.points
            .iter()
            .any(|p| p.orbit.period == 1 && p.orbit.stable && p.param >= xi)
            && p1_end.is_none_or(|e| e > xi)
    };
    // the period-2 orbit stays stable up to its first doubling (or as far as it was followed)
    let p2_end = |t: f64| {
        c.bifurcations
            .iter()
            .filter(|x| {
                x.orbit.period == 2 && x.kind == BifurcationKind::PeriodDoubling && x.param > t
            })
            .map(|x| x.param)
            .reduce(f64::min)
    };
    let window = match (turn, last) {
        (Some(t), Some(l)) if p1_stable(t) && t < l => {
            let e = p2_end(t).unwrap_or(l).min(p1_end.unwrap_or(f64::INFINITY));
            Some((t, e))
        }
        _ => None,
    };
    if let Some((a, e)) = window {
        readings.push(format!(
            "Stable period-1 and period-2 orbits coexist for xi in ({}, {}) (up to the first doubling of either): the period-2 orbit appears at xi = {}, where its branch turns ({}) into an unstable period-2 orbit, the saddle between the two basins; it is not born from the period-1 orbit, which stays stable until its doubling at xi = {}.",
            f(a),
            f(e),
            f(a),
            turn_kind(a),
            p1_end.map_or("the end of the range".into(), f)
        ));
    }
    readings.push(p3_reading(data.p3.as_ref()));
    if let Some(p3) = &data.p3 {
        let rows = geardyn_io::schema::orbit_rows(b, Some("xi"), &p3.points, 0.0);
        geardyn_io::schema::orbit_branch_table(Some("xi"), &rows)
            .write_csv(&dir.join("branch_p3.csv"), geardyn_io::schema::full)?;
    }
    let claim = Claim::new(
        "At the incomplete bifurcation the old period-1 solution stays stable while a new period-2 motion appears beside it",
        format!("{B003} §4 (xi study); {B004} §4.4 (point A)"),
        "P1 stable + new P2",
        match window {
            Some((a, e)) => format!("P2 appears at a fold at xi = {}; P1 and P2 both stable over ({}, {})", f(a), f(a), f(e)),
            None => match start {
                Some(_) => "no stable coexistence window on the branches".into(),
                None => "no period-2 attractor found at xi = 0.02".into(),
            },
        },
        Verdict::of(window.is_some()),
        "Shooting and pseudo-arclength continuation of the period-1 branch (from rest) and of the period-2 attractor's branch (found at xi = 0.02); reproduced when the period-2 branch turns (a fold, or at a grazing) inside the period-1 orbit's stable range, with its unstable twin beside it, so that both orbits are stable beside each other.",
    );
    Ok(Section {
        id: "orbits_xi".into(),
        title: "Periodic orbits over xi: what the incomplete bifurcation is".into(),
        seed_ref: format!("{B003} §4; {B004} §4.4"),
        parameters: format!("xi in [{lo}, {hi}], F = 0.05, omega = 1.5, D_d = {DD_SEED}, D_s = {DS_SEED}, linear contact law"),
        method: "Shooting on the stroboscopic map (Newton, monodromy matrix from the variational equation with saltation matrices, DP5 rtol 1e-11) and pseudo-arclength continuation over xi; the period-2 start is the period-2 attractor reached at xi = 0.02 from the first of a grid of initial states that leads to it.".into(),
        figures: vec![fig],
        readings,
        tables: vec![],
        claims: vec![claim],
        alternatives: vec![],
        seconds: 0.0,
    })
}

/// Where the period-3 branch is stable, in words: the intervals of xi of consecutive stable
/// orbits, and what that means inside the seed's chaotic band.
fn p3_reading(p3: Option<&Continuation>) -> String {
    let Some(c) = p3 else {
        return format!(
            "No period-3 orbit is reached from rest at xi = {}.",
            f(P3_AT)
        );
    };
    // stable stretches along each branch, in the order followed (a branch that turns back
    // passes a value twice, stable once and unstable once), then merged where they overlap
    let mut stable: Vec<(f64, f64)> = Vec::new();
    let mut open: Option<(usize, f64, f64)> = None;
    for p in c.points.iter().filter(|p| p.orbit.period == 3) {
        open = match (open, p.orbit.stable) {
            (Some((b, lo, hi)), true) if b == p.branch => {
                Some((b, lo.min(p.param), hi.max(p.param)))
            }
            (prev, s) => {
                stable.extend(prev.map(|(_, lo, hi)| (lo, hi)));
                s.then_some((p.branch, p.param, p.param))
            }
        };
    }
    stable.extend(open.map(|(_, lo, hi)| (lo, hi)));
    stable.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut merged: Vec<(f64, f64)> = Vec::new();
    for (lo, hi) in stable {
        match merged.last_mut() {
            Some(m) if lo <= m.1 => m.1 = m.1.max(hi),
            _ => merged.push((lo, hi)),
        }
    }
    let stable = merged;
    let text: Vec<String> = stable
        .iter()
        .map(|(a, b)| format!("{}–{}", f(*a), f(*b)))
        .collect();
    let low = stable.first().map(|r| r.0);
    format!(
        "The period-3 orbit reached from rest at xi = {}, followed over xi in [{}, {}] by continuation, is stable for xi in {}{}",
        f(P3_AT),
        f(P3_RANGE.0),
        f(P3_RANGE.1),
        if text.is_empty() { "no interval".to_string() } else { text.join(", ") },
        match low {
            Some(l) if l < 0.126 => format!(
                ": inside the seed's chaotic band (0.044, 0.126) it coexists with the chaotic attractor from xi = {} up{} (the multi-initial sweep of the xi study reaches both where its basin is large enough to be hit).",
                f(l),
                c.bifurcations
                    .iter()
                    .filter(|b| b.orbit.period == 3 && (b.param - l).abs() < 1e-3)
                    .map(|b| format!(" (its stable branch begins there, at a {})", b.kind.name()))
                    .next()
                    .unwrap_or_default()
            ),
            _ => ".".into(),
        }
    )
}
