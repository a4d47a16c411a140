//! B10–B12 over omega (F = 0.07, xi = 0.23): the coexisting attractors of seed B's table over
//! omega from a multi-initial diagram, the bifurcation-safety tree (continuation) and basins at
//! the seed's points 0.364, 0.42 and 1.801. Checks seed B 003 §4.3 (Table 5) and 004 §5.3
//! (Figs. 5.3, 5.5, Table 5.1).

use super::attractor_tables::{
    extra_boxes_text, found_in, labelled_basin_claim, presence, sp, spl, table_row, AttractorsData,
    PRESENT,
};
use super::attractors::AttractorTable;
use super::{B003, B004};
use crate::claims::{resolve_conflicts, Claim, Verdict};
use crate::classes::{self, Class, Pt};
use crate::readings::f;
use geardyn_analysis::basins::BasinResult;
use geardyn_analysis::bifurcation::linspace;

/// The seed's points where basins are drawn (G1 at 0.364 and 0.42, G3 at 1.801).
const BASIN_OMEGAS: [f64; 3] = [0.364, 0.42, 1.801];
/// The first coexistence of Q1 with a healthy period 1 matches a seed's G1 (0.364 or 0.42) when
/// it lies within this distance of it (and nearer to it than to the other).
const G1_TOLERANCE: f64 = 0.03;

/// The study: omega over [0.01, 3] at F = 0.07, xi = 0.23.
pub(super) const TABLE: AttractorTable = AttractorTable {
    id: "attractors_omega",
    param: "omega",
    set: &[("F", 0.07), ("xi", 0.23)],
    at: "F = 0.07, xi = 0.23",
    values: |ctx| {
        let mut values = ctx.n(vec![0.03], vec![0.01, 0.03, 0.06]);
        values.extend(linspace(0.1, 3.0, ctx.n(30, 146)));
        values.extend([0.364, 0.42, 0.56, 0.6, 1.801, 1.812]);
        values
    },
    continuation: |ctx| {
        let mut v = vec![0.03];
        v.extend(linspace(0.1, 3.0, ctx.n(20, 59)));
        v
    },
    // (no extra boxes at 0.364)
    basins: &[
        (BASIN_OMEGAS[0], false),
        (BASIN_OMEGAS[1], true),
        (BASIN_OMEGAS[2], true),
    ],
    markers: &[
        0.2, 0.364, 0.42, 0.5, 0.56, 0.6, 0.68, 1.0, 1.4, 1.801, 2.0, 2.6,
    ],
    multi_caption: "Linear contact law: runs from random initial states per omega, coloured by the attractor label (decided classification); the second panel shows back-side crossings of -D_s.",
    title: (
        "Coexisting attractors over omega (F = 0.07, xi = 0.23): multi-initial diagram, safety tree and basins",
        "003 §4.3 (Table 5); 004 §5.3 (Figs. 5.3, 5.5, Table 5.1)",
    ),
    words,
    claims,
};

/// Parameters and method of the section.
fn words(data: &AttractorsData) -> (String, String) {
    let (d, values, ics, nb) = (data.d, &data.values, data.ics, data.nb);
    let box_txt = &data.basins[0].boxes[0].0;
    (
        format!("omega in [0.01, 3] ({} values, extra values at the seed's points 0.364, 0.42, 1.801, 1.812), F = 0.07, xi = 0.23 (seed); physical backlash; linear contact law; basins {nb} × {nb} on {box_txt} (shares of the seed's attractors also read on {}: the seed gives no box)", values.len(), extra_boxes_text(d)),
        format!("Multi-initial: {ics} random initial states per value (x0 ∈ ±1.5 D_s, x0' ∈ ±1), decided classification; continuation: attractors identified on the stroboscopic section and matched by basin overlap; basins at the seed's points."),
    )
}

/// The claims of the seed's table, by range of omega.
fn claims(data: &AttractorsData) -> Vec<Claim> {
    let pts = classes::points(&data.multi, 0);
    let basin_res = data.basin_results();
    let mut claims = low_claims(&pts, basin_res[1], data.ics);
    claims.extend(middle_claims(&pts));
    claims.extend(high_claims(&pts, basin_res[2]));
    resolve_conflicts(
        &mut claims,
        &[
            "omega in (1.261, 1.526): Q2 (healthy) with chaos (PN)",
            "omega in (1.26, 1.52): Q2 (stable) with P3 (unstable)",
            "omega in (1.261, 1.526): stable 3-1-1-1-1 (P3) coexisting with chaos (PN)",
        ],
    );
    resolve_conflicts(
        &mut claims,
        &[
            "omega in (1.80, 1.89): Q1 (stable) and P3",
            "omega in (1.802, 1.891): Q2 (healthy) and P3",
        ],
    );
    claims
}

/// The healthy P1 of seed B's omega table (1-0-0-1-0).
fn p1(p: &Pt) -> bool {
    p.name == "1-0-0-1-0"
}
/// Q1 with back-side contact (1-1-1-1-1).
fn q1(p: &Pt) -> bool {
    p.name == "1-1-1-1-1"
}
/// A healthy period 1.
fn h1(p: &Pt) -> bool {
    p.class == Class::Periodic(1) && p.healthy
}
/// A non-healthy period 1.
fn u1(p: &Pt) -> bool {
    p.class == Class::Periodic(1) && !p.healthy
}
/// A healthy period 2.
fn q2h(p: &Pt) -> bool {
    p.class == Class::Periodic(2) && p.healthy
}
/// A non-healthy period 3.
fn p3(p: &Pt) -> bool {
    p.class == Class::Periodic(3) && !p.healthy
}
/// Chaos.
fn chaos(p: &Pt) -> bool {
    p.class == Class::Chaotic
}

/// The table's sources: 004 Table 5.1 and 003 Table 5.
fn tables() -> (String, String) {
    (format!("{B004} Table 5.1"), format!("{B003} Table 5"))
}

/// Below omega = 0.42: P1 alone, the incomplete bifurcation G1 (both places the seeds give it)
/// and the basin shares at 0.42 (`bq`).
fn low_claims(pts: &[Pt], bq: &[(String, BasinResult)], ics: usize) -> Vec<Claim> {
    let (t51, t5) = tables();
    let only = |a: f64, bb: f64, test: fn(&Pt) -> bool| -> bool {
        pts.iter()
            .filter(|p| p.value >= a && p.value <= bb)
            .all(&test)
    };
    let mut claims = Vec::new();
    let low_only = only(0.0, 0.36, p1);
    let low_h1 = only(0.0, 0.36, h1);
    claims.push(Claim::new(
        "omega in (0.01, 0.42): only the healthy period-1 motion P1 = 1-0-0-1-0",
        format!("{t51}; {t5}; {B004} §5.3"),
        "P1 (1-0-0-1-0) only",
        format!("found for omega ≤ 0.36: {}", found_in(pts, 0.0, 0.36 / 0.85)),
        if low_only {
            Verdict::Reproduced
        } else if low_h1 || presence(pts, 0.01, 0.42, h1) >= PRESENT {
            Verdict::Partly
        } else {
            Verdict::NotReproduced
        },
        format!("{ics} random initial states per value, omega from 0.01. With the pair's physical backlash (D_s - D_d = 0.002) the healthy period-1 motion stays in contact (label 1-0-0-0-0): the seed's crossing of D_d needs a larger backlash step (sensitivity table)."),
    ));
    // G1: the first value where the back-side Q1 coexists with a healthy period 1
    let first_q1 = {
        let mut vals: Vec<f64> = pts.iter().map(|p| p.value).collect();
        vals.dedup();
        vals.into_iter().find(|&v| {
            pts.iter().any(|p| p.value == v && q1(p)) && pts.iter().any(|p| p.value == v && h1(p))
        })
    };
    for (seed_w, other_w, src) in [
        (0.364, 0.42, format!("{B004} §5.3 (G1 at omega = 0.364)")),
        (0.42, 0.364, format!("{B003} §4.3 and Table 5; {t51}")),
    ] {
        let verdict = match first_q1 {
            Some(v)
                if (v - seed_w).abs() <= (v - other_w).abs()
                    && (v - seed_w).abs() <= G1_TOLERANCE =>
            {
                Verdict::Reproduced
            }
            Some(v)
                if (v - other_w).abs() < (v - seed_w).abs()
                    && (v - other_w).abs() <= G1_TOLERANCE =>
            {
                Verdict::SeedInconsistent
            }
            Some(_) => Verdict::Partly,
            None => Verdict::NotReproduced,
        };
        claims.push(Claim::new(
            format!("An incomplete bifurcation (G1) at omega = {seed_w} adds Q1 = 1-1-1-1-1 (back-side contact) beside the healthy P1"),
            src,
            format!("omega = {seed_w}"),
            first_q1.map_or("P1 and Q1 never coexist".into(), |v| format!("a healthy period 1 and 1-1-1-1-1 first coexist at omega = {}", f(v))),
            verdict,
            "The thesis text gives 0.364, both tables and the summary 0.42: the row nearer to the measurement is reproduced, the other is a seed inconsistency. Multi-initial sweep with extra values at 0.364 and 0.42.",
        ));
    }
    // by label: another healthy period 1 there (1-1-0-1-0) is not the seed's P1
    claims.push(labelled_basin_claim(
        bq,
        &[("P1", "1-0-0-1-0", 0.49), ("Q1", "1-1-1-1-1", 0.51)],
        "At omega = 0.42 the healthy P1 holds 49 % of the basin, Q1 51 %",
        format!("{B003} §4.3; {B004} §5.3 (Fig. 5.5b)"),
    ));
    claims
}

/// The rows from omega = 0.42 to 1.526: Q1 with P1, R1 and R2, chaos, and Q2 or P3 with chaos.
fn middle_claims(pts: &[Pt]) -> Vec<Claim> {
    let (t51, t5) = tables();
    let r1: fn(&Pt) -> bool = |p| h1(p) && p.name != "1-0-0-1-0";
    let r2: fn(&Pt) -> bool = |p| p.class == Class::Periodic(2);
    let mut claims = Vec::new();
    claims.push(table_row(
        pts,
        0.42,
        0.54,
        &[spl("P1 = 1-0-0-1-0", p1, h1), spl("Q1 = 1-1-1-1-1", q1, u1)],
        "omega in (0.42, 0.54): P1 (healthy) and Q1 (1-1-1-1-1)".into(),
        format!("{t51}; {t5}"),
        "P1 + Q1".into(),
    ));
    claims.push(table_row(
        pts,
        0.54,
        0.58,
        &[
            sp("R1 (healthy period 1)", r1),
            spl("Q1 = 1-1-1-1-1", q1, u1),
        ],
        "omega in (0.54, 0.58): R1 (healthy, born from P1 at G2) and Q1".into(),
        format!("{t51}; {t5}"),
        "R1 + Q1".into(),
    ));
    claims.push(table_row(
        pts,
        0.58,
        0.63,
        &[sp("R2 (period 2)", r2), spl("Q1 = 1-1-1-1-1", q1, u1)],
        "omega in (0.58, 0.63): R2 (period doubling of R1) and Q1".into(),
        format!("{t51}; {t5}"),
        "R2 + Q1".into(),
    ));
    claims.push(Claim::new(
        "R2 is listed in the healthy / stable column but marked unstable",
        format!("{t51}; {t5}"),
        "R2 healthy and unstable",
        format!("period-2 motions in (0.58, 0.63): {}", found_in(pts, 0.58, 0.63)),
        Verdict::SeedInconsistent,
        "Both tables put R2 in the healthy column with the mark (In); the label of the period-2 motion found here says which applies (back side = non-healthy).",
    ));
    claims.push(table_row(
        pts,
        0.63,
        0.72,
        &[spl("Q1 = 1-1-1-1-1", q1, u1)],
        "omega in (0.63, 0.72): only Q1".into(),
        format!("{t51}; {t5}"),
        "Q1".into(),
    ));
    claims.push(table_row(
        pts,
        0.72,
        1.26,
        &[sp("chaos", chaos)],
        "omega in (0.72, 1.26): chaos (QN)".into(),
        format!("{t51}; {t5}; {B004} §5.3"),
        "chaos".into(),
    ));
    claims.push(table_row(
        pts,
        1.261,
        1.526,
        &[sp("Q2 (healthy period 2)", q2h), sp("chaos (PN)", chaos)],
        "omega in (1.261, 1.526): Q2 (healthy) with chaos (PN)".into(),
        t51.clone(),
        "Q2 + PN".into(),
    ));
    claims.push(table_row(
        pts,
        1.26,
        1.52,
        &[sp("Q2 (healthy period 2)", q2h), sp("P3", p3)],
        "omega in (1.26, 1.52): Q2 (stable) with P3 (unstable)".into(),
        t5.clone(),
        "Q2 + P3".into(),
    ));
    claims.push(table_row(
        pts,
        1.261,
        1.526,
        &[
            sp("P3 = 3-1-1-1-1", |p| p.name == "3-1-1-1-1"),
            sp("chaos (PN)", chaos),
        ],
        "omega in (1.261, 1.526): stable 3-1-1-1-1 (P3) coexisting with chaos (PN)".into(),
        format!("{B004} §5.3 text"),
        "P3 + PN".into(),
    ));
    claims
}

/// The rows from omega = 1.8 to 3: the basins at G3 (`b18`), the inverse doubling at 1.812, Q1
/// and P3, and the name Q1 used twice.
fn high_claims(pts: &[Pt], b18: &[(String, BasinResult)]) -> Vec<Claim> {
    let (t51, t5) = tables();
    let mut claims = Vec::new();
    claims.push(labelled_basin_claim(
        b18,
        &[("P3", "3-1-1-1-1", 0.84), ("Q2", "2-1-0-2-0", 0.16)],
        "At omega = 1.801 (G3) P3 = 3-1-1-1-1 holds 84 % of the basin and Q2 = 2-1-0-2-0 16 %",
        format!("{B004} §5.3 (Fig. 5.5f)"),
    ));
    let q2_at_1801 = pts
        .iter()
        .any(|p| (p.value - 1.801).abs() < 1e-6 && p.class == Class::Periodic(2));
    let q1_at_1812 = pts.iter().any(|p| (p.value - 1.812).abs() < 1e-6 && h1(p));
    claims.push(Claim::new(
        "At omega = 1.812 (F) Q2 turns into Q1 by an inverse period doubling",
        format!("{B004} §5.3"),
        "Q2 at 1.801, Q1 at 1.812",
        format!("healthy period 2 at 1.801: {q2_at_1801}; healthy period 1 at 1.812: {q1_at_1812}"),
        Verdict::of_parts(&[q2_at_1801, q1_at_1812]),
        "Multi-initial runs at the two values: Q2 at omega = 1.801 and Q1 at 1.812 are both needed.",
    ));
    claims.push(table_row(
        pts,
        1.80,
        1.89,
        &[sp("Q1 (healthy period 1)", h1), sp("P3", p3)],
        "omega in (1.80, 1.89): Q1 (stable) and P3".into(),
        t5.clone(),
        "Q1 + P3".into(),
    ));
    claims.push(table_row(
        pts,
        1.802,
        1.891,
        &[sp("Q2 (healthy period 2)", q2h), sp("P3", p3)],
        "omega in (1.802, 1.891): Q2 (healthy) and P3".into(),
        t51.clone(),
        "Q2 + P3".into(),
    ));
    claims.push(table_row(
        pts,
        1.891,
        2.304,
        &[sp("Q1 (healthy period 1)", h1), sp("P3", p3)],
        "omega in (1.891, 2.304): Q1 (healthy) and P3".into(),
        format!("{t51}; {t5}"),
        "Q1 + P3".into(),
    ));
    claims.push(table_row(
        pts,
        2.304,
        3.0,
        &[sp("Q1 (healthy period 1)", h1)],
        "omega in (2.304, 3.0): only Q1 (healthy)".into(),
        format!("{t51}; {t5}"),
        "Q1".into(),
    ));
    claims.push(Claim::new(
        "Q1 is the unstable 1-1-1-1-1 (0.42–0.72) and the healthy attractor of 1.89–3.0",
        format!("{t51}; {t5}"),
        "one name, two attractors",
        format!("0.42–0.72: {}; 1.89–3.0: {}", found_in(pts, 0.42, 0.72), found_in(pts, 1.89, 3.0)),
        Verdict::SeedInconsistent,
        "The name Q1 is reused for two different attractors (back-side contact vs healthy); the rows above test each by its own description.",
    ));
    claims
}
