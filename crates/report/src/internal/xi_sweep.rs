//! B7: bifurcation and TLE over the error amplitude xi (F = 0.05, omega = 1.5): the incomplete
//! bifurcations A and B (multi-initial), the complete bifurcation C, the chaotic band
//! (0.044, 0.126), the period-3 window and back-side contact; other backlash levels and the
//! preset's contact law beside. Checks seed B 003 §3.4 and 004 §4.4 (Fig. 4.6), Table 4.1.

use super::{
    chaos_ranges, fixed, has_name, interval_table, multi, ranges_text, tle_agreement, B003, B004,
    DD_SEED, DS_SEED, FIVE,
};
use crate::claims::{Claim, Verdict};
use crate::classes::{self, tolerant, Class, Pt};
use crate::readings::{f, sequence};
use crate::runner::{hdr, Ctx, Study};
use crate::shared::{sweep_figure, SweepPanels};
use crate::Section;
use anyhow::Result;
use geardyn_analysis::bifurcation::{linspace, Section as Sec, TaskResult};
use geardyn_analysis::simulate::SimOptions;
use geardyn_scenario::Scenario;
use std::path::Path;

/// The TLE confirms the chaotic regions when its sign agrees with the decided class at this
/// many tenths of the values with a TLE, at least.
const TLE_AGREE_TENTHS: usize = 9;

/// One sweep of the sensitivity table.
#[derive(serde::Serialize, serde::Deserialize)]
struct SensitivityRun {
    /// D_s - D_d in words.
    label: String,
    /// (D_d, D_s) of the run.
    levels: (f64, f64),
    /// The runs over xi from (0, 0).
    runs: Vec<TaskResult>,
}

/// What the study computed: the sweeps over xi.
#[derive(serde::Serialize, serde::Deserialize)]
pub(super) struct XiData {
    /// Values of the main sweep.
    n: usize,
    /// Its integration settings.
    sim: SimOptions,
    /// Its backlash levels (D_d, D_s).
    levels: (f64, f64),
    /// The main sweep over xi from (0, 0) (linear law, five sections, TLE).
    main: Vec<TaskResult>,
    /// The multi-initial sweep over xi in [0.001, 0.15].
    multi: Vec<TaskResult>,
    /// The sweep with the preset's contact law.
    law: Vec<TaskResult>,
    /// The sweeps of the sensitivity table, one per backlash step.
    sensitivity: Vec<SensitivityRun>,
}

/// The study `xi_sweep`: [`compute`], then [`render`].
pub(super) struct XiSweep<'a> {
    /// lin.
    pub(super) lin: &'a Scenario,
    /// preset_law.
    pub(super) preset_law: &'a Scenario,
}

impl Study for XiSweep<'_> {
    type Data = XiData;

    fn id(&self) -> &'static str {
        "xi_sweep"
    }

    fn compute(&self, ctx: &Ctx, dir: &Path) -> Result<XiData> {
        compute(ctx, self.lin, self.preset_law, dir)
    }

    fn render(&self, ctx: &Ctx, dir: &Path, data: &XiData) -> Result<Section> {
        render(ctx, dir, data)
    }
}

/// The sweeps over xi: the main one, the multi-initial one, the preset's contact law and other
/// backlash levels.
pub(super) fn compute(
    ctx: &Ctx,
    lin: &Scenario,
    preset_law: &Scenario,
    dir: &Path,
) -> Result<XiData> {
    let n = ctx.n(60, 300);
    let sim = ctx.sim((150, 300), (40, 100));
    let set = [
        ("F", 0.05),
        ("omega", 1.5),
        ("D_d", DD_SEED),
        ("D_s", DS_SEED),
    ];
    let b = lin.with_all(&set)?;
    let main = ctx.sweep(
        dir,
        "xi sweep (linear law)",
        &b,
        &fixed("xi", linspace(0.001, 0.3, n), sim, FIVE.to_vec(), true),
    )?;
    let d = b.params().d_single;
    let multi = ctx.sweep(
        dir,
        "xi multi-initial",
        &b,
        &multi(
            "xi",
            linspace(0.001, 0.15, ctx.n(30, 100)),
            ctx.sim((150, 300), (30, 60)),
            ctx.n(6, 12),
            d,
        ),
    )?;
    let bl = preset_law.with_all(&set)?;
    let law = ctx.sweep(
        dir,
        "xi sweep (LN law)",
        &bl,
        &fixed(
            "xi",
            linspace(0.001, 0.3, ctx.n(40, 150)),
            sim,
            vec![Sec::Strobe],
            false,
        ),
    )?;
    let mut sensitivity = Vec::new();
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
        let runs = ctx.sweep(
            dir,
            &format!("xi sweep step {txt}"),
            &s,
            &fixed(
                "xi",
                linspace(0.001, 0.3, ctx.n(30, 100)),
                sim,
                vec![Sec::Strobe],
                false,
            ),
        )?;
        sensitivity.push(SensitivityRun {
            label: txt.to_string(),
            levels: (s.params().d_double, s.params().d_single),
            runs,
        });
    }
    Ok(XiData {
        n,
        sim,
        levels: (b.params().d_double, b.params().d_single),
        main,
        multi,
        law,
        sensitivity,
    })
}

/// The figures, tables, readings and claims of the sweeps over xi.
pub(super) fn render(ctx: &Ctx, dir: &Path, data: &XiData) -> Result<Section> {
    let (n, sim) = (data.n, data.sim);
    let r = &data.main;
    let fig = sweep_figure(
        ctx, dir, "bif_xi", "xi", r, &FIVE,
        &SweepPanels { tle: true, p_id: true, ..Default::default() },
        "Bifurcation over the error amplitude xi (F = 0.05, omega = 1.5)",
        "Linear contact law at the seed's F = 0.05, omega = 1.5, with D_d = 0.9, D_s = 1: the five Poincaré sections, P_ID and the TLE over xi; colours by decided motion.",
    )?;
    let pts = classes::fixed_points(r);
    let t = tolerant(&pts);
    let table = interval_table(
        ctx,
        dir,
        "intervals_xi.csv",
        "Motion over xi (linear law, initial state (0, 0))",
        "xi",
        &pts,
    )?;
    let rm = &data.multi;
    let mp = classes::points(rm, 0);
    let fig_m = sweep_figure(
        ctx, dir, "multi_xi", "xi", rm, &[Sec::Strobe], &SweepPanels::default(),
        "Multi-initial diagram over xi in [0.001, 0.15]: incomplete bifurcations",
        "Random initial states per value: coexisting attractors (the seed's incomplete bifurcations A and B) appear as several colours at one xi.",
    )?;
    let rl = &data.law;
    let fig_l = sweep_figure(
        ctx, dir, "bif_xi_johnson", "xi", rl, &[Sec::Strobe], &SweepPanels::default(),
        "Comparison: the xi sweep with the Johnson-type (Lankarani–Nikravesh) law",
        "The preset's contact law at the same parameters, for comparison with the seed's linear law.",
    )?;
    let pl = classes::fixed_points(rl);
    let sens_rows: Vec<Vec<String>> = data
        .sensitivity
        .iter()
        .map(|run| {
            let ps = classes::fixed_points(&run.runs);
            vec![
                run.label.clone(),
                f(run.levels.0),
                f(run.levels.1),
                sequence(&classes::intervals(&tolerant(&ps)), 2),
                ranges_text(&chaos_ranges(&ps)),
            ]
        })
        .collect();
    let sens = ctx.table(
        &dir.join("sensitivity.csv"),
        "The xi sweep for other backlash levels (runs of at least two values)",
        &hdr(&["D_s - D_d", "D_d", "D_s", "sequence over xi", "chaotic xi"]),
        sens_rows,
    )?;
    let chaos = chaos_ranges(&pts);
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
    let c4 = has_name(&pts, "4-2-0-2-0").or_else(|| has_name(&mp, "4-2-0-2-0"));
    let (agree, with_tle, pos_chaos) = tle_agreement(&pts);
    let after: Vec<&Pt> = main.map_or(vec![], |m| t.iter().filter(|p| p.value > m.1).collect());
    let p3_window = after.iter().any(|p| p.class == Class::Periodic(3));
    let chaos_again = main.is_some_and(|m| chaos.iter().any(|c| c.0 > m.1));
    let cascade = after
        .iter()
        .any(|p| p.class.period().is_some_and(|k| k == 6 || k == 12));
    let ends_p3 = t.last().is_some_and(|p| p.class == Class::Periodic(3));
    let back_first = t.iter().find(|p| p.back).map(|p| p.value);
    let seq = sequence(&classes::intervals(&t), 2);
    let claims = vec![
        Claim::new("Small xi: constant 1-0-0-1-0 motion (stable meshing)", format!("{B004} §4.4"), "1-0-0-1-0", format!("at xi = 0.001: {small}"), Verdict::of(small == "1-0-0-1-0"), "Linear contact law, D_d = 0.9, D_s = 1 (with the pair's physical levels, 0.002 apart, the motion stays in contact: see the sensitivity table)."),
        Claim::new("An incomplete bifurcation (A): 1-0-0-1-0 coexists with 2-1-0-1-0", format!("{B004} §4.4 (point A); {B003} §3.4"), "1-0-0-1-0 + 2-1-0-1-0", match (inc_a, inc_a_any) { (Some(v), _) => format!("both at xi = {}", f(v)), (None, Some(v)) => format!("1-0-0-1-0 with another period 2 at xi = {}", f(v)), _ => "no coexistence found".into() }, if inc_a.is_some() { Verdict::Reproduced } else if inc_a_any.is_some() { Verdict::Partly } else { Verdict::NotReproduced }, "Multi-initial sweep (second figure): both labels at one xi; 1-0-0-1-0 beside a period 2 of another label counts as partly."),
        Claim::new("A second incomplete bifurcation (B): period-2 motions coexist with 3-1-0-1-0", format!("{B004} §4.4 (point B)"), "P2 + P2 + 3-1-0-1-0", inc_b.map_or("no period 2 beside a period 3".into(), |v| format!("period 2 beside period 3 at xi = {}", f(v))), if inc_b.is_some() { Verdict::Reproduced } else { Verdict::NotReproduced }, "Multi-initial sweep: a value of xi where a period 2 and a period 3 are both reached is what the row needs."),
        Claim::new("A complete bifurcation (C) to 4-2-0-2-0", format!("{B004} §4.4 (point C)"), "4-2-0-2-0", c4.map_or("not found".into(), |v| format!("at xi = {}", f(v))), Verdict::of(c4.is_some()), "The label 4-2-0-2-0 among the runs of the fixed and multi-initial sweeps over xi."),
        xi_band_claim(&pts),
        Claim::new("Then a period-3 window, a period-doubling cascade to chaos, and finally a stable period 3", format!("{B003} §3.4"), "P3 window, cascade, chaos, P3", format!("after the main chaos: period 3 {p3_window}, period 6/12 {cascade}, chaos again {chaos_again}, period 3 at xi = 0.3 {ends_p3}"), Verdict::of_parts(&[p3_window, cascade || chaos_again, ends_p3]), format!("Sequence: {seq}.")),
        Claim::new("The TLE confirms the chaotic regions", format!("{B003} §3.4"), "TLE > 0 where chaotic", format!("TLE > 0 at {pos_chaos} chaotic values; sign agrees with the class at {agree} of {with_tle}"), Verdict::of(with_tle > 0 && agree * 10 >= with_tle * TLE_AGREE_TENTHS), "TLE over the recorded periods."),
        Claim::new("The error amplitude triggers back-side contact and tooth separation", format!("{B003} §3.4; {B004} §4.4"), "back-side contact appears with xi", back_first.map_or("no back-side contact".into(), |v| format!("back-side contact from xi = {}", f(v))), Verdict::of(back_first.is_some()), "Back-side contact = crossings of -D_s or -D_d."),
    ];
    let table_cmp = ctx.table(
        &dir.join("law_comparison.csv"),
        "Linear law (seed) and Johnson-type law (preset) over xi",
        &hdr(&["contact law", "sequence", "chaotic xi"]),
        vec![
            vec!["linear".into(), seq.clone(), ranges_text(&chaos)],
            vec![
                "Johnson-type (Lankarani–Nikravesh)".into(),
                sequence(&classes::intervals(&tolerant(&pl)), 2),
                ranges_text(&chaos_ranges(&pl)),
            ],
        ],
    )?;
    Ok(Section {
        id: "xi_sweep".into(),
        title: "Bifurcation and TLE over the error amplitude xi (F = 0.05, omega = 1.5)".into(),
        seed_ref: "003 §3.4; 004 §4.4 (Fig. 4.6), Table 4.1".into(),
        parameters: format!("xi in [0.001, 0.3] ({n} values), F = 0.05, omega = 1.5 (seed); D_d = {}, D_s = {} (chosen: the seed gives only D_s > D_d; other levels in the sensitivity table); linear contact law", f(data.levels.0), f(data.levels.1)),
        method: format!("Dormand–Prince 5(4), {} + {} periods from (0, 0), five sections, TLE; multi-initial sweep over [0.001, 0.15].", sim.transient_periods, sim.record_periods),
        figures: vec![fig, fig_m, fig_l],
        readings: vec![format!("Sequence (runs of ≥ 2 values): {seq}.")],
        tables: vec![table, sens, table_cmp],
        claims,
        alternatives: vec![],
        seconds: 0.0,
    })
}

/// The seed's chaotic band of xi (004 §4.4).
const XI_BAND: (f64, f64) = (0.044, 0.126);
/// The largest chaotic range reproduces [`XI_BAND`] when its ends lie within these distances
/// of the seed's (lower, upper).
const XI_BAND_TOLERANCE: (f64, f64) = (0.015, 0.02);

/// The chaotic band of the xi sweep (004 §4.4: chaos and complex motion for xi in (0.044, 0.126)),
/// from the runs `pts` of one initial state.
pub(super) fn xi_band_claim(pts: &[Pt]) -> Claim {
    let chaos = chaos_ranges(pts);
    let main = chaos.iter().max_by_key(|c| c.2).copied();
    let ends = main.map(|m| ((m.0 - XI_BAND.0).abs(), (m.1 - XI_BAND.1).abs()));
    Claim::new(
        "Chaos and complex motion for xi in (0.044, 0.126)",
        format!("{B004} §4.4, §4.5, §6(3)"),
        "(0.044, 0.126)",
        format!("chaos for xi in {}", ranges_text(&chaos)),
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
