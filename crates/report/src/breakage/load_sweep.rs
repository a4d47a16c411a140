//! Bifurcation over the load F, broken pair against its healthy twin, at omega = 1.2 (the seed
//! does not give the frequency): the motions over F, impacts at low load, periodic motion
//! without impact above F = 0.1 and the impact-force periodogram. Checks seed A 000 ¶9 and ¶11,
//! 001 §3 (bifurcation diagram, impact-force periodogram over F) and 002 §5.2 (table).

use super::{healthy_sim, sweep, A000, A001, A002, OMEGA_LOAD};
use crate::claims::{Claim, Verdict};
use crate::classes::{self, tolerant, Class, Pt};
use crate::coexisting;
use crate::readings::{f, interval_header, interval_rows, pct, ranges_text, sequence};
use crate::runner::Ctx;
use crate::shared::{sweep_figure, SweepPanels};
use crate::Section;
use anyhow::Result;
use geardyn_analysis::bifurcation::{
    attractor_region, linspace, Section as Sec, SweepMode, SweepOptions, TaskResult,
};
use geardyn_analysis::simulate::SimOptions;
use geardyn_scenario::Scenario;
use std::path::Path;

/// Relative difference below which two largest mesh forces count as equal (the integrator's
/// noise on one orbit is about 1e-5 relative; the audit found ties of 1e-7 counted as higher).
const FORCE_TIE: f64 = 1e-4;

/// What the study computed: the load sweeps of both pairs.
#[derive(serde::Serialize, serde::Deserialize)]
pub(super) struct LoadSweepData {
    /// Values of F.
    nf: usize,
    /// Integration settings of the broken pair.
    sim: SimOptions,
    /// Mesh cycles per revolution.
    cycles: u32,
    /// The sections recorded.
    secs: Vec<Sec>,
    /// The broken pair's sweep over F.
    broken: Vec<TaskResult>,
    /// The healthy twin's sweep over F (same physical time).
    healthy: Vec<TaskResult>,
    /// The broken pair from several initial states per load ([`attractor_loads`]): every
    /// attractor the claims are judged over.
    multi: Vec<TaskResult>,
    /// The broken pair's sweep again with the other integrator and twice the transient
    /// ([`crate::runner::twin_sim`]): values whose verdict changes are not counted as decided.
    twin: Vec<TaskResult>,
    /// Some chaotic values of the broken pair's sweep decided again by a deeper escape test
    /// ([`crate::deep_escape`]): their verdict replaces the sweep's.
    #[serde(default)]
    deep: Vec<TaskResult>,
}

/// The loads and initial states per load of the multi-initial runs that find the coexisting
/// attractors of a load sweep (coarser than the sweep: a claim over a range of loads is judged
/// on them).
pub(super) fn attractor_loads(ctx: &Ctx) -> (Vec<f64>, usize) {
    (
        ctx.n(vec![0.03, 0.06, 0.11, 0.14], linspace(0.01, 0.15, 15)),
        ctx.n(4, 8),
    )
}

/// The multi-initial runs of `b` over [`attractor_loads`] (initial states uniform in the
/// attractor region of its half backlash, seeded).
pub(super) fn attractor_sweep(
    ctx: &Ctx,
    dir: &Path,
    name: &str,
    b: &Scenario,
    sim: SimOptions,
) -> Result<Vec<TaskResult>> {
    let (loads, ics) = attractor_loads(ctx);
    let (x0_range, v0_range) = attractor_region(b.params().d_single);
    let mode = SweepMode::Multi {
        ics,
        seed: 7,
        x0_range,
        v0_range,
    };
    ctx.sweep(
        dir,
        name,
        b,
        &sweep("F", loads, mode, sim, vec![Sec::Strobe]),
    )
}

crate::runner::study!(LoadSweep { base: &'a Scenario, healthy: &'a Scenario, nf: usize } "load_sweep" LoadSweepData,
    |s, ctx, dir| compute(ctx, dir, s.base, s.healthy, s.nf), |data| render(ctx, dir, data), serde_json::json!([s.nf, OMEGA_LOAD]));

/// The sweeps over F of the broken pair and of its healthy twin at [`OMEGA_LOAD`].
pub(super) fn compute(
    ctx: &Ctx,
    dir: &Path,
    base: &Scenario,
    healthy: &Scenario,
    nf: usize,
) -> Result<LoadSweepData> {
    let fvals = linspace(0.0, 0.15, nf);
    let sim = ctx.sim((40, 100), (16, 40));
    let cycles = base.model().cycles_per_period();
    let secs = vec![Sec::Strobe, Sec::Impact];
    let b = base.with("omega", OMEGA_LOAD)?;
    let h = healthy.with("omega", OMEGA_LOAD)?;
    let o = sweep("F", fvals.clone(), SweepMode::Fixed, sim, secs.clone());
    let broken = ctx.sweep(dir, "broken F sweep", &b, &o)?;
    let oh = SweepOptions {
        sim: healthy_sim(sim, cycles),
        ..o.clone()
    };
    let healthy = ctx.sweep(dir, "healthy F sweep", &h, &oh)?;
    let multi = attractor_sweep(ctx, dir, "multi-initial F", &b, sim)?;
    let ot = SweepOptions {
        sim: crate::runner::twin_sim(sim),
        sections: vec![Sec::Strobe],
        ..o.clone()
    };
    let twin = ctx.sweep(dir, "broken F sweep, twin", &b, &ot)?;
    let deep =
        crate::deep_escape::recheck(ctx, dir, "broken F sweep", &b, &o, &broken, ctx.n(0, 6))?;
    Ok(LoadSweepData {
        nf,
        sim,
        cycles,
        secs,
        broken,
        healthy,
        multi,
        twin,
        deep,
    })
}

/// The figures, interval tables, readings and claims of the load sweeps.
pub(super) fn render(ctx: &Ctx, dir: &Path, data: &LoadSweepData) -> Result<Section> {
    let (nf, sim, cycles, secs) = (data.nf, data.sim, data.cycles, &data.secs);
    // the figure and the claims read the deeper decisions where there are some; the twin's
    // comparison is between the two ordinary decisions
    let rb = &crate::deep_escape::substituted(&data.broken, &data.deep);
    let rh = &data.healthy;
    let panels = SweepPanels {
        impact_force: true,
        max_force: true,
        ..Default::default()
    };
    let fig_b = sweep_figure(
            ctx, dir, "bif_F_broken", "F", rb, secs, &panels,
            "Broken pair: bifurcation over the load F (omega = 1.2)",
            "Broken pair, omega = 1.2: stroboscopic x (one point per revolution), velocity before each back-side impact, the largest impact force of every recorded revolution (the seed's impact-force periodogram) and the largest mesh force, over F; colours by decided motion.",
        )?;
    let fig_h = sweep_figure(
            ctx, dir, "bif_F_healthy", "F", rh, secs,
            &SweepPanels { max_force: true, ..Default::default() },
            "Healthy pair: bifurcation over the load F (omega = 1.2)",
            "Healthy twin (no chipped tooth), same physical time: stroboscopic x (one point per mesh cycle), impacts and the largest mesh force over F.",
        )?;
    let pb = classes::fixed_points(rb);
    let ph = classes::fixed_points(rh);
    let intervals = |pts: &[Pt], file: &str, title: &str| {
        ctx.table(
            &dir.join(file),
            title,
            &interval_header("F"),
            interval_rows(&classes::intervals(pts)),
        )
    };
    let table = intervals(
        &pb,
        "intervals_F_broken.csv",
        "Broken pair: motion over F (intervals of equal label)",
    )?;
    let table_h = intervals(
        &ph,
        "intervals_F_healthy.csv",
        "Healthy pair: motion over F",
    )?;
    let fragile = classes::fragile(
        &classes::fixed_points(&data.broken),
        &classes::fixed_points(&data.twin),
    );
    let mut claims = load_claims(&pb, &ph, &classes::points(&data.multi, 0), &fragile);
    crate::readings::note_transients(&mut claims, &pb, "F", "revolutions");
    Ok(Section {
            id: "load_sweep".into(),
            title: "Bifurcation over the load F: broken versus healthy (omega = 1.2)".into(),
            seed_ref: "000 ¶9 and ¶11; 001 §3 (bifurcation diagram, impact-force periodogram over F); 002 §5.2 (table)".into(),
            parameters: format!(
                "F in [0, 0.15] ({nf} values), omega = 1.2 (the seed does not give the frequency of its load sweep; chosen where seed 000 places periodic motion, sensitivity in the next section), xi = 0.05, c = 0.01, R = 0.85, mu = 0.15; initial state (0, 0)"
            ),
            method: format!(
                "Dormand–Prince 5(4), {} + {} revolutions (each {cycles} mesh cycles) per value; the healthy twin integrates the same time; each value classified (period test, TLE, extended transient when undecided); a twin sweep with the other integrator (RK4 with 256 steps per mesh cycle for Dormand–Prince) and twice the transient flags the values whose verdict changes; 4–8 random initial states per load at 4–15 loads for every attractor.",
                sim.transient_periods, sim.record_periods
            ),
            figures: vec![fig_b, fig_h],
            readings: vec![
                format!("Broken: {}.", sequence(&classes::intervals(&tolerant(&pb)), 2)),
                crate::readings::fragile_reading(&fragile, pb.len(), "F"),
                format!("Healthy: {}.", sequence(&classes::intervals(&tolerant(&ph)), 2)),
            ]
            .into_iter()
            .chain(crate::deep_escape::reading(&data.deep, "F", "revolutions"))
            .collect(),
            tables: vec![table, table_h],
            claims,
            alternatives: vec![],
            seconds: 0.0,
        })
}

/// The seed's "F > 0.1" is checked on the interior of (0.1, 0.15], trimmed by 15 % at each end
/// as every interval of the seeds (a boundary is not a point).
pub(super) const HIGH_LOADS: (f64, f64) = (0.1075, 0.1425);
/// "Periodic without impact at F > 0.1" is reproduced when that holds at this share of the
/// [`HIGH_LOADS`] values at least, with no impact and no chaos there ...
const HIGH_LOAD_PERIODIC: f64 = 0.8;
/// ... and partly at this share.
const HIGH_LOAD_PERIODIC_PARTLY: f64 = 0.6;
/// Border between the lower and the upper loads of "larger loads inhibit back-side impact" (the
/// middle of the sweep).
const IMPACT_SPLIT: f64 = 0.075;

/// The claims of the load sweep that need only the broken pair's runs: `pb` from rest (at
/// `omega`) and `multi`, every run of the multi-initial sweep there ([`attractor_sweep`]): a
/// claim about the motion at a load is judged over every attractor found, not from rest only.
pub(super) fn broken_load_claims(pb: &[Pt], multi: &[Pt], omega: f64) -> Vec<Claim> {
    let tb = tolerant(pb);
    // shares and counts from the decided class of every value; the smoothed reading (`tb`,
    // `th`) only for ranges and sequences, where one value at a bifurcation point is noise
    let hi: Vec<&Pt> = classes::within(pb, HIGH_LOADS.0, HIGH_LOADS.1);
    let hi_ok = classes::share(&hi, |p| p.class.periodic() && !p.back);
    let hi_imp = classes::share(&hi, |p| p.back);
    let hi_chaos = classes::share(&hi, |p| p.class == Class::Chaotic);
    let hi_undecided = classes::share(&hi, |p| !p.class.periodic() && p.class != Class::Chaotic);
    // undecided values (no period within the extended transient, TLE not positive) do not
    // contradict "periodic"; impacts or chaos do
    let from_rest = if hi_imp == 0.0 && hi_chaos == 0.0 && hi_ok >= HIGH_LOAD_PERIODIC {
        Verdict::Reproduced
    } else if hi_ok >= HIGH_LOAD_PERIODIC_PARTLY {
        Verdict::Partly
    } else {
        Verdict::NotReproduced
    };
    // every attractor found at the high loads: an impacting or chaotic one beside the periodic
    // motion from rest makes the statement hold only on part of the state space
    let hi_m: Vec<&Pt> = classes::within(multi, HIGH_LOADS.0, HIGH_LOADS.1);
    let hi_m_bad = classes::share(&hi_m, |p| p.back || p.class == Class::Chaotic);
    let hi_found = coexisting::found(&hi_m);
    let bad_txt = coexisting::describe(&hi_found, |a| a.back || a.name == "chaotic", "F", 3);
    let hi_verdict = if from_rest == Verdict::Reproduced && hi_m_bad > 0.0 {
        Verdict::Partly
    } else {
        from_rest
    };
    let hi_txt = format!(
        "F in [0.1075, 0.1425] (the seed's F > 0.1 without its boundary), from rest: periodic without impacts at {}, undecided {}, chaotic {}, impacts at {} of values; {}",
        pct(hi_ok),
        pct(hi_undecided),
        pct(hi_chaos),
        pct(hi_imp),
        every_attractor(&hi_m, hi_m_bad, &bad_txt),
    );
    let chaos = classes::ranges(&tb, |p| p.class == Class::Chaotic);
    let chaos_imp = chaos_with_impacts(pb);
    let iv = classes::intervals(&tb);
    // on the mesh-cycle clock: a 3 -> 6 mesh-cycle doubling inside one revolution is one
    let doubling = classes::has_doubling(&iv);
    let largest_imp = pb
        .iter()
        .filter(|p| p.back)
        .map(|p| p.value)
        .fold(f64::NAN, f64::max);
    let ch_txt = ranges_text(&chaos);
    let lower: Vec<&Pt> = classes::within(pb, 0.0, IMPACT_SPLIT);
    let upper: Vec<&Pt> = classes::within(pb, IMPACT_SPLIT, 0.15);
    let (sl, su) = (
        classes::share(&lower, |p| p.back),
        classes::share(&upper, |p| p.back),
    );
    // the same over every attractor: the share of all initial states that end impacting
    let (ml, mu) = (
        classes::share(&classes::within(multi, 0.0, IMPACT_SPLIT), |p| p.back),
        classes::share(&classes::within(multi, IMPACT_SPLIT, 0.15), |p| p.back),
    );
    vec![
        Claim::new(
            "At higher loads (F > 0.1) the motion is periodic without back-side impact",
            format!("{A000} ¶9"),
            "F > 0.1: periodic, no impact",
            format!("{hi_txt}; the last value with impacts is F = {} (seed's border 0.1)", f(largest_imp)),
            hi_verdict,
            format!("Broken pair, omega = {}, F in [0.1075, 0.1425]; largest F with impacts from rest {}. Judged over every attractor found: from rest only it would read {}. Undecided values (no period, TLE not significantly positive) do not contradict it.", f(omega), f(largest_imp), from_rest.word()),
        ),
        Claim::new(
            "High load: stable periodic motion without tooth-back impact",
            format!("{A002} §5.2 (table, row High)"),
            "periodic, no impact",
            hi_txt.clone(),
            hi_verdict,
            "Same sweep and attractors as the row above (the short version's restatement).",
        ),
        Claim::new(
            "As F decreases, chaotic motion and period-doubling bifurcations occur, accompanied by back-side impact",
            format!("{A000} ¶9"),
            "chaos and period doubling with impacts at lower F",
            format!("chaos for F in {ch_txt}; period doubling between periodic intervals: {}", if doubling { "yes" } else { "no" }),
            Verdict::of_parts(&[chaos_imp, doubling]),
            "Chaotic values all show back-side impacts when the first part holds.",
        ),
        Claim::new(
            "Larger loads inhibit back-side impact",
            format!("{A001} abstract and conclusions"),
            "impacts fewer at larger F",
            format!("from rest, share of values with impacts: F < {} {}, F ≥ {} {}; largest F with impacts {}; over every attractor, share of initial states ending with impacts: F < {} {}, F ≥ {} {}", f(IMPACT_SPLIT), pct(sl), f(IMPACT_SPLIT), pct(su), f(largest_imp), f(IMPACT_SPLIT), pct(ml), f(IMPACT_SPLIT), pct(mu)),
            inhibit_verdict(sl > su, multi.is_empty() || ml > mu),
            format!("Broken pair, omega = {}; fewer impacts at larger loads both from rest and over the initial states of the multi-initial runs gives reproduced, one of the two partly.", f(omega)),
        ),
    ]
}

/// The claims of the load sweep: [`broken_load_claims`] at [`OMEGA_LOAD`] and those that compare
/// the broken pair `pb` with its healthy twin `ph`.
fn load_claims(pb: &[Pt], ph: &[Pt], multi: &[Pt], fragile: &[f64]) -> Vec<Claim> {
    let th = tolerant(ph);
    let chaos_imp = chaos_with_impacts(pb);
    let imp = |pts: &[Pt]| {
        pts.iter()
            .filter(|p| p.back)
            .map(|p| p.value)
            .collect::<Vec<f64>>()
    };
    let (ib, ih) = (imp(pb), imp(ph));
    let chaos_b = pb.iter().filter(|p| p.class == Class::Chaotic).count();
    let chaos_h = ph.iter().filter(|p| p.class == Class::Chaotic).count();
    // healthy: period 1 at high load, period 2 somewhere below it
    let h_p1_high = classes::within(ph, 0.1, 0.15)
        .iter()
        .any(|p| p.class == Class::Periodic(1));
    let h_p2_low = ph
        .iter()
        .any(|p| p.class == Class::Periodic(2) || p.mesh_period == Some(2));
    let higher = pb
        .iter()
        .zip(ph)
        .filter(|(b, h)| b.max_force > h.max_force * (1.0 + FORCE_TIE))
        .count();
    let lower_f = pb
        .iter()
        .zip(ph)
        .filter(|(b, h)| b.max_force < h.max_force * (1.0 - FORCE_TIE))
        .count();
    // the claims on the broken pair alone count only the values decided alike by the twin
    let decided: Vec<Pt> = pb
        .iter()
        .filter(|p| !fragile.contains(&p.value))
        .cloned()
        .collect();
    let mut v = broken_load_claims(&decided, multi, OMEGA_LOAD);
    crate::readings::note_fragile(&mut v, fragile, "F");
    v.extend([
        Claim::new(
            "With decreasing load a healthy pair goes from period 1 to period 2, a broken one becomes chaotic with back-side impact",
            format!("{A000} ¶11"),
            "healthy: P1 → P2; broken: chaos + impacts",
            format!("healthy: period 1 at high F {}, period 2 below {}; broken chaos with impacts {}", h_p1_high, h_p2_low, chaos_imp),
            Verdict::of_parts(&[h_p1_high, h_p2_low, chaos_imp]),
            format!("Healthy twin sweep: {}.", sequence(&classes::intervals(&th), 2)),
        ),
        Claim::new(
            "Breakage promotes back-side impact",
            format!("{A000} ¶11; {A001} abstract"),
            "more impacts with breakage",
            format!("values with impacts: broken {}, healthy {} of {}", ib.len(), ih.len(), pb.len()),
            Verdict::of(ib.len() > ih.len()),
            "Same F grid, same physical time.",
        ),
        Claim::new(
            "Breakage amplifies the nonlinearity: healthy gears show less pronounced chaos",
            format!("{A000} ¶11; {A001} abstract"),
            "less chaos when healthy",
            format!("chaotic values: broken {chaos_b}, healthy {chaos_h}"),
            Verdict::of(chaos_b > chaos_h),
            "Decided classification of every value.",
        ),
        Claim::new(
            "Breakage raises the dynamic load (localized overloading)",
            format!("{A000} ¶3"),
            "larger mesh force",
            format!(
                "largest mesh force broken > healthy at {higher} of {} loads, lower at {lower_f}, equal within {FORCE_TIE:e} (relative) at the rest",
                pb.len()
            ),
            if higher * 10 >= pb.len() * 8 { Verdict::Reproduced } else if higher * 2 > pb.len() { Verdict::Partly } else { Verdict::NotReproduced },
            "At omega = 1.2 the broken cycle often falls into a separation, where the chipped tooth changes nothing (see the revolution section).",
        ),
    ]);
    v
}

/// What the multi-initial runs `hi` at the high loads add to a claim of periodic motion without
/// impact there: the share of initial states that end impacting or chaotic, and which.
fn every_attractor(hi: &[&Pt], bad: f64, which: &str) -> String {
    if hi.is_empty() {
        return "no multi-initial runs at these loads: judged from rest only".into();
    }
    let k = hi.len();
    if bad == 0.0 {
        format!("every one of {k} runs from random initial states there is periodic without impact")
    } else {
        format!(
            "over every attractor ({k} runs from random initial states there): {} end with back-side impacts or chaos: {which}",
            pct(bad)
        )
    }
}

/// "Larger loads inhibit impact" from rest and over every attractor.
fn inhibit_verdict(from_rest: bool, over_attractors: bool) -> Verdict {
    match (from_rest, over_attractors) {
        (true, true) => Verdict::Reproduced,
        (false, false) => Verdict::NotReproduced,
        _ => Verdict::Partly,
    }
}

/// Chaotic values below F = 0.1 exist and all show back-side impacts.
fn chaos_with_impacts(pb: &[Pt]) -> bool {
    let chaos = classes::ranges(&tolerant(pb), |p| p.class == Class::Chaotic);
    classes::within(pb, 0.0, 0.1)
        .iter()
        .filter(|p| p.class == Class::Chaotic)
        .all(|p| p.back)
        && !chaos.is_empty()
}
