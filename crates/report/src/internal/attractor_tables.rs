//! B10–B12, shared: the rows of seed B's attractor tables (an interval of the parameter and the
//! attractors listed in it) and its basin shares, checked against multi-initial runs and basins;
//! used by the studies `attractors_omega`, `attractors_F` and `readings`.

use super::{multi, DD_SEED, DS_SEED};
use crate::claims::{Claim, Verdict};
use crate::classes::{self, Pt};
use crate::readings::{f, pct};
use crate::runner::Ctx;
use crate::shared::{
    basin_boxes, basin_grid, basin_render, box_text, identify_options, BasinGrid, StateBox,
};
use crate::{Figure, Table};
use anyhow::Result;
use geardyn_analysis::basins::BasinResult;
use geardyn_analysis::bifurcation::attractor_region;
use geardyn_analysis::continuation::ContinuationOptions;
use geardyn_model::MeshModel;
use geardyn_scenario::Scenario;
use std::path::Path;

/// Share of a table row's interval trimmed at each end before it is checked: the seed's borders
/// are bifurcation points.
const TRIM: f64 = 0.15;

/// An attractor of the seed's tables, as a test on a run.
pub(super) struct Spec {
    /// Name shown in the claim.
    pub(super) name: &'static str,
    /// The seed's attractor exactly (its label).
    pub(super) test: fn(&Pt) -> bool,
    /// The same kind of motion with another label (e.g. a healthy period 1).
    pub(super) loose: Option<fn(&Pt) -> bool>,
}

/// An attractor of the seed's tables known by its test alone.
pub(super) fn sp(name: &'static str, test: fn(&Pt) -> bool) -> Spec {
    Spec {
        name,
        test,
        loose: None,
    }
}

/// An attractor of the seed's tables, with the same kind of motion under another label.
pub(super) fn spl(name: &'static str, test: fn(&Pt) -> bool, loose: fn(&Pt) -> bool) -> Spec {
    Spec {
        name,
        test,
        loose: Some(loose),
    }
}

/// Share of the values in the interior of `[a, b]` (15 % trimmed at each end, at least the value
/// nearest the middle) where some run satisfies `test`.
pub(super) fn presence(pts: &[Pt], a: f64, b: f64, test: fn(&Pt) -> bool) -> f64 {
    let w = b - a;
    let (lo, hi) = (a + TRIM * w, b - TRIM * w);
    let mut vals = classes::values_in(pts, lo, hi);
    if vals.is_empty() {
        let mid = 0.5 * (a + b);
        if let Some(p) = pts
            .iter()
            .min_by(|x, y| (x.value - mid).abs().total_cmp(&(y.value - mid).abs()))
        {
            vals.push(p.value);
        }
    }
    let hit = vals
        .iter()
        .filter(|&&v| pts.iter().any(|p| p.value == v && test(p)))
        .count();
    hit as f64 / vals.len().max(1) as f64
}

pub(super) fn found_in(pts: &[Pt], a: f64, b: f64) -> String {
    let w = b - a;
    let (lo, hi) = (a + TRIM * w, b - TRIM * w);
    let mut inside: Vec<&Pt> = pts
        .iter()
        .filter(|p| p.value >= lo && p.value <= hi)
        .collect();
    if inside.is_empty() {
        let mid = 0.5 * (a + b);
        if let Some(p) = pts
            .iter()
            .min_by(|x, y| (x.value - mid).abs().total_cmp(&(y.value - mid).abs()))
        {
            inside = pts.iter().filter(|q| q.value == p.value).collect();
        }
    }
    let mut vals: Vec<f64> = inside.iter().map(|p| p.value).collect();
    vals.dedup();
    let nv = vals.len().max(1) as f64;
    let names = classes::names(&inside);
    names
        .iter()
        .map(|n| {
            let k = vals
                .iter()
                .filter(|&&v| inside.iter().any(|p| p.value == v && &p.name == n))
                .count();
            format!("{n} ({})", pct(k as f64 / nv))
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// A row is reproduced when every listed attractor is reached at this share of the interval's
/// values at least (and no unlisted one at half of them).
pub(super) const PRESENT: f64 = 0.5;
/// A row is partly reproduced when some listed attractor, or one of the same kind, is reached
/// at this share of the values at least (or every one at [`PRESENT`]).
const PARTLY_PRESENT: f64 = 0.25;

/// A row of an attractor table checked against the multi-initial runs.
pub(super) fn table_row(
    pts: &[Pt],
    a: f64,
    b: f64,
    specs: &[Spec],
    claim: String,
    source: String,
    seed: String,
) -> Claim {
    let shares: Vec<f64> = specs.iter().map(|s| presence(pts, a, b, s.test)).collect();
    let loose: Vec<f64> = specs
        .iter()
        .zip(&shares)
        .map(|(s, &e)| s.loose.map_or(e, |l| e.max(presence(pts, a, b, l))))
        .collect();
    // an attractor the seed does not list, present at half the values or more
    let extra: Vec<String> = {
        let w = b - a;
        let (lo, hi) = (a + TRIM * w, b - TRIM * w);
        let inside: Vec<&Pt> = pts
            .iter()
            .filter(|p| p.value >= lo && p.value <= hi)
            .collect();
        let mut vals: Vec<f64> = inside.iter().map(|p| p.value).collect();
        vals.dedup();
        classes::names(&inside)
            .into_iter()
            .filter(|n| {
                let listed = inside.iter().filter(|p| &p.name == n).any(|p| {
                    specs
                        .iter()
                        .any(|s| (s.test)(p) || s.loose.is_some_and(|l| l(p)))
                });
                let k = vals
                    .iter()
                    .filter(|&&v| inside.iter().any(|p| p.value == v && &p.name == n))
                    .count();
                !listed && k * 2 >= vals.len().max(1)
            })
            .collect()
    };
    let verdict = if shares.iter().all(|&s| s >= PRESENT) && extra.is_empty() {
        Verdict::Reproduced
    } else if loose.iter().all(|&s| s >= PRESENT) || loose.iter().any(|&s| s >= PARTLY_PRESENT) {
        Verdict::Partly
    } else {
        Verdict::NotReproduced
    };
    let mut label_note = if shares.iter().zip(&loose).any(|(e, l)| l > e) {
        " The same kind of motion (period, health) with another label counts as partly.".to_string()
    } else {
        String::new()
    };
    {
        let w = b - a;
        let n_in = {
            let mut v: Vec<f64> = pts
                .iter()
                .map(|p| p.value)
                .filter(|v| *v >= a + TRIM * w && *v <= b - TRIM * w)
                .collect();
            v.dedup();
            v.len()
        };
        if n_in < 2 {
            label_note
                .push_str(" Interval narrower than two grid steps: the nearest values checked.");
        }
    }
    if !extra.is_empty() {
        label_note.push_str(&format!(
            " Also present at half the values or more, not in the seed's row: {}.",
            extra.join(", ")
        ));
    }
    Claim::new(
        claim,
        source,
        seed,
        format!(
            "found in the interior [{}, {}] of ({}, {}) (15 % trimmed at each end: the seed's borders are bifurcation points): {}",
            f(a + TRIM * (b - a)),
            f(b - TRIM * (b - a)),
            f(a),
            f(b),
            found_in(pts, a, b)
        ),
        verdict,
        format!(
            "Share of values (interval interior) where each listed attractor is reached from some initial state: {}.{label_note}",
            specs
                .iter()
                .zip(shares.iter().zip(&loose))
                .map(|(s, (e, l))| if l > e {
                    format!("{} {} (same kind {})", s.name, pct(*e), pct(*l))
                } else {
                    format!("{} {}", s.name, pct(*e))
                })
                .collect::<Vec<_>>()
                .join(", ")
        ),
    )
}

fn share_of(
    r: &BasinResult,
    test: &dyn Fn(&geardyn_analysis::attractor::Descriptor) -> bool,
) -> f64 {
    r.attractors
        .iter()
        .filter(|a| test(&a.descriptor))
        .map(|a| a.fraction)
        .sum()
}

/// Whether an attractor is the one a seed names.
type AttractorTest = dyn Fn(&geardyn_analysis::attractor::Descriptor) -> bool;

/// A seed attractor of a basin: name, seed share, test.
type BasinPart<'a> = (&'a str, f64, &'a AttractorTest);

/// [`basin_claim`] of attractors the seed names by label (`(name, label, seed share)`), each
/// matched by its label only: another attractor of the same period and health is another
/// attractor, with a share of its own.
pub(super) fn labelled_basin_claim(
    boxes: &[(String, BasinResult)],
    named: &[(&str, &str, f64)],
    claim: &str,
    source: String,
) -> Claim {
    let names: Vec<String> = named.iter().map(|(n, l, _)| format!("{n} ({l})")).collect();
    let tests: Vec<Box<AttractorTest>> = named
        .iter()
        .map(|&(_, l, _)| {
            let l = l.to_string();
            Box::new(move |a: &geardyn_analysis::attractor::Descriptor| a.label == l) as Box<_>
        })
        .collect();
    let parts: Vec<BasinPart> = named
        .iter()
        .zip(&names)
        .zip(&tests)
        .map(|((&(_, _, share), n), t)| (n.as_str(), share, t.as_ref()))
        .collect();
    basin_claim(boxes, &parts, claim, source)
}

/// Boxes of initial states on which basin shares are read, besides the figure's box
/// (`x0 ∈ ±2 D, x0' ∈ ±1.5`): the former multi-initial box (`±1.5 D, ±1`) and a wide one (`±3 D,
/// ±3`).
pub(super) fn extra_boxes(d: f64) -> [StateBox; 2] {
    [
        ((-1.5 * d, 1.5 * d), (-1.0, 1.0)),
        ((-3.0 * d, 3.0 * d), (-3.0, 3.0)),
    ]
}

/// The boxes of [`extra_boxes`] in words: `A and B`.
pub(super) fn extra_boxes_text(d: f64) -> String {
    let [a, b] = extra_boxes(d);
    format!(
        "{} and {}",
        crate::shared::box_text(a.0, a.1),
        crate::shared::box_text(b.0, b.1)
    )
}

/// A seed's basin share is matched when the measured share lies within this distance of it
/// (10 points).
const SHARE_TOLERANCE: f64 = 0.1;
/// Attractors the seed does not name may hold less than this share of the figure's box for the
/// basin claim to be reproduced.
const UNNAMED_MAX: f64 = 0.1;

/// A share claim of the seed against basins on several boxes (the first is the figure's). The
/// seed never gives its box and shares depend on it: the claim is reproduced when every named
/// attractor is found on the figure's box and, on at least one box, every share lies within 10
/// points of the seed's; partly when some are found.
pub(super) fn basin_claim(
    boxes: &[(String, BasinResult)],
    parts: &[BasinPart],
    claim: &str,
    source: String,
) -> Claim {
    let (_, r) = &boxes[0];
    let found: Vec<bool> = parts
        .iter()
        .map(|(_, _, t)| r.attractors.iter().any(|a| t(&a.descriptor)))
        .collect();
    let shares: Vec<Vec<f64>> = boxes
        .iter()
        .map(|(_, rb)| parts.iter().map(|(_, _, t)| share_of(rb, *t)).collect())
        .collect();
    let close_on = |sh: &Vec<f64>| {
        parts
            .iter()
            .zip(sh)
            .all(|((_, seed, _), s)| (seed - s).abs() <= SHARE_TOLERANCE)
    };
    let close_box = shares.iter().position(close_on);
    let all_found = found.iter().all(|&x| x);
    // a seed attractor stands for one attractor: several matching it (or attractors the seed
    // does not name holding a tenth of the basin) is not the seed's picture
    let several: Vec<&str> = parts
        .iter()
        .filter(|(_, _, t)| r.attractors.iter().filter(|a| t(&a.descriptor)).count() > 1)
        .map(|(n, _, _)| *n)
        .collect();
    let unnamed: f64 = r
        .attractors
        .iter()
        .filter(|a| !parts.iter().any(|(_, _, t)| t(&a.descriptor)))
        .map(|a| a.fraction)
        .sum();
    let verdict = if all_found && close_box.is_some() && several.is_empty() && unnamed < UNNAMED_MAX
    {
        Verdict::Reproduced
    } else if found.iter().any(|&x| x) {
        Verdict::Partly
    } else {
        Verdict::NotReproduced
    };
    let measured = parts
        .iter()
        .enumerate()
        .map(|(i, (n, _, _))| {
            if found[i] {
                let per_box: Vec<String> = shares.iter().map(|sh| pct(sh[i])).collect();
                format!("{n} {}", per_box.join(" / "))
            } else {
                format!("{n} not found")
            }
        })
        .collect::<Vec<_>>()
        .join(", ");
    let mut closest = match close_box {
        Some(i) => format!(" Within 10 points of every seed share on box ({}).", i + 1),
        None => " No box brings every share within 10 points of the seed's.".into(),
    };
    for n in &several {
        closest.push_str(&format!(
            " Several attractors match {n}: its share is their sum."
        ));
    }
    if unnamed >= UNNAMED_MAX {
        closest.push_str(&format!(
            " Attractors the seed does not name hold {} of the figure's box.",
            pct(unnamed)
        ));
    }
    let missing: Vec<&str> = parts
        .iter()
        .zip(&found)
        .filter(|(_, f)| !**f)
        .map(|((n, _, _), _)| *n)
        .collect();
    if !missing.is_empty() {
        closest.push_str(&format!(" Not found: {}.", missing.join(", ")));
    }
    Claim::new(
        claim,
        source,
        parts.iter().map(|(n, seed, _)| format!("{n} {}", pct(*seed))).collect::<Vec<_>>().join(", "),
        format!("{measured} (boxes 1 / 2 / 3)"),
        verdict,
        format!(
            "The seed gives no box of initial states and shares depend on it: read on three boxes (the section's parameters).{closest} On box 1: {}.",
            r.attractors.iter().map(|a| format!("{} {}", a.descriptor.label, pct(a.fraction))).collect::<Vec<_>>().join(", ")
        ),
    )
}

pub(super) fn continuation_opts(
    param: &str,
    values: Vec<f64>,
    ics: usize,
    d: f64,
) -> ContinuationOptions {
    ContinuationOptions {
        param: param.into(),
        values,
        ics,
        seed: 1,
        x0_range: attractor_region(d).0,
        v0_range: attractor_region(d).1,
        phase: 0.0,
        identify: identify_options(300, 32),
    }
}

/// What an attractor study (over omega, over F) computed: the multi-initial sweep, the
/// continuation, the basins and the marker runs, rendered by the study's own `render`.
pub(super) struct AttractorsData {
    /// Half backlash D_s of the scenario (the boxes of initial states scale with it).
    pub(super) d: f64,
    /// Values of the multi-initial sweep.
    pub(super) values: Vec<f64>,
    /// Initial states per value.
    pub(super) ics: usize,
    /// Basin cells per axis.
    pub(super) nb: usize,
    /// The multi-initial sweep.
    pub(super) multi: Vec<geardyn_analysis::bifurcation::TaskResult>,
    /// The attractor continuation (safety tree).
    pub(super) continuation: geardyn_analysis::continuation::ContinuationResult,
    /// Basins at the study's basin values.
    pub(super) basins: Vec<BasinsAt>,
    /// The motions at marker values with both backlash levels.
    pub(super) markers: MarkerRuns,
}

impl AttractorsData {
    /// The basins of each basin value, box by box.
    pub(super) fn basin_results(&self) -> Vec<&[(String, geardyn_analysis::basins::BasinResult)]> {
        self.basins.iter().map(|b| b.boxes.as_slice()).collect()
    }
}

/// The motions found at a few marker values with the pair's physical backlash and with the
/// levels of the xi sweep (D_d = 0.9, D_s = 1): how much the attractor tables depend on the
/// backlash levels the seed does not give.
pub(super) struct MarkerRuns {
    /// The parameter.
    param: String,
    /// Its marker values.
    markers: Vec<f64>,
    /// Initial states per value.
    ics: usize,
    /// The pair's physical D_s - D_d.
    physical_step: f64,
    /// The motions found at each marker: with the physical backlash, then with the nominal one.
    motions: [Vec<String>; 2],
}

/// Runs the marker values of `param` from several initial states with both backlash levels.
pub(super) fn marker_runs(
    ctx: &Ctx,
    dir: &Path,
    b: &Scenario,
    param: &str,
    markers: &[f64],
) -> Result<MarkerRuns> {
    let alt = b.with_all(&[("D_d", DD_SEED), ("D_s", DS_SEED)])?;
    let ics = ctx.n(4, 8);
    let sim = ctx.sim((150, 300), (30, 60));
    let mut cols: Vec<Vec<String>> = Vec::new();
    for (k, s) in [b, &alt].into_iter().enumerate() {
        let d = s.params().d_single;
        let r = ctx.sweep(
            dir,
            &format!("{param} markers {k}"),
            s,
            &multi(param, markers.to_vec(), sim, ics, d),
        )?;
        let pts = classes::points(&r, 0);
        cols.push(
            markers
                .iter()
                .map(|&v| {
                    let ps: Vec<&Pt> = pts.iter().filter(|p| p.value == v).collect();
                    classes::names(&ps).join(", ")
                })
                .collect(),
        );
    }
    let nominal = cols.pop().unwrap_or_default();
    let physical = cols.pop().unwrap_or_default();
    Ok(MarkerRuns {
        param: param.to_string(),
        markers: markers.to_vec(),
        ics,
        physical_step: b.params().d_single - b.params().d_double,
        motions: [physical, nominal],
    })
}

/// The table of [`MarkerRuns`] (`backlash_sensitivity.csv`).
pub(super) fn backlash_sensitivity(ctx: &Ctx, dir: &Path, runs: &MarkerRuns) -> Result<Table> {
    let (param, ics, cols) = (&runs.param, runs.ics, &runs.motions);
    ctx.table(
        &dir.join("backlash_sensitivity.csv"),
        &format!("Motions at marker values of {param}: physical backlash of the pair (D_s - D_d = {}) against D_d = 0.9, D_s = 1 ({ics} initial states)", f(runs.physical_step)),
        &[param.to_string(), "physical backlash".into(), "D_d = 0.9, D_s = 1".into()],
        runs.markers
            .iter()
            .enumerate()
            .map(|(i, v)| vec![f(*v), cols[0][i].clone(), cols[1][i].clone()])
            .collect(),
    )
}

/// Basins at one value of the swept parameter, on the figure's box (`x0 ∈ ±2 D, x0' ∈ ±1.5`)
/// and possibly on [`extra_boxes`].
pub(super) struct BasinsAt {
    /// File name of the figure (and of the checkpoints).
    pub(super) name: String,
    /// Cells per axis.
    pub(super) n: usize,
    /// The figure's box.
    pub(super) state_box: StateBox,
    /// (box description, basins) per box, the figure's first.
    pub(super) boxes: Vec<(String, BasinResult)>,
}

/// Basins of `model` on the figure's box for the half backlash `d`, and on [`extra_boxes`]
/// when `extra`.
pub(super) fn basins_at(
    ctx: &Ctx,
    dir: &Path,
    name: String,
    model: &MeshModel,
    (n, d): (usize, f64),
    extra: bool,
) -> Result<BasinsAt> {
    let state_box = ((-2.0 * d, 2.0 * d), (-1.5, 1.5));
    let g = BasinGrid {
        name: &name,
        n,
        x: state_box.0,
        v: state_box.1,
    };
    let grid = basin_grid(ctx, dir, &g, model, identify_options(300, 32))?;
    let mut boxes = vec![(box_text(state_box.0, state_box.1), grid)];
    if extra {
        boxes.extend(basin_boxes(
            ctx,
            dir,
            &name,
            model,
            n,
            &extra_boxes(d),
            identify_options(300, 32),
        )?);
    }
    Ok(BasinsAt {
        name,
        n,
        state_box,
        boxes,
    })
}

/// The figure and the attractor table of [`BasinsAt`] on the figure's box.
pub(super) fn basins_figure(
    ctx: &Ctx,
    dir: &Path,
    basins: &BasinsAt,
    title: &str,
) -> Result<(Figure, Table)> {
    let (x, v) = basins.state_box;
    let g = BasinGrid {
        name: &basins.name,
        n: basins.n,
        x,
        v,
    };
    basin_render(ctx, dir, &g, title, &basins.boxes[0].1)
}
