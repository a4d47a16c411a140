//! B6: bifurcation and TLE over the static half backlash D (xi = 0.27, omega = 1.4): the
//! sequence of motions (1-1-1-1-1, 2-1-1-1-1, period doubling, chaos, period 3, long period),
//! coexistence at large backlash, and the same sweep for other loads, backlash steps and the
//! preset's contact law. Checks seed B 003 §3.3 and 004 §4.3 (Fig. 4.4), Table 4.1.

use super::{
    chaos_ranges, fixed, has_name, interval_table, multi, ranges_text, tle_agreement, B003, B004,
    BACKLASH_STEP, FIVE, F_BACKLASH,
};
use crate::claims::{Claim, Verdict};
use crate::classes::{self, tolerant, Class, Pt};
use crate::readings::{f, pct, sequence};
use crate::runner::{hdr, Ctx, Study};
use crate::shared::{sweep_figure, SweepPanels};
use crate::Section;
use anyhow::Result;
use geardyn_analysis::bifurcation::{linspace, Section as Sec, TaskResult};
use geardyn_analysis::simulate::SimOptions;
use geardyn_scenario::Scenario;
use std::path::Path;

/// Loads of the sensitivity table (the chosen [`F_BACKLASH`] among them).
const SENSITIVITY_LOADS: [f64; 4] = [0.03, 0.05, 0.07, 0.1];
/// Border between small and large backlash in the coexistence and separation claims.
const LARGE_D: f64 = 1.15;
/// Values of D where the seed's small-backlash motion 1-1-1-1-1 is looked for.
const SMALL_D: (f64, f64) = (0.3, 0.45);

/// One sweep of the sensitivity table.
#[derive(serde::Serialize, serde::Deserialize)]
struct SensitivityRun {
    /// Load F.
    load: f64,
    /// D_s - D_d.
    step: f64,
    /// Whether the step is the pair's physical one.
    physical: bool,
    /// The runs over D from (0, 0).
    runs: Vec<TaskResult>,
}

/// What the study computed: the sweeps over D.
#[derive(serde::Serialize, serde::Deserialize)]
pub(super) struct BacklashData {
    /// Values of the main sweep.
    n: usize,
    /// Its integration settings.
    sim: SimOptions,
    /// The main sweep over D from (0, 0) (linear law, five sections, TLE).
    main: Vec<TaskResult>,
    /// The coarse multi-initial sweep over D.
    multi: Vec<TaskResult>,
    /// The sweeps of the sensitivity table, by load, then by backlash step.
    sensitivity: Vec<SensitivityRun>,
    /// The sweep with the preset's contact law.
    law: Vec<TaskResult>,
}

/// The study `backlash_sweep`: [`compute`], then [`render`].
pub(super) struct BacklashSweep<'a> {
    /// lin.
    pub(super) lin: &'a Scenario,
    /// preset_law.
    pub(super) preset_law: &'a Scenario,
}

impl Study for BacklashSweep<'_> {
    type Data = BacklashData;

    fn id(&self) -> &'static str {
        "backlash_sweep"
    }

    fn request(&self) -> serde_json::Value {
        serde_json::json!([BACKLASH_STEP, F_BACKLASH])
    }

    fn compute(&self, ctx: &Ctx, dir: &Path) -> Result<BacklashData> {
        compute(ctx, self.lin, self.preset_law, dir)
    }

    fn render(&self, ctx: &Ctx, dir: &Path, data: &BacklashData) -> Result<Section> {
        render(ctx, dir, data)
    }
}

/// The sweeps over D: the main one, the multi-initial one, the sensitivity to the load and the
/// backlash step, and the preset's contact law.
pub(super) fn compute(
    ctx: &Ctx,
    lin: &Scenario,
    preset_law: &Scenario,
    dir: &Path,
) -> Result<BacklashData> {
    let n = ctx.n(40, 171);
    let values = linspace(0.3, 2.0, n);
    let sim = ctx.sim((150, 300), (40, 100));
    let at = |s: &Scenario, step: f64, fl: f64| -> Result<Scenario> {
        Ok(s.with_all(&[
            ("xi", 0.27),
            ("omega", 1.4),
            ("F", fl),
            ("D_d", 1.0 - step),
            ("D_s", 1.0),
        ])?)
    };
    let b = at(lin, BACKLASH_STEP, F_BACKLASH)?;
    let main = ctx.sweep(
        dir,
        "D sweep (linear law)",
        &b,
        &fixed("D", values.clone(), sim, FIVE.to_vec(), true),
    )?;
    // multi-initial, coarse: coexistence at large backlash
    let mvals = linspace(0.3, 2.0, ctx.n(12, 35));
    let multi = ctx.sweep(
        dir,
        "D multi-initial",
        &b,
        &multi("D", mvals, ctx.sim((150, 300), (30, 60)), ctx.n(4, 8), 1.0),
    )?;
    // sensitivity to the chosen load and backlash step
    let ns = ctx.n(20, 69);
    let mut sensitivity = Vec::new();
    // the pair's own step (its labels keep p = r, q = s, as the seed's labels of this figure do)
    let phys = lin.get("D_s")? - lin.get("D_d")?;
    for &fl in &SENSITIVITY_LOADS {
        for &st in &[phys, 0.1, 0.2] {
            let s = at(lin, st, fl)?;
            let runs = ctx.sweep(
                dir,
                &format!("D sweep F {fl} step {st}"),
                &s,
                &fixed(
                    "D",
                    linspace(0.3, 2.0, ns),
                    ctx.sim((150, 300), (40, 100)),
                    vec![Sec::Strobe],
                    false,
                ),
            )?;
            sensitivity.push(SensitivityRun {
                load: fl,
                step: st,
                physical: st == phys,
                runs,
            });
        }
    }
    // the preset's contact law, for comparison
    let bl = at(preset_law, BACKLASH_STEP, F_BACKLASH)?;
    let law = ctx.sweep(
        dir,
        "D sweep (LN law)",
        &bl,
        &fixed(
            "D",
            linspace(0.3, 2.0, ctx.n(30, 86)),
            sim,
            vec![Sec::Strobe],
            false,
        ),
    )?;
    Ok(BacklashData {
        n,
        sim,
        main,
        multi,
        sensitivity,
        law,
    })
}

/// The figures, tables, readings and claims of the sweeps over D.
pub(super) fn render(ctx: &Ctx, dir: &Path, data: &BacklashData) -> Result<Section> {
    let (n, sim) = (data.n, data.sim);
    let r = &data.main;
    let fig = sweep_figure(
        ctx, dir, "bif_D", "D", r, &FIVE,
        &SweepPanels { tle: true, p_id: true, ..Default::default() },
        "Bifurcation over the static half backlash D (xi = 0.27, omega = 1.4)",
        "Linear contact law, D_s = D, D_d = D - 0.2, F = 0.07: the five Poincaré sections of the seed (stroboscopic x; velocity at the crossings of ±D_s, ±D_d), P_ID and the TLE over D; colours by decided motion.",
    )?;
    let pts = classes::fixed_points(r);
    let t = tolerant(&pts);
    let table = interval_table(
        ctx,
        dir,
        "intervals_D.csv",
        "Motion over D (linear law)",
        "D",
        &pts,
    )?;
    let rm = &data.multi;
    let mp = classes::points(rm, 0);
    let coexist = |lo: f64, hi: f64| {
        let vals: Vec<f64> = {
            let mut v: Vec<f64> = mp
                .iter()
                .map(|p| p.value)
                .filter(|v| *v >= lo && *v <= hi)
                .collect();
            v.dedup();
            v
        };
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
    let fig_m = sweep_figure(
        ctx, dir, "multi_D", "D", rm, &[Sec::Strobe], &SweepPanels::default(),
        "Multi-initial diagram over D (coexisting attractors)",
        "Several random initial states per value (x0 ∈ ±4, x0' ∈ ±3 for D = 1: the attractor region, docs/analyses.md): points coloured by the attractor reached.",
    )?;
    let sens_rows: Vec<Vec<String>> = data
        .sensitivity
        .iter()
        .map(|run| {
            let ps = classes::fixed_points(&run.runs);
            let iv = classes::intervals(&tolerant(&ps));
            let st_txt = if run.physical {
                format!("{} (physical)", f(run.step))
            } else {
                f(run.step)
            };
            vec![f(run.load), st_txt, sequence(&iv, 2)]
        })
        .collect();
    let sens = ctx.table(
        &dir.join("sensitivity.csv"),
        "Sequence of motions over D for other loads F and backlash steps D_s - D_d (runs of at least two values)",
        &hdr(&["F", "D_s - D_d", "sequence over D from 0.3 to 2"]),
        sens_rows,
    )?;
    let rl = &data.law;
    let fig_l = sweep_figure(
        ctx, dir, "bif_D_johnson", "D", rl, &[Sec::Strobe], &SweepPanels::default(),
        "Comparison: the same sweep with the Johnson-type (Lankarani–Nikravesh) contact law",
        "The preset's contact law (exponent from the seed's Johnson table, restitution 0.8) at the same parameters, for comparison.",
    )?;
    let pl = classes::fixed_points(rl);
    // claims
    let first = t.first().map(|p| p.name.clone()).unwrap_or_default();
    let small: Vec<&Pt> = classes::within(&t, SMALL_D.0, SMALL_D.1);
    let p1_small = small.iter().any(|p| p.name == "1-1-1-1-1");
    let a = has_name(&t, "2-1-1-1-1");
    let b4 = has_name(&pts, "4-2-2-2-2");
    let b4b = has_name(&pts, "4-1-1-1-1");
    let any4 = pts
        .iter()
        .find(|p| p.class == Class::Periodic(4))
        .map(|p| (p.value, p.name.clone()));
    let chaos = chaos_ranges(&pts);
    // every chaotic value, isolated ones included (the tolerant reading above absorbs them)
    let chaos_all = classes::ranges(&pts, |p| p.class == Class::Chaotic);
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
    let (agree, with_tle, pos_chaos) = tle_agreement(&pts);
    let pid = |lo: f64, hi: f64| {
        let w = classes::within(&pts, lo, hi);
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
    let claims = vec![
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
    ];
    let table_cmp = ctx.table(
        &dir.join("law_comparison.csv"),
        "Linear law (seed) and Johnson-type law (preset) over D",
        &hdr(&["contact law", "sequence", "chaotic D"]),
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
        id: "backlash_sweep".into(),
        title: "Bifurcation and TLE over the static half backlash D (xi = 0.27, omega = 1.4)".into(),
        seed_ref: "003 §3.3; 004 §4.3 (Fig. 4.4), Table 4.1".into(),
        parameters: format!("D in [0.3, 2] ({n} values) with D_s = D and D_d = D - {} (chosen: the physical difference at the operating point is 0.002, too small for the seed's labels); xi = 0.27, omega = 1.4 (seed); F = {} (chosen: the seed gives none); linear contact law", f(BACKLASH_STEP), f(F_BACKLASH)),
        method: format!("Dormand–Prince 5(4), {} + {} periods from (0, 0); five Poincaré sections; TLE over the recorded periods; decided classification. Multi-initial and sensitivity sweeps coarser.", sim.transient_periods, sim.record_periods),
        figures: vec![fig, fig_m, fig_l],
        readings: vec![format!("Sequence (runs of ≥ 2 values): {seq}.")],
        tables: vec![table, sens, table_cmp],
        claims,
        alternatives: vec![],
        seconds: 0.0,
    })
}
