//! B6: bifurcation and TLE over the static half backlash D (xi = 0.27, omega = 1.4): the
//! sequence of motions (1-1-1-1-1, 2-1-1-1-1, period doubling, chaos, period 3, long period),
//! coexistence at large backlash, and the same sweep for other loads, backlash steps and the
//! preset's contact law. Checks seed B 003 §3.3 and 004 §4.3 (Fig. 4.4), Table 4.1.

use super::param_sweep::{Case, Runs, SweepData, SweepTable, Texts};
use super::{
    chaos_ranges, has_name, ranges_text, tle_agreement, B003, B004, BACKLASH_STEP, F_BACKLASH,
};
use crate::claims::{Claim, Verdict};
use crate::classes::{self, tolerant, Class, Pt};
use crate::readings::{f, pct, sequence};
use anyhow::Result;
use geardyn_scenario::Scenario;

/// Loads of the sensitivity table (the chosen [`F_BACKLASH`] among them).
const SENSITIVITY_LOADS: [f64; 4] = [0.03, 0.05, 0.07, 0.1];
/// Border between small and large backlash in the coexistence and separation claims.
const LARGE_D: f64 = 1.15;
/// Values of D where the seed's small-backlash motion 1-1-1-1-1 is looked for.
const SMALL_D: (f64, f64) = (0.3, 0.45);

/// The sweep: D over [0.3, 2] at the seed's xi and omega, the chosen load and backlash step.
pub(super) const TABLE: SweepTable = SweepTable {
    id: "backlash_sweep",
    param: "D",
    set: &[
        ("xi", 0.27),
        ("omega", 1.4),
        ("F", F_BACKLASH),
        ("D_d", 1.0 - BACKLASH_STEP),
        ("D_s", 1.0),
    ],
    range: (0.3, 2.0),
    n: (40, 171),
    n_law: (30, 86),
    // multi-initial, coarse: coexistence at large backlash
    multi: ((0.3, 2.0), (12, 35), (4, 8)),
    multi_d: Some(1.0),
    n_sensitivity: (20, 69),
    cases,
    chaotic_column: false,
    texts: Texts {
        main: (
            "Bifurcation over the static half backlash D (xi = 0.27, omega = 1.4)",
            "Linear contact law, D_s = D, D_d = D - 0.2, F = 0.07: the five Poincaré sections of the seed (stroboscopic x; velocity at the crossings of ±D_s, ±D_d), P_ID and the TLE over D; colours by decided motion.",
        ),
        intervals: "Motion over D (linear law)",
        multi: (
            "Multi-initial diagram over D (coexisting attractors)",
            "Several random initial states per value (x0 ∈ ±4, x0' ∈ ±3 for D = 1: the attractor region, docs/analyses.md): points coloured by the attractor reached.",
        ),
        law: (
            "Comparison: the same sweep with the Johnson-type (Lankarani–Nikravesh) contact law",
            "The preset's contact law (exponent from the seed's Johnson table, restitution 0.8) at the same parameters, for comparison.",
        ),
        sensitivity: (
            "Sequence of motions over D for other loads F and backlash steps D_s - D_d (runs of at least two values)",
            &["F", "D_s - D_d", "sequence over D from 0.3 to 2"],
        ),
        title: (
            "Bifurcation and TLE over the static half backlash D (xi = 0.27, omega = 1.4)",
            "003 §3.3; 004 §4.3 (Fig. 4.4), Table 4.1",
        ),
    },
    words,
    claims,
};

/// The sensitivity to the chosen load and backlash step: every load of [`SENSITIVITY_LOADS`]
/// with the pair's own step (its labels keep p = r, q = s, as the seed's labels of this figure
/// do) and two nominal ones.
fn cases(lin: &Scenario) -> Result<Vec<Case>> {
    let phys = lin.get("D_s")? - lin.get("D_d")?;
    let mut out = Vec::new();
    for &fl in &SENSITIVITY_LOADS {
        for &st in &[phys, 0.1, 0.2] {
            let scenario = lin.with_all(&[
                ("xi", 0.27),
                ("omega", 1.4),
                ("F", fl),
                ("D_d", 1.0 - st),
                ("D_s", 1.0),
            ])?;
            let step = if st == phys {
                format!("{} (physical)", f(st))
            } else {
                f(st)
            };
            out.push(Case {
                name: format!("D sweep F {fl} step {st}"),
                cells: vec![f(fl), step],
                scenario,
            });
        }
    }
    Ok(out)
}

/// Parameters and method of the section.
fn words(data: &SweepData) -> (String, String) {
    let (n, sim) = (data.n, data.sim);
    (
        format!("D in [0.3, 2] ({n} values) with D_s = D and D_d = D - {} (chosen: the physical difference at the operating point is 0.002, too small for the seed's labels); xi = 0.27, omega = 1.4 (seed); F = {} (chosen: the seed gives none); linear contact law", f(BACKLASH_STEP), f(F_BACKLASH)),
        format!("Dormand–Prince 5(4), {} + {} periods from (0, 0); five Poincaré sections; TLE over the recorded periods; decided classification. Multi-initial and sensitivity sweeps coarser.", sim.transient_periods, sim.record_periods),
    )
}

/// The claims of the sweeps over D.
fn claims(runs: &Runs) -> Vec<Claim> {
    let (r, pts, mp) = (runs.main, &runs.pts, &runs.multi);
    let t = tolerant(pts);
    let coexist = |lo: f64, hi: f64| {
        let vals = classes::values_in(mp, lo, hi);
        let c = vals
            .iter()
            .filter(|&&v| {
                let ps: Vec<&Pt> = mp.iter().filter(|p| p.value == v).collect();
                classes::names(&ps).len() >= 2
            })
            .count();
        c as f64 / vals.len().max(1) as f64
    };
    let (co_small, co_large) = (coexist(0.3, LARGE_D), coexist(LARGE_D, 2.0));
    // claims
    let first = t.first().map(|p| p.name.clone()).unwrap_or_default();
    let small: Vec<&Pt> = classes::within(&t, SMALL_D.0, SMALL_D.1);
    let p1_small = small.iter().any(|p| p.name == "1-1-1-1-1");
    let a = has_name(&t, "2-1-1-1-1");
    let b4 = has_name(pts, "4-2-2-2-2");
    let b4b = has_name(pts, "4-1-1-1-1");
    let any4 = pts
        .iter()
        .find(|p| p.class == Class::Periodic(4))
        .map(|p| (p.value, p.name.clone()));
    let chaos = chaos_ranges(pts);
    // every chaotic value, isolated ones included (the tolerant reading above absorbs them)
    let chaos_all = classes::ranges(pts, |p| p.class == Class::Chaotic);
    let chaos_band = chaos_all.iter().any(|c| c.2 >= 2);
    let first_chaos = chaos.first().map(|c| c.0);
    // reverse doubling: a period-2 interval after a period-4 interval
    let iv = classes::intervals(&t);
    let rev = iv
        .windows(2)
        .any(|w| w[0].class == Class::Periodic(4) && w[1].class == Class::Periodic(2));
    let p3_after = first_chaos.and_then(|c0| {
        t.iter()
            .find(|p| p.value > c0 && p.class == Class::Periodic(3))
            .map(|p| p.value)
    });
    let chaos_after_p3 = p3_after.is_some_and(|v| chaos.iter().any(|c| c.0 > v));
    let long_period = t
        .iter()
        .filter(|p| p.class.period().is_some_and(|k| k >= 5))
        .map(|p| (p.value, p.name.clone()))
        .next_back();
    // the summary's order: period 3, chaos again, *then* the long period
    let chaos_back = p3_after.and_then(|v| chaos.iter().map(|c| c.0).find(|&c| c > v));
    let long_in_order = match (long_period.as_ref(), chaos_back) {
        (Some((v, _)), Some(c)) => *v > c,
        _ => false,
    };
    let (agree, with_tle, pos_chaos) = tle_agreement(pts);
    let pid = |lo: f64, hi: f64| {
        let w = classes::within(pts, lo, hi);
        let ps: Vec<f64> = r
            .iter()
            .filter(|x| x.value >= lo && x.value <= hi)
            .map(|x| x.runs[0].p_id)
            .collect();
        let _ = w;
        ps.iter().sum::<f64>() / ps.len().max(1) as f64
    };
    let (pid_lo, pid_hi) = (pid(0.3, LARGE_D), pid(LARGE_D, 2.0));
    let seq = sequence(&iv, 2);
    let chosen = format!(
        "F = {} and D_s - D_d = {} (chosen; the seed gives neither); sequence {seq}",
        f(F_BACKLASH),
        f(BACKLASH_STEP)
    );
    vec![
        Claim::new("Small backlash: stable 1-1-1-1-1 motion, crossing D_s, D_d, -D_s and -D_d", format!("{B003} §3.3; {B004} §4.3"), "1-1-1-1-1", format!("at D = 0.3: {first}"), Verdict::of(p1_small), chosen.clone()),
        Claim::new("As D grows, a bifurcation (A) to 2-1-1-1-1", format!("{B003} §3.3; {B004} §4.3 (point A)"), "2-1-1-1-1", a.map_or("not found".into(), |v| format!("2-1-1-1-1 from D = {}", f(v))), Verdict::of(a.is_some()), "Fixed initial state (0, 0)."),
        Claim::new("A period doubling (B) to 4-2-2-2-2", format!("{B004} §4.3 (point B)"), "4-2-2-2-2", match (&b4, &any4) { (Some(v), _) => format!("4-2-2-2-2 at D = {}", f(*v)), (None, Some((v, n))) => format!("period 4 ({n}) at D = {}", f(*v)), _ => "no period 4".into() }, if b4.is_some() { Verdict::Reproduced } else if any4.is_some() { Verdict::Partly } else { Verdict::NotReproduced }, "No period-4 motion from the fixed initial state at these parameters: 2-1-1-1-1 turns chaotic directly (see the sensitivity table for other loads and backlash steps)."),
        Claim::new("... leading to 4-1-1-1-1", format!("{B003} §3.3"), "4-1-1-1-1", b4b.map_or("not found".into(), |v| format!("at D = {}", f(v))), if b4b.is_some() { Verdict::Reproduced } else { Verdict::SeedInconsistent }, "A period doubling of 2-1-1-1-1 doubles the crossing counts (4-2-2-2-2, as the thesis writes); the summary's 4-1-1-1-1 contradicts it."),
        Claim::new("A reverse doubling (C) back to period 2", format!("{B004} §4.3 (point C)"), "4 → 2", format!("period 4 followed by period 2: {rev}"), Verdict::of(rev), "Needs the period-4 stage: without it (row above) there is no reverse doubling."),
        Claim::new("Chaos (D) with a positive TLE", format!("{B003} §3.3; {B004} §4.3 (point D)"), "chaos, TLE > 0", format!("chaos for D in {}; TLE > 0 at {pos_chaos} chaotic values; sign agrees with the class at {agree} of {with_tle}", ranges_text(&chaos_all)), if chaos_band && pos_chaos > 0 { Verdict::Reproduced } else if pos_chaos > 0 { Verdict::Partly } else { Verdict::NotReproduced }, if chaos_band { "TLE by the variational equation with saltation matrices.".to_string() } else if chaos_all.is_empty() { "TLE by the variational equation with saltation matrices. No value of the D grid is chaotic.".to_string() } else { "TLE by the variational equation with saltation matrices. Chaos appears only at isolated values of the grid (no two neighbours chaotic), not as the seed's chaotic region.".to_string() }),
        Claim::new("The chaos degenerates (E) to a period-3 window", format!("{B003} §3.3; {B004} §4.3 (point E)"), "period 3 after chaos", p3_after.map_or("none".into(), |v| format!("period 3 from D = {}", f(v))), Verdict::of(p3_after.is_some()), "Fixed initial state (0, 0); a period 3 after the main chaotic range is what the row needs (the motion over D: intervals_D.csv)."),
        Claim::new("Chaos returns after the period-3 window (F)", format!("{B003} §3.3; {B004} §4.3 (point F)"), "chaos again", format!("chaotic ranges: {}", ranges_text(&chaos)), Verdict::of(chaos_after_p3), "At these parameters the period-3 motion persists up to D = 2 (see the sensitivity table)."),
        Claim::new("Eventually a long-period motion emerges", format!("{B003} §3.3"), "long period", long_period.as_ref().map_or("none".into(), |(v, n)| format!("{n} at D = {}", f(*v))), if long_in_order { Verdict::Reproduced } else if long_period.is_some() { Verdict::Partly } else { Verdict::NotReproduced }, format!("Long = period ≥ 5 (the last one over D). The summary places it after the return of chaos; chaos after the period-3 window: {}.", chaos_back.map_or("none (row above)".into(), |c| format!("from D = {}", f(c))))),
        Claim::new("For large backlash periodic and chaotic motions coexist (stronger nonlinearity)", format!("{B004} §4.3; {B003} §3.3"), "coexistence at large D", format!("values with ≥ 2 motions among the initial states: D < {} {}, D ≥ {} {}", f(LARGE_D), pct(co_small), f(LARGE_D), pct(co_large)), Verdict::of(co_large > co_small), "Multi-initial diagram (second figure). Where it fails, all initial states at large D reach the same motion (3-1-1-1-1 at these parameters): larger backlash does not add attractors here."),
        Claim::new("Larger backlash increases tooth separation and back-side contact", format!("{B003} §3.3"), "more separation / back contact", format!("mean P_ID: D < {} {}, D ≥ {} {}", f(LARGE_D), f(pid_lo), f(LARGE_D), f(pid_hi)), Verdict::of(pid_hi > pid_lo), "P_ID = share of time in separation or back-side contact."),
    ]
}
