//! Coexisting attractors over the load (multi-initial diagram) and basins at F = 0.05, where
//! seed A has a period 4 and a period 2 coexist. Checks seed A 000 ¶9, 001 abstract and 002
//! §5.2.

use super::{sweep, A000, A001, A002, OMEGA_LOAD};
use crate::claims::{Claim, Verdict};
use crate::classes::{self, Class, Pt};
use crate::readings::{f, pct};
use crate::runner::{hdr, Ctx};
use crate::shared::{basin_grid, basin_render, sweep_figure, BasinGrid, SweepPanels};
use crate::{Section, Table};
use anyhow::Result;
use geardyn_analysis::basins::BasinResult;
use geardyn_analysis::bifurcation::{
    attractor_region, linspace, Section as Sec, SweepMode, TaskResult,
};
use geardyn_analysis::simulate::SimOptions;
use geardyn_scenario::Scenario;
use std::path::Path;

/// "At F = 0.05": the loads within this distance of it ([0.04, 0.06], with room for rounding).
const NEAR: f64 = 0.0101;
/// Back-side impacts occur in a range of loads when at more than this share of its loads.
const IMPACTS: f64 = 0.5;
/// The medium-load row's chaos: chaotic runs at more than this share of the loads.
const CHAOS_MEDIUM: f64 = 0.3;

/// What the study computed: the multi-initial runs over F, the frequency scan and the basins.
pub(super) struct CoexistenceData {
    /// Half backlash D_s (the region of initial states scales with it).
    d: f64,
    /// The loads.
    values: Vec<f64>,
    /// Integration settings.
    sim: SimOptions,
    /// Initial states per value.
    ics: usize,
    /// The multi-initial sweep over F at [`OMEGA_LOAD`].
    multi: Vec<TaskResult>,
    /// The frequencies of the scan at F = 0.05.
    scan_omegas: Vec<f64>,
    /// The multi-initial scan over omega at F = 0.05.
    scan: Vec<TaskResult>,
    /// Basin cells per axis.
    nb: usize,
    /// Basins at F = 0.05.
    basins: BasinResult,
}

crate::runner::study!(CoexistenceLoad { base: &'a Scenario } "coexistence_load" CoexistenceData,
    |s, ctx, dir| compute(ctx, s.base, dir), |data| render(ctx, dir, data));

/// The multi-initial sweep over F, the scan over omega at F = 0.05 and the basins there.
pub(super) fn compute(ctx: &Ctx, base: &Scenario, dir: &Path) -> Result<CoexistenceData> {
    let b = base.with("omega", OMEGA_LOAD)?;
    let d = b.params().d_single;
    let mut values = ctx.n(vec![0.02, 0.1, 0.14], linspace(0.01, 0.15, 15));
    values.extend(ctx.n(
        vec![0.045, 0.05, 0.055],
        vec![0.04, 0.045, 0.05, 0.055, 0.06],
    ));
    values.sort_by(f64::total_cmp);
    values.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    let sim = ctx.sim((40, 100), (12, 30));
    let ics = ctx.n(3, 6);
    // the same initial states for the load sweep and the frequency scan
    let multi = SweepMode::Multi {
        ics,
        seed: 7,
        x0_range: attractor_region(d).0,
        v0_range: attractor_region(d).1,
    };
    let o = sweep(
        "F",
        values.clone(),
        multi.clone(),
        sim,
        vec![Sec::Strobe, Sec::Impact],
    );
    let multi_runs = ctx.sweep(dir, "multi-initial F", &b, &o)?;
    // the seed gives no frequency for this load: the same question over a few omega at F = 0.05
    let scan_w = ctx.n(
        vec![0.6, 1.0, 1.6, 2.2],
        vec![0.5, 0.7, 0.9, 1.0, 1.1, 1.3, 1.5, 1.8, 2.2],
    );
    let scan = ctx.sweep(
        dir,
        "omega scan at F = 0.05",
        &b.with("F", 0.05)?,
        &sweep("omega", scan_w.clone(), multi, sim, vec![Sec::Strobe]),
    )?;
    // basins at F = 0.05
    let nb = ctx.n(8, 24);
    let m = b.with("F", 0.05)?.model().clone();
    let basins = basin_grid(
        ctx,
        dir,
        &basins_grid(nb, d),
        &m,
        crate::shared::identify_options(ctx.n(40, 100), 16),
    )?;
    Ok(CoexistenceData {
        d,
        values,
        sim,
        ics,
        multi: multi_runs,
        scan_omegas: scan_w,
        scan,
        nb,
        basins,
    })
}

/// The grid of the basins at F = 0.05: `nb` x `nb` initial states on the [`attractor_region`] of
/// the largest half backlash `d`.
fn basins_grid(nb: usize, d: f64) -> BasinGrid<'static> {
    let (x, v) = attractor_region(d);
    BasinGrid {
        name: "basins_F_0.05",
        n: nb,
        x,
        v,
    }
}

/// The diagram, the tables, the basin figure and the claims.
pub(super) fn render(ctx: &Ctx, dir: &Path, data: &CoexistenceData) -> Result<Section> {
    let (d, values, sim, ics, nb) = (data.d, &data.values, data.sim, data.ics, data.nb);
    let (scan_w, br) = (&data.scan_omegas, &data.basins);
    let fig = sweep_figure(
        ctx, dir, "multi_F", "F", &data.multi, &[Sec::Strobe, Sec::Impact], &SweepPanels::default(),
        "Broken pair: multi-initial bifurcation over F (omega = 1.2)",
        "Broken pair, omega = 1.2: runs from several random initial states per load, coloured by decided motion (label in revolutions, period in mesh cycles in the legend); periodic motions drawn as larger squares over the points of the chaotic bands.",
    )?;
    let pts = classes::points(&data.multi, 0);
    let per_value: Vec<(f64, Vec<&Pt>)> = values
        .iter()
        .map(|&v| (v, pts.iter().filter(|p| p.value == v).collect()))
        .collect();
    let table = load_table(ctx, dir, &per_value)?;
    let (scan_table, p24_elsewhere) = omega_scan(ctx, dir, data)?;
    let mut claims = vec![near_claim(&Near::of(&pts), &p24_elsewhere, ics)];
    claims.extend(load_range_claims(&Shares::of(&per_value)));
    let (bfig, btable) = basin_render(
        ctx,
        dir,
        &basins_grid(nb, d),
        "Broken pair: basins at omega = 1.2, F = 0.05",
        br,
    )?;
    Ok(Section {
        id: "coexistence_load".into(),
        title: "Coexisting attractors over the load (multi-initial) and basins at F = 0.05".into(),
        seed_ref: "000 ¶9 (period-4 and period-2 coexist at F = 0.05); 001 abstract; 002 §5.2".into(),
        parameters: format!("F in [0.01, 0.15] plus 0.04–0.06 ({} values), omega = 1.2 (chosen: the seed gives none; a scan over {} values of omega at F = 0.05 shows the effect of that choice), {ics} initial states per value in x0 ∈ ±{}, x0' ∈ ±{} (a region that holds the coexisting impacting orbit); basins {nb} x {nb} over the same region", values.len(), scan_w.len(), f(attractor_region(d).0 .1), f(attractor_region(d).1 .1)),
        method: format!("Multi-initial sweep, {} + {} revolutions per run, decided classification; basins with attractor identification on the revolution strobe.", sim.transient_periods, sim.record_periods),
        figures: vec![fig, bfig],
        readings: vec![format!(
            "Basins at F = 0.05: {} attractor(s): {}.",
            br.attractors.len(),
            br.attractors.iter().map(|a| format!("{} ({:.0} %)", a.descriptor.label, 100.0 * a.fraction)).collect::<Vec<_>>().join(", ")
        )],
        tables: vec![table, scan_table, btable],
        claims,
        alternatives: vec![],
        seconds: 0.0,
    })
}

/// Whether the runs `ps` of one load coexist: two different periodic motions, or a periodic
/// and a chaotic one.
fn coexist(ps: &[&Pt]) -> bool {
    let periodic: Vec<&&Pt> = ps.iter().filter(|p| p.class.periodic()).collect();
    let mut n: Vec<&String> = periodic.iter().map(|p| &p.name).collect();
    n.sort();
    n.dedup();
    n.len() >= 2 || (n.len() == 1 && ps.iter().any(|p| p.class == Class::Chaotic))
}

/// The table of the motions found at each load.
fn load_table(ctx: &Ctx, dir: &Path, per_value: &[(f64, Vec<&Pt>)]) -> Result<Table> {
    let rows: Vec<Vec<String>> = per_value
        .iter()
        .map(|(v, ps)| {
            vec![
                f(*v),
                classes::names(ps).join(", "),
                classes::names(ps).len().to_string(),
                (if ps.iter().any(|p| p.back) {
                    "yes"
                } else {
                    "no"
                })
                .into(),
            ]
        })
        .collect();
    ctx.table(
        &dir.join("attractors_per_load.csv"),
        "Motions found from the initial states at each load",
        &hdr(&["F", "motions", "distinct", "back-side impacts"]),
        rows,
    )
}

/// The scan over omega at F = 0.05: its table, and the frequencies where a period 2 and a
/// period 4 coexist.
fn omega_scan(ctx: &Ctx, dir: &Path, data: &CoexistenceData) -> Result<(Table, Vec<f64>)> {
    let wpts = classes::points(&data.scan, 0);
    let scan_rows: Vec<(f64, Vec<String>, bool)> = data
        .scan_omegas
        .iter()
        .map(|&w| {
            let ps: Vec<&Pt> = wpts.iter().filter(|p| p.value == w).collect();
            let per = |k: usize| {
                ps.iter().any(|p| {
                    p.class.periodic() && (p.class.period() == Some(k) || p.mesh_period == Some(k))
                })
            };
            // revolution label and, for periodic motions, the period in mesh cycles
            let mut names: Vec<String> = ps
                .iter()
                .map(|p| match p.mesh_period {
                    Some(m) if p.class.periodic() => format!("{} ({m} mesh cycles)", p.name),
                    _ => p.name.clone(),
                })
                .collect();
            names.sort();
            names.dedup();
            (w, names, per(2) && per(4))
        })
        .collect();
    let p24_elsewhere: Vec<f64> = scan_rows.iter().filter(|r| r.2).map(|r| r.0).collect();
    let scan_table = ctx.table(
        &dir.join("omega_scan_F_0.05.csv"),
        "Motions at F = 0.05 over a few frequencies (the seed gives none for its load sweep)",
        &hdr(&["omega", "motions", "period 2 and period 4"]),
        scan_rows
            .iter()
            .map(|(w, n, both)| {
                vec![
                    f(*w),
                    n.join(", "),
                    (if *both { "yes" } else { "no" }).into(),
                ]
            })
            .collect(),
    )?;
    Ok((scan_table, p24_elsewhere))
}

/// The motions near F = 0.05 (within [`NEAR`]).
struct Near {
    /// A periodic motion of period 2, and of period 4 (on either clock).
    p2: bool,
    p4: bool,
    /// The periodic motions, with their periods in mesh cycles.
    periodic: Vec<String>,
    /// Every motion.
    all: Vec<String>,
}

impl Near {
    fn of(pts: &[Pt]) -> Near {
        let near: Vec<&Pt> = pts
            .iter()
            .filter(|p| (p.value - 0.05).abs() <= NEAR && p.class.periodic())
            .collect();
        let has = |k: usize| {
            near.iter()
                .any(|p| p.class.period() == Some(k) || p.mesh_period == Some(k))
        };
        let mut periodic: Vec<String> = near
            .iter()
            .map(|p| {
                format!(
                    "{}{}",
                    p.name,
                    p.mesh_period
                        .map_or(String::new(), |m| format!(" ({m} mesh cycles)"))
                )
            })
            .collect();
        periodic.sort();
        periodic.dedup();
        let mut all: Vec<String> = pts
            .iter()
            .filter(|p| (p.value - 0.05).abs() <= NEAR)
            .map(|p| p.name.clone())
            .collect();
        all.sort();
        all.dedup();
        Near {
            p2: has(2),
            p4: has(4),
            periodic,
            all,
        }
    }
}

/// Seed A's period 4 beside a period 2 at F = 0.05 (`p24_elsewhere`: the frequencies of the
/// scan where they coexist).
fn near_claim(near: &Near, p24_elsewhere: &[f64], ics: usize) -> Claim {
    let p24 = near.p2 && near.p4;
    let near_names = &near.periodic;
    Claim::new(
        "At F = 0.05 period-4 and period-2 attractors coexist",
        format!("{A000} ¶9"),
        "P2 and P4 coexist at F = 0.05",
        format!("periodic motions for F in [0.04, 0.06]: {}", if near_names.is_empty() { "none".into() } else { near_names.join("; ") }),
        // partly: a period 2 or 4 near F = 0.05, or the pair of them at another frequency;
        // another periodic motion alone (1-40-40) is not part of the statement
        if p24 { Verdict::Reproduced } else if near.p2 || near.p4 || !p24_elsewhere.is_empty() { Verdict::Partly } else { Verdict::NotReproduced },
        format!(
            "{ics} initial states per load at omega = 1.2 (the seed gives no frequency); periods in revolutions and in mesh cycles. Motions near F = 0.05: {}.{} At other frequencies (omega_scan_F_0.05.csv), period 2 beside period 4 at {}.",
            near.all.join(", "),
            if p24 || !near_names.is_empty() { "" } else { " Chaotic from every initial state tried." },
            if p24_elsewhere.is_empty() { "none of them".to_string() } else { format!("omega = {}", p24_elsewhere.iter().map(|w| f(*w)).collect::<Vec<_>>().join(", ")) }
        ),
    )
}

/// Shares of the loads of the low (F < 0.03), medium and high (F > 0.1) ranges.
#[derive(Clone, Copy)]
struct Shares {
    /// With coexisting motions.
    cl: f64,
    cm: f64,
    ch: f64,
    /// With back-side impacts (low and medium).
    il: f64,
    im: f64,
    /// With a chaotic run (medium).
    chaos_mid: f64,
}

impl Shares {
    fn of(per_value: &[(f64, Vec<&Pt>)]) -> Shares {
        let low: Vec<&(f64, Vec<&Pt>)> = per_value.iter().filter(|(v, _)| *v < 0.03).collect();
        let mid: Vec<&(f64, Vec<&Pt>)> = per_value
            .iter()
            .filter(|(v, _)| *v >= 0.03 && *v <= 0.1)
            .collect();
        let high: Vec<&(f64, Vec<&Pt>)> = per_value.iter().filter(|(v, _)| *v > 0.1).collect();
        let frac = |s: &[&(f64, Vec<&Pt>)], pred: &dyn Fn(&[&Pt]) -> bool| {
            s.iter().filter(|(_, ps)| pred(ps)).count() as f64 / s.len().max(1) as f64
        };
        let back = |ps: &[&Pt]| ps.iter().any(|p| p.back);
        Shares {
            cl: frac(&low, &coexist),
            cm: frac(&mid, &coexist),
            ch: frac(&high, &coexist),
            il: frac(&low, &back),
            im: frac(&mid, &back),
            chaos_mid: frac(&mid, &|ps| ps.iter().any(|p| p.class == Class::Chaotic)),
        }
    }
}

/// The claims on the load ranges: coexistence at smaller loads, and the low and medium rows of
/// the short version's table.
fn load_range_claims(s: &Shares) -> Vec<Claim> {
    let Shares {
        cl,
        cm,
        ch,
        il,
        im,
        chaos_mid,
    } = *s;
    let coexist_low_high = cl.max(cm) > ch;
    let low_ok = il > IMPACTS && cl == 0.0;
    vec![
        Claim::new(
            "Smaller loads induce the coexistence behaviour and back-side impact",
            format!("{A001} abstract and conclusions"),
            "coexistence at small F",
            format!("values with coexisting motions: F < 0.03 {}, 0.03–0.1 {}, F > 0.1 {}", pct(cl), pct(cm), pct(ch)),
            Verdict::of(coexist_low_high && il.max(im) > IMPACTS),
            format!(
                "Coexistence = two different periodic motions, or a periodic and a chaotic one, among the initial states of one load.{}",
                match (coexist_low_high, il.max(im) > IMPACTS, cl == 0.0) {
                    (true, true, true) => " Smaller than the large loads, not the smallest: every initial state reaches the same motion at F < 0.03 (as the short version's table has it, row below).",
                    (true, true, false) => "",
                    (false, _, _) => " Coexistence is not more frequent at the smaller loads here (shares above).",
                    (true, false, _) => " Coexistence is more frequent at the smaller loads, but back-side impacts occur at half the small loads or fewer.",
                }
            ),
        ),
        Claim::new(
            "Medium load: chaotic motion and period coexistence, with tooth-back impact",
            format!("{A002} §5.2 (table, row Medium)"),
            "chaos, coexistence, impacts",
            format!("0.03 ≤ F ≤ 0.1: chaos at {}, coexistence at {}, impacts at {} of loads", pct(chaos_mid), pct(cm), pct(im)),
            Verdict::of_parts(&[chaos_mid > CHAOS_MEDIUM, cm > 0.0, im > IMPACTS]),
            "Medium = 0.03–0.1 (the table gives no numbers).",
        ),
        Claim::new(
            "Low load: tooth-back impact, no period coexistence",
            format!("{A002} §5.2 (table, row Low)"),
            "impacts, no coexistence",
            format!("F < 0.03: impacts at {}, coexistence at {} of loads", pct(il), pct(cl)),
            if low_ok {
                Verdict::Reproduced
            } else if cl > 0.0 && coexist_low_high {
                Verdict::SeedInconsistent
            } else {
                Verdict::of_parts(&[il > IMPACTS, cl == 0.0])
            },
            "The long summary and the paper tie coexistence to smaller loads; the short version's table excludes it at the lowest loads. The row above with its measurement decides between them.",
        ),
    ]
}
