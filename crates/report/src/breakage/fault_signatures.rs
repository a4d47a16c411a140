//! Seed A's "fault prediction": which gear condition indicator shows the chipped tooth, at which
//! speeds and loads and for which chip sizes, with the multi-state motion (impacts, back-side
//! contact) beside each ratio (docs/analyses.md, "Fault signatures").
//!
//! Every point records the broken pair and its healthy twin with `geardyn signals`' library
//! request ([`run_signals`]): same operating point, same initial state, and like with like on
//! coexisting attractors (the healthy twin is moved onto the broken pair's attractor class when
//! it can be; a point where it cannot is marked and left out of the detection counts).

use crate::claims::{Claim, Verdict};
use crate::readings::f;
use crate::runner::{hdr, Ctx};
use crate::shared::{line_figure, Line};
use crate::{Figure, Section, Table};
use anyhow::{Context, Result};
use geardyn_analysis::indicators::{gaussian_reference, INDICATOR_NAMES};
use geardyn_analysis::signals::{run_signals, SignalsRequest, SignalsResult, SIGNAL_NAMES};
use geardyn_scenario::Scenario;
use rayon::prelude::*;
use std::path::Path;

const SOURCE: &str = "seed A 000 (summary) ¶1; 001 (paper) abstract; 002 (short version) §6";

/// A broken/healthy ratio at or above this factor (or at or below its inverse) detects the chip.
const DETECT: f64 = 2.0;

/// Content of a difference, residual or envelope signal (or of the first sidebands) below this
/// fraction of the TSA's standard deviation (-60 dB) counts as absent: a measurement's noise
/// would hide it. The integration's own floor is far lower
/// ([`geardyn_analysis::indicators::NOISE_FLOOR`]); a chip whose signature stays below -60 dB is
/// not detectable in practice.
const SENSOR_FLOOR: f64 = 1e-3;

/// The signal a condition-monitoring engineer measures: the acceleration (index in
/// [`SIGNAL_NAMES`]).
const ACCEL: usize = 2;

/// Indicators ranked for "which detects where": the ones whose healthy value is defined without
/// a noise model (a noise-free healthy pair has no sideband or difference energy at all, so the
/// energy ratio and the sideband indicators read infinite ratios wherever the broken pair has
/// any).
/// (the first ten of [`INDICATOR_NAMES`]; the energy ratio and the two sideband indicators follow)
const RANKED: &[&str] = INDICATOR_NAMES.split_at(10).0;

#[derive(Clone, Copy, Debug, PartialEq)]
struct Point {
    omega: f64,
    load: f64,
    chip_mm: f64,
}

/// Broken/healthy ratio of indicator `name` of signal `s`: against the Gaussian reference when
/// the healthy record's difference, residual or envelope is below [`SENSOR_FLOOR`] (normalised
/// moments), infinite for the others when only the broken pair has content, 1 when neither has.
fn ratio(r: &SignalsResult, s: usize, name: &str) -> f64 {
    let (h, b) = (&r.pairs[0], &r.pairs[1]);
    let z = r.options.mesh_order;
    let (hv, bv) = (
        h.indicators[s].get(name).unwrap_or(f64::NAN),
        b.indicators[s].get(name).unwrap_or(f64::NAN),
    );
    let hn = h.decompositions[s].indicator_below(name, z, SENSOR_FLOOR);
    let bn = b.decompositions[s].indicator_below(name, z, SENSOR_FLOOR);
    match (hn, bn, gaussian_reference(name)) {
        (true, true, _) => 1.0,
        (true, false, Some(g)) => bv / g,
        (false, true, Some(g)) => g / hv,
        (true, false, None) => f64::INFINITY,
        _ => bv / hv,
    }
}

fn detects(q: f64) -> bool {
    q >= DETECT || q <= 1.0 / DETECT
}

fn motion_text(r: &SignalsResult, k: usize) -> String {
    let m = &r.pairs[k].motion;
    format!("{} ({} impacts/rev)", m.label, f(m.impacts_per_rev))
}

/// Ratio as printed: `∞` when only the broken pair has the content.
fn q_text(q: f64) -> String {
    if q.is_infinite() {
        "∞".into()
    } else {
        f(q)
    }
}

/// What the study computed: the signals of both pairs at every point.
pub(super) struct FaultSignaturesData {
    /// The preset's chip (mm removed).
    chip0: f64,
    /// The request at every point.
    req: SignalsRequest,
    /// The speeds of the speed-load map.
    speeds: Vec<f64>,
    /// The loads of the speed-load map.
    loads: Vec<f64>,
    /// The (omega, F) of the chip-size points.
    chip_at: (f64, f64),
    /// The chip sizes (mm removed) besides the preset's.
    chips: Vec<f64>,
    /// The points: the speed-load map (its first `map_len`), then the chip sizes.
    points: Vec<Point>,
    /// Points of the speed-load map.
    map_len: usize,
    /// The signals of both pairs at each point.
    results: Vec<SignalsResult>,
}

crate::runner::study!(FaultSignatures { base: &'a Scenario } "fault_signatures" FaultSignaturesData,
    |s, ctx, dir| compute(ctx, s.base), |data| render(ctx, dir, data));

/// Records the broken pair and its healthy twin over the speed-load map and the chip sizes.
pub(super) fn compute(ctx: &Ctx, base: &Scenario) -> Result<FaultSignaturesData> {
    let chip0 = base
        .spec()
        .pair
        .as_ref()
        .and_then(|p| p.breakage)
        .and_then(|b| b.removed_height_mm)
        .context("the detectability study needs a pair with a chipped tooth (pair.breakage.removed_height_mm)")?;
    let req = SignalsRequest {
        revolutions: ctx.n(8, 16),
        transient: ctx.n(100, 300),
        samples_per_cycle: ctx.n(16, 32),
        segment_revolutions: ctx.n(2, 4),
        ..Default::default()
    };
    let speeds: Vec<f64> = ctx.n(vec![0.3, 1.2], vec![0.3, 0.6, 0.9, 1.2, 1.5]);
    let loads: Vec<f64> = ctx.n(vec![0.05, 0.15], vec![0.05, 0.1, 0.15]);
    let chip_at = (0.3, 0.15);
    let chips: Vec<f64> = ctx.n(vec![0.5, 1.5], vec![0.25, 0.5, 1.5]);
    let mut points: Vec<Point> = speeds
        .iter()
        .flat_map(|&omega| {
            loads.iter().map(move |&load| Point {
                omega,
                load,
                chip_mm: chip0,
            })
        })
        .collect();
    let map_len = points.len();
    points.extend(chips.iter().map(|&c| Point {
        omega: chip_at.0,
        load: chip_at.1,
        chip_mm: c,
    }));
    let results: Vec<SignalsResult> = points
        .par_iter()
        .map(|p| -> Result<SignalsResult> {
            let s = super::with_chip(base, p.chip_mm)?
                .with_all(&[("omega", p.omega), ("F", p.load)])?;
            Ok(run_signals(&s, &req)?)
        })
        .collect::<Result<_>>()?;
    Ok(FaultSignaturesData {
        chip0,
        req,
        speeds,
        loads,
        chip_at,
        chips,
        points,
        map_len,
        results,
    })
}

/// The ratios of the acceleration's indicators at every comparable point of `data`, ranked.
type Ranked = Vec<(&'static str, (usize, f64, f64))>;

/// The CSV of every ratio, the tables, the figures, the readings and the claims.
pub(super) fn render(ctx: &Ctx, dir: &Path, data: &FaultSignaturesData) -> Result<Section> {
    let (chip0, req, chip_at) = (data.chip0, &data.req, data.chip_at);
    let (speeds, loads, chips) = (&data.speeds, &data.loads, &data.chips);
    write_all_ratios(dir, data)?;
    let table = ratio_table(ctx, dir, data)?;
    // which indicator detects where (comparable points of the speed-load map and the chip sizes)
    let comparable: Vec<usize> = (0..data.points.len())
        .filter(|&i| data.results[i].comparable)
        .collect();
    let ranked = rank(data, &comparable);
    let readings = readings(data, &comparable, &ranked);
    let fig_chip = chip_figure(ctx, dir, data, &ranked)?;
    let fig_tsa = tsa_figure(ctx, dir, data, &comparable, ranked[0].0)?;
    let claims = vec![claim(data, &comparable, &ranked)];
    Ok(Section {
        id: "fault_signatures".into(),
        title: "Fault signatures: which condition indicator shows the chip, where".into(),
        seed_ref: "000 ¶1, 001 abstract, 002 §6 (\"fault prediction\"; the seeds compute no indicator)".into(),
        parameters: format!(
            "Speed-load map omega ∈ {{{}}} × F ∈ {{{}}} with the preset's chip ({} mm removed); chip sizes {{{}}} mm at omega = {}, F = {}; xi, c, friction and restitution of the preset.",
            speeds.iter().map(|v| f(*v)).collect::<Vec<_>>().join(", "),
            loads.iter().map(|v| f(*v)).collect::<Vec<_>>().join(", "),
            f(chip0),
            {
                let mut all: Vec<f64> = chips.iter().copied().chain(std::iter::once(chip0)).collect();
                all.sort_by(f64::total_cmp);
                all.dedup();
                all.iter().map(|v| f(*v)).collect::<Vec<_>>().join(", ")
            },
            f(chip_at.0),
            f(chip_at.1)
        ),
        method: format!(
            "geardyn signals' request at each point: {} revolutions of transient, {} recorded, {} samples per mesh cycle; both pairs from rest at tau = 0. Indicators of the acceleration's time-synchronous average (residual: mesh harmonics and shaft order 1 removed; NA4/NB4 over the run healthy → broken). A ratio detects at ≥ {} or ≤ 1/{}. Difference, residual, envelope or sideband content below -60 dB of the TSA counts as absent (a measurement's noise hides it); an absent healthy content is compared at the Gaussian value of its moment (FM4, NA4, NB4 3; M6A 15; M8A 105), both absent reads 1. When the two pairs settle on attractors of different classes, the healthy twin is restarted from the broken pair's final state; where it still differs the point is marked and not counted.",
            req.transient, req.revolutions, req.samples_per_cycle, f(DETECT), f(DETECT)
        ),
        figures: vec![fig_chip, fig_tsa],
        readings,
        tables: vec![table],
        claims,
        alternatives: vec![],
        seconds: 0.0,
    })
}

/// `detectability_all.csv`: every ratio of every signal, long format.
fn write_all_ratios(dir: &Path, data: &FaultSignaturesData) -> Result<()> {
    let (points, results) = (&data.points, &data.results);
    let mut long = Vec::new();
    for (p, r) in points.iter().zip(results) {
        for (s, sig) in SIGNAL_NAMES.iter().enumerate() {
            for name in INDICATOR_NAMES {
                let q = ratio(r, s, name);
                long.push(vec![
                    f(p.omega),
                    f(p.load),
                    f(p.chip_mm),
                    sig.to_string(),
                    name.to_string(),
                    format!("{}", r.pairs[1].indicators[s].get(name).unwrap_or(f64::NAN)),
                    format!("{}", r.pairs[0].indicators[s].get(name).unwrap_or(f64::NAN)),
                    q_text(q),
                    r.pairs[0].decompositions[s]
                        .indicator_below(name, r.options.mesh_order, SENSOR_FLOOR)
                        .to_string(),
                    r.comparable.to_string(),
                    r.pairs[1].motion.class.clone(),
                    r.pairs[0].motion.class.clone(),
                ]);
            }
        }
    }
    let all_csv = dir.join("detectability_all.csv");
    geardyn_io::output::write_csv(
        &all_csv,
        &[
            "omega",
            "F",
            "chip_mm",
            "signal",
            "indicator",
            "broken",
            "healthy",
            "ratio",
            "healthy_below_floor",
            "comparable",
            "class_broken",
            "class_healthy",
        ],
        long.iter().cloned(),
    )?;
    Ok(())
}

/// The page's table: the acceleration's ratios beside the motion of both pairs.
fn ratio_table(ctx: &Ctx, dir: &Path, data: &FaultSignaturesData) -> Result<Table> {
    let (points, results) = (&data.points, &data.results);
    let mut header = hdr(&[
        "omega",
        "F",
        "chip (mm)",
        "broken pair",
        "healthy twin",
        "like with like",
    ]);
    header.extend(INDICATOR_NAMES.iter().map(|s| s.to_string()));
    let rows: Vec<Vec<String>> = points
        .iter()
        .zip(results)
        .map(|(p, r)| {
            let mut row = vec![
                f(p.omega),
                f(p.load),
                f(p.chip_mm),
                motion_text(r, 1),
                motion_text(r, 0),
                if r.comparable {
                    if r.pairs[0].start == "initial state" {
                        "yes".into()
                    } else {
                        "yes (healthy twin moved)".into()
                    }
                } else {
                    "no".into()
                },
            ];
            row.extend(INDICATOR_NAMES.iter().map(|n| q_text(ratio(r, ACCEL, n))));
            row
        })
        .collect();
    ctx.table(
        &dir.join("detectability.csv"),
        "Broken/healthy ratio of each indicator of the acceleration (∞: the healthy twin has no such content, not even noise: no difference or sideband energy), with the motion of both pairs",
        &header,
        rows,
    )
}

/// The ranked indicators with their detections and their range of ratios over the comparable
/// points: most detections first, then the largest ratio.
fn rank(data: &FaultSignaturesData, comparable: &[usize]) -> Ranked {
    let score = |name: &str| -> (usize, f64, f64) {
        let qs: Vec<f64> = comparable
            .iter()
            .map(|&i| ratio(&data.results[i], ACCEL, name))
            .collect();
        let n = qs.iter().filter(|q| detects(**q)).count();
        let lo = qs.iter().cloned().fold(f64::INFINITY, f64::min);
        let hi = qs.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
        (n, lo, hi)
    };
    let mut ranked: Ranked = RANKED.iter().map(|n| (*n, score(n))).collect();
    ranked.sort_by(|a, b| b.1 .0.cmp(&a.1 .0).then(b.1 .2.total_cmp(&a.1 .2)));
    ranked
}

/// Where the indicator `name` detects the chip, in words.
fn where_of(data: &FaultSignaturesData, comparable: &[usize], name: &str) -> String {
    let (points, results) = (&data.points, &data.results);
    let at: Vec<String> = comparable
        .iter()
        .filter(|&&i| detects(ratio(&results[i], ACCEL, name)))
        .map(|&i| {
            let p = points[i];
            format!(
                "omega {} F {}{} (x{})",
                f(p.omega),
                f(p.load),
                if p.chip_mm == data.chip0 {
                    String::new()
                } else {
                    format!(" chip {} mm", f(p.chip_mm))
                },
                f(ratio(&results[i], ACCEL, name))
            )
        })
        .collect();
    if at.is_empty() {
        "nowhere".into()
    } else {
        at.join(", ")
    }
}

/// The readings: the four best indicators and where they detect, and the points left out.
fn readings(data: &FaultSignaturesData, comparable: &[usize], ranked: &Ranked) -> Vec<String> {
    ranked
        .iter()
        .take(4)
        .map(|(n, (k, lo, hi))| {
            format!(
                "{n} (acceleration): ratio ≥ {} or ≤ 1/{} at {k} of {} comparable points, ratios {}–{}; detects at {}.",
                f(DETECT),
                f(DETECT),
                comparable.len(),
                f(*lo),
                f(*hi),
                where_of(data, comparable, n)
            )
        })
        .chain(
            data.points
                .iter()
                .zip(&data.results)
                .filter(|(_, r)| !r.comparable)
                .map(|(p, r)| {
                    format!(
                        "Unlike attractors at omega {}, F {}, chip {} mm: broken pair {}, healthy twin {} (left out of the counts).",
                        f(p.omega),
                        f(p.load),
                        f(p.chip_mm),
                        r.pairs[1].motion.class,
                        r.pairs[0].motion.class
                    )
                }),
        )
        .collect()
}

/// Chip size at one point: the ratios of the ranked indicators, and the impacts beside them.
fn chip_figure(
    ctx: &Ctx,
    dir: &Path,
    data: &FaultSignaturesData,
    ranked: &Ranked,
) -> Result<Figure> {
    let (points, results, chip_at) = (&data.points, &data.results, data.chip_at);
    let mut chip_idx: Vec<usize> = (0..points.len())
        .filter(|&i| points[i].omega == chip_at.0 && points[i].load == chip_at.1)
        .collect();
    chip_idx.sort_by(|&a, &b| points[a].chip_mm.total_cmp(&points[b].chip_mm));
    let lines: Vec<Line> = ranked
        .iter()
        .take(5)
        .map(|(n, _)| Line {
            label: n.to_string(),
            points: chip_idx
                .iter()
                .map(|&i| (points[i].chip_mm, ratio(&results[i], ACCEL, n)))
                .collect(),
            dots: false,
        })
        .collect();
    let impacts: Vec<Line> = [(1usize, "broken pair"), (0, "healthy twin")]
        .iter()
        .map(|&(k, label)| Line {
            label: label.into(),
            points: chip_idx
                .iter()
                .map(|&i| {
                    (
                        points[i].chip_mm,
                        results[i].pairs[k].motion.impacts_per_rev,
                    )
                })
                .collect(),
            dots: true,
        })
        .collect();
    line_figure(
        ctx,
        dir,
        "detectability_chip",
        &format!(
            "Broken/healthy indicator ratios of the acceleration over chip size (omega = {}, F = {})",
            f(chip_at.0),
            f(chip_at.1)
        ),
        "removed tip height (mm)",
        vec![
            ("broken / healthy".into(), lines),
            ("impacts per revolution".into(), impacts),
        ],
        &[1.0, DETECT],
        &format!(
            "The indicators that detect the chip most often, as broken/healthy ratios over the chip size at omega = {}, F = {} (lines at 1 and at the detection factor {}), and the back-side impacts per revolution of both pairs beside them.",
            f(chip_at.0),
            f(chip_at.1),
            f(DETECT)
        ),
        false,
    )
}

/// The time-synchronous average of the acceleration where the best indicator `best` reads most.
fn tsa_figure(
    ctx: &Ctx,
    dir: &Path,
    data: &FaultSignaturesData,
    comparable: &[usize],
    best: &str,
) -> Result<Figure> {
    let (points, results) = (&data.points, &data.results);
    let at = comparable
        .iter()
        .copied()
        .max_by(|&a, &b| {
            let qa = ratio(&results[a], ACCEL, best);
            let qb = ratio(&results[b], ACCEL, best);
            (qa.ln().abs()).total_cmp(&qb.ln().abs())
        })
        .unwrap_or(0);
    let r = &results[at];
    let spr = r.samples_per_rev;
    let tsa_lines: Vec<Line> = [(1usize, "broken pair"), (0, "healthy twin")]
        .iter()
        .map(|&(k, label)| Line {
            label: label.into(),
            points: r.pairs[k].decompositions[ACCEL]
                .tsa
                .iter()
                .enumerate()
                .map(|(i, v)| ((i as f64 + 0.5) * 360.0 / spr as f64, *v))
                .collect(),
            dots: false,
        })
        .collect();
    let p = points[at];
    line_figure(
        ctx,
        dir,
        "detectability_tsa",
        &format!(
            "Time-synchronous average of the acceleration, omega = {}, F = {}, chip {} mm",
            f(p.omega),
            f(p.load),
            f(p.chip_mm)
        ),
        "pinion angle (degrees)",
        vec![("acceleration (m/s²)".into(), tsa_lines)],
        &[],
        &format!(
            "Where {best} reads the largest ratio (x{}): the acceleration averaged over {} revolutions, broken pair ({}) against its healthy twin ({}).",
            f(ratio(r, ACCEL, best)),
            r.revolutions,
            motion_text(r, 1),
            motion_text(r, 0)
        ),
        false,
    )
}

/// The seeds' aim: the best indicator detects the chip at most like-with-like points.
fn claim(data: &FaultSignaturesData, comparable: &[usize], ranked: &Ranked) -> Claim {
    let (results, map_len) = (&data.results, data.map_len);
    let best = ranked[0].0;
    let (n_best, lo_best, hi_best) = ranked[0].1;
    let n_cmp = comparable.len();
    let verdict = if n_cmp > 0 && 4 * n_best >= 3 * n_cmp {
        Verdict::Reproduced
    } else if n_best > 0 {
        Verdict::Partly
    } else {
        Verdict::NotReproduced
    };
    let map_cmp = comparable.iter().filter(|&&i| i < map_len).count();
    let map_det = comparable
        .iter()
        .filter(|&&i| i < map_len && detects(ratio(&results[i], ACCEL, best)))
        .count();
    Claim::new(
        "Localized tooth breakage can be predicted from the gear's vibration (the seeds' aim: guidance for fault prediction)",
        SOURCE,
        "a detectable signature (no indicator named)",
        format!(
            "{best} of the acceleration changes by a factor {} or more at {n_best} of {n_cmp} like-with-like points (ratios {}–{}); speed-load map: {map_det} of {map_cmp}",
            f(DETECT),
            f(lo_best),
            f(hi_best)
        ),
        verdict,
        "Broken pair and healthy twin from one state, one operating point; condition indicators of the acceleration's TSA (detectability.csv: every indicator, signal and point). Where the chip falls into separation the two pairs move alike and nothing detects it.",
    )
}
