//! B7: bifurcation and TLE over the error amplitude xi (F = 0.05, omega = 1.5): the incomplete
//! bifurcations A and B (multi-initial), the complete bifurcation C, the chaotic band
//! (0.044, 0.126), the period-3 window and back-side contact; other backlash levels and the
//! preset's contact law beside. Checks seed B 003 §3.4 and 004 §4.4 (Fig. 4.6), Table 4.1.

use super::param_sweep::{Case, Runs, SweepData, SweepTable, Texts};
use super::{chaos_ranges, has_name, ranges_text, tle_agreement, B003, B004, DD_SEED, DS_SEED};
use crate::claims::{Claim, Verdict};
use crate::classes::{self, tolerant, Class, Pt};
use crate::coexisting;
use crate::readings::{f, sequence};
use anyhow::Result;
use geardyn_scenario::Scenario;

/// The TLE confirms the chaotic regions when its sign agrees with the decided class at this
/// many tenths of the values with a TLE, at least.
const TLE_AGREE_TENTHS: usize = 9;

/// The sweep: xi over [0.001, 0.3] at the seed's F and omega and the nominal backlash levels.
pub(super) const TABLE: SweepTable = SweepTable {
    id: "xi_sweep",
    param: "xi",
    set: &[
        ("F", 0.05),
        ("omega", 1.5),
        ("D_d", DD_SEED),
        ("D_s", DS_SEED),
    ],
    range: (0.001, 0.3),
    n: (60, 300),
    n_law: (40, 150),
    multi: ((0.001, 0.15), (30, 100), (6, 12)),
    multi_d: None,
    n_sensitivity: (30, 100),
    cases,
    chaotic_column: true,
    texts: Texts {
        main: (
            "Bifurcation over the error amplitude xi (F = 0.05, omega = 1.5)",
            "Linear contact law at the seed's F = 0.05, omega = 1.5, with D_d = 0.9, D_s = 1: the five Poincaré sections, P_ID and the TLE over xi; colours by decided motion.",
        ),
        intervals: "Motion over xi (linear law, initial state (0, 0))",
        multi: (
            "Multi-initial diagram over xi in [0.001, 0.15]: incomplete bifurcations",
            "Random initial states per value: coexisting attractors (the seed's incomplete bifurcations A and B) appear as several colours at one xi.",
        ),
        law: (
            "Comparison: the xi sweep with the Johnson-type (Lankarani–Nikravesh) law",
            "The preset's contact law at the same parameters, for comparison with the seed's linear law.",
        ),
        sensitivity: (
            "The xi sweep for other backlash levels (runs of at least two values)",
            &["D_s - D_d", "D_d", "D_s", "sequence over xi", "chaotic xi"],
        ),
        title: (
            "Bifurcation and TLE over the error amplitude xi (F = 0.05, omega = 1.5)",
            "003 §3.4; 004 §4.4 (Fig. 4.6), Table 4.1",
        ),
    },
    words,
    claims,
};

/// The backlash levels of the sensitivity table: the pair's own and three nominal steps.
fn cases(lin: &Scenario) -> Result<Vec<Case>> {
    let mut out = Vec::new();
    for (txt, lv) in [
        ("physical (pair)", None),
        ("0.05", Some((0.95, 1.0))),
        ("0.1 (chosen)", Some((DD_SEED, DS_SEED))),
        ("0.2", Some((0.8, 1.0))),
    ] {
        let s = match lv {
            Some((dd, ds)) => {
                lin.with_all(&[("F", 0.05), ("omega", 1.5), ("D_d", dd), ("D_s", ds)])?
            }
            None => lin.with_all(&[("F", 0.05), ("omega", 1.5)])?,
        };
        out.push(Case {
            name: format!("xi sweep step {txt}"),
            cells: vec![
                txt.to_string(),
                f(s.params().d_double),
                f(s.params().d_single),
            ],
            scenario: s,
        });
    }
    Ok(out)
}

/// Parameters and method of the section.
fn words(data: &SweepData) -> (String, String) {
    let (n, sim) = (data.n, data.sim);
    (
        format!("xi in [0.001, 0.3] ({n} values), F = 0.05, omega = 1.5 (seed); D_d = {}, D_s = {} (chosen: the seed gives only D_s > D_d; other levels in the sensitivity table); linear contact law", f(data.levels.0), f(data.levels.1)),
        format!("Dormand–Prince 5(4), {} + {} periods from (0, 0), five sections, TLE; multi-initial sweep over [0.001, 0.15].", sim.transient_periods, sim.record_periods),
    )
}

/// The claims of the sweeps over xi.
fn claims(runs: &Runs) -> Vec<Claim> {
    let (pts, mp) = (&runs.pts, &runs.multi);
    let t = tolerant(pts);
    let chaos = chaos_ranges(pts);
    let main = chaos.iter().max_by_key(|c| c.2).copied();
    let small = t.first().map(|p| p.name.clone()).unwrap_or_default();
    let coexist_with = |a: &str, pred: &dyn Fn(&Pt) -> bool| -> Option<f64> {
        let mut vals: Vec<f64> = mp.iter().map(|p| p.value).collect();
        vals.dedup();
        vals.into_iter().find(|&v| {
            let ps: Vec<&Pt> = mp.iter().filter(|p| p.value == v).collect();
            ps.iter().any(|p| p.name == a) && ps.iter().any(|p| p.name != a && pred(p))
        })
    };
    let inc_a = coexist_with("1-0-0-1-0", &|p| p.name == "2-1-0-1-0");
    let inc_a_any = coexist_with("1-0-0-1-0", &|p| p.class == Class::Periodic(2));
    let inc_b = {
        let mut vals: Vec<f64> = mp.iter().map(|p| p.value).collect();
        vals.dedup();
        vals.into_iter().find(|&v| {
            let ps: Vec<&Pt> = mp.iter().filter(|p| p.value == v).collect();
            let p2: Vec<&String> = {
                let mut n: Vec<&String> = ps
                    .iter()
                    .filter(|p| p.class == Class::Periodic(2))
                    .map(|p| &p.name)
                    .collect();
                n.sort();
                n.dedup();
                n
            };
            (p2.len() >= 2 || !p2.is_empty()) && ps.iter().any(|p| p.class == Class::Periodic(3))
        })
    };
    let c4 = has_name(pts, "4-2-0-2-0").or_else(|| has_name(mp, "4-2-0-2-0"));
    let (agree, with_tle, pos_chaos) = tle_agreement(pts);
    let after: Vec<&Pt> = main.map_or(vec![], |m| t.iter().filter(|p| p.value > m.1).collect());
    let p3_window = after.iter().any(|p| p.class == Class::Periodic(3));
    let chaos_again = main.is_some_and(|m| chaos.iter().any(|c| c.0 > m.1));
    let cascade = after
        .iter()
        .any(|p| p.class.period().is_some_and(|k| k == 6 || k == 12));
    let ends_p3 = t.last().is_some_and(|p| p.class == Class::Periodic(3));
    let back_first = t.iter().find(|p| p.back).map(|p| p.value);
    let seq = sequence(&classes::intervals(&t), 2);
    vec![
        Claim::new("Small xi: constant 1-0-0-1-0 motion (stable meshing)", format!("{B004} §4.4"), "1-0-0-1-0", format!("at xi = 0.001: {small}"), Verdict::of(small == "1-0-0-1-0"), "Linear contact law, D_d = 0.9, D_s = 1 (with the pair's physical levels, 0.002 apart, the motion stays in contact: see the sensitivity table)."),
        Claim::new("An incomplete bifurcation (A): 1-0-0-1-0 coexists with 2-1-0-1-0", format!("{B004} §4.4 (point A); {B003} §3.4"), "1-0-0-1-0 + 2-1-0-1-0", match (inc_a, inc_a_any) { (Some(v), _) => format!("both at xi = {}", f(v)), (None, Some(v)) => format!("1-0-0-1-0 with another period 2 at xi = {}", f(v)), _ => "no coexistence found".into() }, if inc_a.is_some() { Verdict::Reproduced } else if inc_a_any.is_some() { Verdict::Partly } else { Verdict::NotReproduced }, "Multi-initial sweep (second figure): both labels at one xi; 1-0-0-1-0 beside a period 2 of another label counts as partly."),
        Claim::new("A second incomplete bifurcation (B): period-2 motions coexist with 3-1-0-1-0", format!("{B004} §4.4 (point B)"), "P2 + P2 + 3-1-0-1-0", inc_b.map_or("no period 2 beside a period 3".into(), |v| format!("period 2 beside period 3 at xi = {}", f(v))), if inc_b.is_some() { Verdict::Reproduced } else { Verdict::NotReproduced }, "Multi-initial sweep: a value of xi where a period 2 and a period 3 are both reached is what the row needs."),
        Claim::new("A complete bifurcation (C) to 4-2-0-2-0", format!("{B004} §4.4 (point C)"), "4-2-0-2-0", c4.map_or("not found".into(), |v| format!("at xi = {}", f(v))), Verdict::of(c4.is_some()), "The label 4-2-0-2-0 among the runs of the fixed and multi-initial sweeps over xi."),
        xi_band_claim(pts, mp),
        Claim::new("Then a period-3 window, a period-doubling cascade to chaos, and finally a stable period 3", format!("{B003} §3.4"), "P3 window, cascade, chaos, P3", format!("after the main chaos: period 3 {p3_window}, period 6/12 {cascade}, chaos again {chaos_again}, period 3 at xi = 0.3 {ends_p3}"), Verdict::of_parts(&[p3_window, cascade || chaos_again, ends_p3]), format!("Sequence: {seq}.")),
        Claim::new("The TLE confirms the chaotic regions", format!("{B003} §3.4"), "TLE > 0 where chaotic", format!("TLE > 0 at {pos_chaos} chaotic values; sign agrees with the class at {agree} of {with_tle}"), Verdict::of(with_tle > 0 && agree * 10 >= with_tle * TLE_AGREE_TENTHS), "TLE over the recorded periods."),
        Claim::new("The error amplitude triggers back-side contact and tooth separation", format!("{B003} §3.4; {B004} §4.4"), "back-side contact appears with xi", back_first.map_or("no back-side contact".into(), |v| format!("back-side contact from xi = {}", f(v))), Verdict::of(back_first.is_some()), "Back-side contact = crossings of -D_s or -D_d."),
    ]
}

/// The seed's chaotic band of xi (004 §4.4).
const XI_BAND: (f64, f64) = (0.044, 0.126);
/// The largest chaotic range reproduces [`XI_BAND`] when its ends lie within these distances
/// of the seed's (lower, upper).
const XI_BAND_TOLERANCE: (f64, f64) = (0.015, 0.02);

/// The chaotic band of the xi sweep (004 §4.4: chaos and complex motion for xi in (0.044, 0.126)),
/// from the runs `pts` of one initial state.
///
/// `multi` (the runs of a multi-initial sweep, empty for none) adds the periodic attractors that
/// coexist with the chaos inside the band, with their shares of the initial states: the chaos
/// there holds on part of the state space only.
pub(super) fn xi_band_claim(pts: &[Pt], multi: &[Pt]) -> Claim {
    let chaos = chaos_ranges(pts);
    let main = chaos.iter().max_by_key(|c| c.2).copied();
    let ends = main.map(|m| ((m.0 - XI_BAND.0).abs(), (m.1 - XI_BAND.1).abs()));
    let in_band: Vec<&Pt> = main.map_or(vec![], |m| classes::within(multi, m.0, m.1));
    let beside = coexisting::describe(&coexisting::found(&in_band), |a| a.periodic, "xi", 4);
    let every = match (in_band.is_empty(), beside.is_empty()) {
        (true, _) => String::new(),
        (false, true) => "; every run from random initial states inside it is chaotic".into(),
        (false, false) => format!(
            "; over every attractor (runs from random initial states inside it), periodic attractors coexist with the chaos: {beside}"
        ),
    };
    Claim::new(
        "Chaos and complex motion for xi in (0.044, 0.126)",
        format!("{B004} §4.4, §4.5, §6(3)"),
        "(0.044, 0.126)",
        format!("chaos from rest for xi in {}{every}", ranges_text(&chaos)),
        match ends {
            Some((a, b)) if a <= XI_BAND_TOLERANCE.0 && b <= XI_BAND_TOLERANCE.1 => {
                Verdict::Reproduced
            }
            Some(_) => Verdict::Partly,
            None => Verdict::NotReproduced,
        },
        format!(
            "Largest chaotic range compared with the seed's ends (tolerance {} / {}).",
            f(XI_BAND_TOLERANCE.0),
            f(XI_BAND_TOLERANCE.1)
        ),
    )
}
