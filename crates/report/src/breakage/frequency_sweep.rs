//! Bifurcation over the mesh frequency omega at F = 0.1 (study `frequency_sweep`): the motions
//! over omega and the seed's statements on them, at the main load and at other loads of a grid.
//! Checks seed A 000 ¶10, 001 §3 (bifurcation over the meshing frequency) and 002 §5.3 (table).

use super::{sweep, A000, A001, A002};
use crate::claims::{Claim, Verdict};
use crate::classes::{self, tolerant, Class, Pt};
use crate::readings::{f, interval_header, interval_rows, pct, ranges_text, sequence};
use crate::runner::{hdr, Ctx};
use crate::shared::{sweep_figure, SweepPanels};
use crate::{Section, Table};
use anyhow::Result;
use geardyn_analysis::bifurcation::{
    linspace, Section as Sec, SweepMode, SweepOptions, TaskResult,
};
use geardyn_analysis::simulate::SimOptions;
use geardyn_scenario::Scenario;
use std::path::Path;

/// A motion (chaos, impacts, a period) describes a range of omega when it holds at more than
/// this share of its values.
const MOST: f64 = 0.5;
/// Chaos occurs in a third of the range when at more than this share of its values.
const SOME: f64 = 0.1;
/// The short version's medium frequencies have impacts at more than this share of the middle
/// third's values.
const MEDIUM_IMPACTS: f64 = 0.3;

/// What the seed's frequency statements need from one omega sweep.
struct FreqStats {
    low_chaos: f64,
    low_imp: f64,
    low_per_noimp: f64,
    mid_per: f64,
    mid_imp: f64,
    high_n: usize,
    high_chaos: usize,
    high_chaos_imp: usize,
    band: Vec<(f64, f64, usize)>,
    /// `(impacts, chaotic, periodic without impact)` shares per third of the range.
    thirds: Vec<(f64, f64, f64)>,
}

impl FreqStats {
    fn of(pts: &[Pt]) -> FreqStats {
        // shares from the decided class of every value (a smoothed one could stand for the only
        // value of a short interval); the chaotic band from the smoothed reading
        let t = tolerant(pts);
        let at = |lo: f64, hi: f64| classes::within(pts, lo, hi);
        let low = at(0.1, 0.2);
        let mid = at(1.1, 1.3);
        let high = at(2.0001, 3.0);
        let chaos_high: Vec<&&Pt> = high.iter().filter(|p| p.class == Class::Chaotic).collect();
        FreqStats {
            low_chaos: classes::share(&low, |p| p.class == Class::Chaotic),
            low_imp: classes::share(&low, |p| p.back),
            low_per_noimp: classes::share(&low, |p| p.class.periodic() && !p.back),
            mid_per: classes::share(&mid, |p| {
                p.class.periodic()
                    && (matches!(p.class.period(), Some(1 | 2))
                        || matches!(p.mesh_period, Some(1 | 2)))
            }),
            mid_imp: classes::share(&mid, |p| p.back),
            high_n: high.len(),
            high_chaos: chaos_high.len(),
            high_chaos_imp: chaos_high.iter().filter(|p| p.back).count(),
            band: classes::ranges(&t, |p| p.class == Class::Chaotic && p.value > 1.5),
            thirds: [(0.1, 1.0666), (1.0667, 2.0333), (2.0334, 3.0)]
                .iter()
                .map(|&(a, b)| {
                    let s = at(a, b);
                    (
                        classes::share(&s, |p| p.back),
                        classes::share(&s, |p| p.class == Class::Chaotic),
                        classes::share(&s, |p| p.class.periodic() && !p.back),
                    )
                })
                .collect(),
        }
    }
    fn low_000(&self) -> bool {
        self.low_chaos > MOST && self.low_imp > MOST
    }
    fn low_002(&self) -> bool {
        self.low_per_noimp > MOST
    }
    fn mid_000(&self) -> bool {
        self.mid_per > MOST && self.mid_imp < self.low_imp.max(0.01)
    }
    /// Chaos "reappears" above omega = 2 when it holds at a fifth of those values or more (a
    /// value at the tail of a band that starts below 2 is no reappearance), with impacts at
    /// half of them.
    fn high_000(&self) -> bool {
        self.high_chaos > 0
            && self.high_chaos * 5 >= self.high_n
            && self.high_chaos_imp * 2 >= self.high_chaos
    }
    fn ends_001(&self) -> bool {
        self.thirds[0].0 > self.thirds[1].0 && self.thirds[2].0 > self.thirds[1].0
    }
    fn medium_002(&self) -> bool {
        self.thirds[1].1 > SOME && self.thirds[1].0 > MEDIUM_IMPACTS
    }
    fn high_002(&self) -> bool {
        self.thirds[2].1 > SOME
    }
}

/// Reproduced at the main load, partly if only at another load of the grid.
fn at_loads(main: bool, others: &[(f64, bool)]) -> (Verdict, String) {
    let other: Vec<String> = others.iter().filter(|o| o.1).map(|o| f(o.0)).collect();
    let v = if main {
        Verdict::Reproduced
    } else if !other.is_empty() {
        Verdict::Partly
    } else {
        Verdict::NotReproduced
    };
    let all = others
        .iter()
        .map(|o| f(o.0))
        .collect::<Vec<_>>()
        .join(" or ");
    let txt = match (main, other.is_empty()) {
        (true, true) => format!("at the other loads (F = {all}) it does not hold"),
        (true, false) => format!("it also holds at F = {}", other.join(", ")),
        (false, true) => format!("not at F = {all} either"),
        (false, false) => format!("it holds at F = {} instead", other.join(", ")),
    };
    (v, txt)
}

/// What the study computed: the broken pair's sweeps over omega.
#[derive(serde::Serialize, serde::Deserialize)]
pub(super) struct FrequencyData {
    /// Values of the main sweep.
    nw: usize,
    /// Values of the sweeps at the other loads.
    ns: usize,
    /// Integration settings.
    sim: SimOptions,
    /// The sections recorded by the main sweep.
    secs: Vec<Sec>,
    /// The load of the main sweep (the preset's).
    load: f64,
    /// The main sweep over omega.
    main: Vec<TaskResult>,
    /// The coarser sweeps at the other loads: (F, runs).
    others: Vec<(f64, Vec<TaskResult>)>,
    /// The main sweep again with the other integrator and twice the transient
    /// ([`crate::runner::twin_sim`]): values whose verdict changes are not counted as decided.
    twin: Vec<TaskResult>,
    /// Some chaotic values of the main sweep decided again by a deeper escape test
    /// ([`crate::deep_escape`]): their verdict replaces the main sweep's.
    #[serde(default)]
    deep: Vec<TaskResult>,
}

crate::runner::study!(FrequencySweep { base: &'a Scenario } "frequency_sweep" FrequencyData,
    |s, ctx, dir| compute(ctx, s.base, dir), |data| render(ctx, dir, data));

/// The sweep over omega at the preset's load and, coarser, at two other loads.
pub(super) fn compute(ctx: &Ctx, base: &Scenario, dir: &Path) -> Result<FrequencyData> {
    let nw = ctx.n(20, 117);
    let values = linspace(0.1, 3.0, nw);
    let sim = ctx.sim((30, 80), (12, 30));
    let secs = vec![Sec::Strobe, Sec::Impact];
    let o = sweep("omega", values.clone(), SweepMode::Fixed, sim, secs.clone());
    let main = ctx.sweep(dir, "broken omega sweep", base, &o)?;
    let ot = SweepOptions {
        sim: crate::runner::twin_sim(sim),
        sections: vec![Sec::Strobe],
        ..o.clone()
    };
    let twin = ctx.sweep(dir, "broken omega sweep, twin", base, &ot)?;
    let deep =
        crate::deep_escape::recheck(ctx, dir, "broken omega sweep", base, &o, &main, ctx.n(1, 6))?;
    // the seed does not state the load: the same sweep, coarser, at two other loads
    let mut others = Vec::new();
    let ns = ctx.n(8, 40);
    for fl in [0.05, 0.15] {
        let b = base.with("F", fl)?;
        let o = sweep(
            "omega",
            linspace(0.1, 3.0, ns),
            SweepMode::Fixed,
            sim,
            vec![Sec::Impact],
        );
        others.push((fl, ctx.sweep(dir, &format!("omega sweep F {fl}"), &b, &o)?));
    }
    Ok(FrequencyData {
        nw,
        ns,
        sim,
        secs,
        load: base.params().load,
        main,
        others,
        twin,
        deep,
    })
}

/// The diagram, the tables and the seed's frequency statements at the three loads.
pub(super) fn render(ctx: &Ctx, dir: &Path, data: &FrequencyData) -> Result<Section> {
    let (nw, ns, sim, secs, fload) = (data.nw, data.ns, data.sim, &data.secs, data.load);
    // the figure and the claims read the deeper decisions where there are some; the twin's
    // comparison is between the two ordinary decisions
    let r = &crate::deep_escape::substituted(&data.main, &data.deep);
    let fig = sweep_figure(
        ctx, dir, "bif_omega", "omega", r, secs,
        &SweepPanels { impact_force: true, ..Default::default() },
        "Broken pair: bifurcation over the mesh frequency omega (F = 0.1)",
        "Broken pair, F = 0.1: stroboscopic x, velocity before back-side impacts and the impact-force record over omega; colours by decided motion.",
    )?;
    let pts = classes::fixed_points(r);
    let table = ctx.table(
        &dir.join("intervals_omega.csv"),
        "Motion over omega (intervals of equal label)",
        &interval_header("omega"),
        interval_rows(&classes::intervals(&pts)),
    )?;
    let fragile = classes::fragile(
        &classes::fixed_points(&data.main),
        &classes::fixed_points(&data.twin),
    );
    let decided: Vec<Pt> = pts
        .iter()
        .filter(|p| !fragile.contains(&p.value))
        .cloned()
        .collect();
    let st = FreqStats::of(&decided);
    let others: Vec<(f64, FreqStats)> = data
        .others
        .iter()
        .map(|(fl, rr)| (*fl, FreqStats::of(&classes::fixed_points(rr))))
        .collect();
    let sens = sensitivity_table(ctx, dir, fload, &st, &others)?;
    let mut claims = claims(fload, &st, &others);
    crate::readings::note_transients(&mut claims, &pts, "omega", "revolutions");
    crate::readings::note_fragile(&mut claims, &fragile, "omega");
    Ok(Section {
        id: "frequency_sweep".into(),
        title: "Bifurcation over the mesh frequency omega (F = 0.1)".into(),
        seed_ref: "000 ¶10; 001 §3 (bifurcation over the meshing frequency); 002 §5.3 (table)".into(),
        parameters: format!("omega in [0.1, 3] ({nw} values), F = {} (the preset's load; the seed does not state it — the statements are also checked at F = 0.05 and 0.15 with {ns} values), xi = 0.05, initial state (0, 0)", f(fload)),
        method: format!("Dormand–Prince 5(4), {} + {} revolutions per value, decided classification; a twin sweep with the other integrator (RK4 with 256 steps per mesh cycle for Dormand–Prince) and twice the transient flags the values whose verdict changes.", sim.transient_periods, sim.record_periods),
        figures: vec![fig],
        readings: vec![
            format!("Sequence: {}.", sequence(&classes::intervals(&tolerant(&pts)), 2)),
            crate::readings::fragile_reading(&fragile, pts.len(), "omega"),
        ]
        .into_iter()
        .chain(crate::deep_escape::reading(&data.deep, "omega", "revolutions"))
        .collect(),
        tables: vec![table, sens],
        claims,
        alternatives: vec![],
        seconds: 0.0,
    })
}

/// The frequency statements' measures at the three loads.
fn sensitivity_table(
    ctx: &Ctx,
    dir: &Path,
    fload: f64,
    st: &FreqStats,
    others: &[(f64, FreqStats)],
) -> Result<Table> {
    let sens_rows: Vec<Vec<String>> = std::iter::once((fload, st))
        .chain(others.iter().map(|(fl, s)| (*fl, s)))
        .map(|(fl, s)| {
            vec![
                f(fl),
                format!("{} / {}", pct(s.low_chaos), pct(s.low_imp)),
                format!("{} / {}", pct(s.mid_per), pct(s.mid_imp)),
                format!(
                    "{} of {} ({} with impacts)",
                    s.high_chaos, s.high_n, s.high_chaos_imp
                ),
                s.thirds
                    .iter()
                    .map(|t| pct(t.0))
                    .collect::<Vec<_>>()
                    .join(" / "),
            ]
        })
        .collect();
    ctx.table(
        &dir.join("load_sensitivity.csv"),
        "The frequency statements at three loads (the seed does not state the load of its frequency sweep)",
        &hdr(&["F", "omega 0.1–0.2: chaotic / impacts", "omega 1.1–1.3: period 1 or 2 / impacts", "omega > 2: chaotic values", "impacts per third of the range"]),
        sens_rows,
    )
}

/// The seed's frequency statements, at the main load `fload` and at the other loads.
fn claims(fload: f64, st: &FreqStats, others: &[(f64, FreqStats)]) -> Vec<Claim> {
    let oth = |pred: &dyn Fn(&FreqStats) -> bool| -> Vec<(f64, bool)> {
        others.iter().map(|(fl, s)| (*fl, pred(s))).collect()
    };
    let (v_low, t_low) = at_loads(st.low_000(), &oth(&|s| s.low_000()));
    let (v_low2, t_low2) = at_loads(st.low_002(), &oth(&|s| s.low_002()));
    let (v_mid, t_mid) = at_loads(st.mid_000(), &oth(&|s| s.mid_000()));
    let (v_high, t_high) = at_loads(st.high_000(), &oth(&|s| s.high_000()));
    let (v_ends, t_ends) = at_loads(st.ends_001(), &oth(&|s| s.ends_001()));
    let (v_med, t_med) = at_loads(st.medium_002(), &oth(&|s| s.medium_002()));
    // coexistence over omega is not tested by this one-initial-state sweep: partly at best
    let v_med = if v_med == Verdict::Reproduced {
        Verdict::Partly
    } else {
        v_med
    };
    let (v_hi2, t_hi2) = at_loads(st.high_002(), &oth(&|s| s.high_002()));
    // "chaotic motion" describes the regime: chaos at most values; some chaos is partly
    let v_hi2 = if v_hi2 == Verdict::Reproduced && st.thirds[2].1 <= MOST {
        Verdict::Partly
    } else {
        v_hi2
    };
    // the two low-frequency statements contradict each other
    let low_pair = |v: Verdict, other_holds: bool| {
        if v == Verdict::NotReproduced && other_holds {
            Verdict::SeedInconsistent
        } else {
            v
        }
    };
    let any_low_000 = st.low_000() || others.iter().any(|o| o.1.low_000());
    let any_low_002 = st.low_002() || others.iter().any(|o| o.1.low_002());
    let sh = &st.thirds;
    vec![
        Claim::new(
            "At omega = 0.1 the system is chaotic with frequent back-side collisions",
            format!("{A000} ¶10"),
            "chaotic, frequent impacts",
            format!("omega 0.1–0.2 at F = {}: chaotic {}, impacts {} of values", f(fload), pct(st.low_chaos), pct(st.low_imp)),
            low_pair(v_low, any_low_002),
            format!("The seed does not state the load of its frequency sweep: main sweep at F = {}; {t_low}. At low omega every stiffness jump excites a lightly damped free vibration (damping ratio 0.005): the motion is chaotic with drive-side separations, but it reaches the back side only at small loads. The short version says the opposite (next row).", f(fload)),
        ),
        Claim::new(
            "Low meshing frequency: periodic motion, no tooth-back impact",
            format!("{A002} §5.3 (table, row Low)"),
            "periodic, no impact",
            format!("omega 0.1–0.2 at F = {}: periodic without impacts at {} of values", f(fload), pct(st.low_per_noimp)),
            low_pair(v_low2, any_low_000),
            format!("Main sweep at F = {}; {t_low2}. Contradicts the long summary's chaos at omega = 0.1 (row above).", f(fload)),
        ),
        Claim::new(
            "Around omega = 1.2 the motion becomes periodic (period 1 or 2) and back-side impact diminishes",
            format!("{A000} ¶10"),
            "period 1 or 2, fewer impacts",
            format!("omega 1.1–1.3 at F = {}: period 1 or 2 (revolutions or mesh cycles) at {}, impacts at {} of values", f(fload), pct(st.mid_per), pct(st.mid_imp)),
            v_mid,
            format!("Periods counted on both clocks (revolution and mesh cycle); {t_mid}. At F = 0.1 and omega = 1.2 the pair sits at the end of the chaotic load range of the load sweep."),
        ),
        Claim::new(
            "At higher frequencies (omega > 2) chaos reappears with back-side impact",
            format!("{A000} ¶10"),
            "chaos with impacts above omega = 2",
            format!(
                "chaotic at {} of {} values above 2 ({} with impacts); chaotic band {}",
                st.high_chaos,
                st.high_n,
                st.high_chaos_imp,
                ranges_text(&st.band)
            ),
            v_high,
            format!("Decided classification of every value above omega = 2; {t_high}."),
        ),
        Claim::new(
            "Larger or smaller meshing frequencies induce back-side impact",
            format!("{A001} abstract and conclusions"),
            "impacts at both ends of the range",
            format!("impacts at {} (low third), {} (middle), {} (high third) of values", pct(sh[0].0), pct(sh[1].0), pct(sh[2].0)),
            v_ends,
            format!("Thirds of omega ∈ [0.1, 3]; {t_ends}. Where it fails, impacts are most frequent in the middle of the range."),
        ),
        Claim::new(
            "Medium frequency: period coexistence and chaotic motion, with tooth-back impact",
            format!("{A002} §5.3 (table, row Medium)"),
            "chaos and impacts in the middle range",
            format!("middle third: chaotic {}, impacts {} of values", pct(sh[1].1), pct(sh[1].0)),
            v_med,
            format!("Chaos and impacts: {t_med}. Coexistence is not tested over omega (one initial state per value; it is checked over the load in the previous sections), so at best partly."),
        ),
        Claim::new(
            "High frequency: chaotic motion, potential tooth-back impact",
            format!("{A002} §5.3 (table, row High)"),
            "chaos, possibly impacts",
            format!("high third: chaotic {}, impacts {} of values", pct(sh[2].1), pct(sh[2].0)),
            v_hi2,
            format!("High third = omega ∈ [2.03, 3]; chaos at more than 10 % of its values: {t_hi2}; reproduced only where chaos is the motion at most values of the third."),
        ),
    ]
}
