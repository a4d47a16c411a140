//! Attractor continuation along a parameter — the "bifurcation and safety tree" (docs/model.md §5).
//!
//! At every value, the same `K` seeded initial states are integrated and their attractors
//! identified ([`crate::attractor`]); the values are independent and run in parallel. Attractors
//! of consecutive values are then matched into branches: a periodic orbit described at both values
//! (same label, points within ten times the matching tolerance) continues its branch; the others
//! by **basin overlap** — how many of the same initial states go to the old and to the new
//! attractor, pairs that keep their periodic label first — and only where no initial state is
//! shared, by descriptor distance. Events between consecutive values are reported: an
//! attractor appears while others persist (incomplete bifurcation), disappears, doubles its
//! period, turns chaotic, or several merge into one chaotic attractor.

// Branch matching indexes several parallel tables by attractor number.
#![allow(clippy::needless_range_loop)]

use crate::attractor::{Descriptor, IdentifyOptions, Outcome, Recordable};
use crate::basins::Slice;
use crate::identify::{assign, consolidate, identify};
use geardyn_model::MeshModel;
use geardyn_scenario::{Scenario, ScenarioError};
use geardyn_solvers::HybridSystem;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;

/// Settings of a continuation.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ContinuationOptions {
    /// Parameter name.
    pub param: String,
    /// Values, in order.
    pub values: Vec<f64>,
    /// Initial states per value.
    pub ics: usize,
    /// Seed of the initial states.
    pub seed: u64,
    /// Range of `x0`.
    pub x0_range: (f64, f64),
    /// Range of `v0`.
    pub v0_range: (f64, f64),
    /// Phase of the initial states, as a fraction of the excitation period in `[0, 1)`: the
    /// runs of every value start at `phase` times that value's excitation period (the
    /// stroboscopic section the basins share; `identify.sim.tau0` is replaced by it).
    pub phase: f64,
    /// Identification settings.
    pub identify: IdentifyOptions,
}

/// Attractors found at one value.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ValueAttractors<const N: usize = 2> {
    /// Index of the value.
    pub index: usize,
    /// Parameter value.
    pub value: f64,
    /// Attractors (in order of discovery).
    pub attractors: Vec<Descriptor<N>>,
    /// Attractor of each initial state (-1 divergent, -2 failed).
    pub assignment: Vec<i64>,
}

impl<const N: usize> ValueAttractors<N> {
    /// Basin fraction of attractor `a` (over all initial states).
    pub fn fraction(&self, a: usize) -> f64 {
        self.assignment.iter().filter(|&&x| x == a as i64).count() as f64
            / self.assignment.len().max(1) as f64
    }
}

/// One row of the continuation table: an attractor at a value, on its branch.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BranchPoint {
    /// Parameter value.
    pub value: f64,
    /// Branch id (stable along the parameter).
    pub branch: usize,
    /// Label.
    pub label: String,
    /// Period.
    pub period: usize,
    /// Healthy.
    pub healthy: bool,
    /// Basin fraction.
    pub fraction: f64,
    /// Maximum mesh force.
    pub max_force: f64,
    /// First stroboscopic point.
    pub x: f64,
    /// First stroboscopic point (velocity).
    pub v: f64,
}

/// An event between two consecutive values.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ContinuationEvent {
    /// Value before.
    pub from: f64,
    /// Value after.
    pub to: f64,
    /// Kind: `appearance`, `incomplete_bifurcation`, `disappearance`, `period_doubling`,
    /// `period_change`, `transition_to_chaos`, `merger_into_chaos`, `exit_from_chaos`.
    pub kind: String,
    /// Branches involved.
    pub branches: Vec<usize>,
    /// Human-readable description.
    pub text: String,
}

/// A parameter interval over which the set of attractors (branch and label) does not change.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Interval {
    /// First value.
    pub from: f64,
    /// Last value.
    pub to: f64,
    /// Healthy attractors: `(branch, label, min fraction, max fraction)`.
    pub healthy: Vec<(usize, String, f64, f64)>,
    /// Non-healthy attractors (back-side contact, or not periodic; the seeds call them
    /// "unstable", which does not mean dynamically unstable).
    pub non_healthy: Vec<(usize, String, f64, f64)>,
}

/// Continuation result.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ContinuationResult {
    /// Parameter name.
    pub param: String,
    /// Table rows.
    pub points: Vec<BranchPoint>,
    /// Events.
    pub events: Vec<ContinuationEvent>,
    /// Intervals (the seeds' attractor-evolution table).
    pub intervals: Vec<Interval>,
    /// Fraction of divergent or failed initial states per value.
    pub lost: Vec<(f64, f64)>,
}

/// Initial state `ic` (the same set at every value, so basins can be compared), drawn among the
/// states `admissible` accepts ([`crate::sweep_settings::draw_state`]).
pub fn initial_state(
    opts: &ContinuationOptions,
    ic: usize,
    admissible: impl Fn(&[f64; 2]) -> bool,
) -> [f64; 2] {
    let mut rng =
        ChaCha8Rng::seed_from_u64(opts.seed ^ (ic as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15));
    crate::sweep_settings::draw_state(&mut rng, opts.x0_range, opts.v0_range, admissible)
}

/// Attractors at one value (first quarter of the initial states without, the rest with early
/// capture; deterministic).
pub fn attractors_at(
    model: &MeshModel,
    index: usize,
    value: f64,
    opts: &ContinuationOptions,
) -> ValueAttractors {
    attractors_of(model, index, value, opts, &Slice::default())
}

/// As [`attractors_at`] for any system that can be identified, its initial states in `slice`
/// (the pair: its whole state). With fixed-step RK4 the pair's initial states run in lockstep
/// lanes (the same outcomes).
pub fn attractors_of<S: Recordable<N>, const N: usize>(
    sys: &S,
    index: usize,
    value: f64,
    opts: &ContinuationOptions,
    slice: &Slice<N>,
) -> ValueAttractors<N> {
    let k = opts.ics.max(1);
    let first = k.div_ceil(4);
    let mut id = opts.identify;
    id.sim.tau0 = opts.phase * sys.strobe_period();
    let t0 = id.sim.tau0;
    let plane =
        |ic: usize| initial_state(opts, ic, |&[a, b]| sys.admissible(t0, &slice.state(a, b)));
    let start = |ic: usize| {
        let [a, b] = plane(ic);
        slice.state(a, b)
    };
    let mut known: Vec<Descriptor<N>> = Vec::new();
    let mut assignment = vec![-2i64; k];
    for (lo, hi) in [(0, first), (first, k)] {
        let snapshot = known.clone();
        let lanes = sys
            .as_mesh()
            .filter(|_| *slice == Slice::default())
            .zip(crate::lanes_identify::LaneIdentify::new(&id));
        let outs: Vec<Outcome<N>> = if let Some((model, lane)) = lanes {
            // fixed-step RK4: the initial states in lockstep lanes (the same outcomes; the
            // pair's lanes speak its own dimension, N = 2 here)
            let y0s: Vec<[f64; 2]> = (lo..hi).map(plane).collect();
            let pair: Vec<Descriptor> = snapshot.iter().map(|d| d.clone().resized()).collect();
            crate::lanes_identify::identify_lanes(model, &y0s, &pair, None, lane, |_, _| {})
                .into_iter()
                .map(Outcome::resized)
                .collect()
        } else {
            (lo..hi)
                .into_par_iter()
                .map(|ic| identify(sys, start(ic), &snapshot, &id))
                .collect()
        };
        let first_new = known.len();
        let ids = assign(&mut known, &outs, id.match_tol);
        assignment[lo..hi].copy_from_slice(&ids);
        consolidate(sys, &mut known, first_new, &mut assignment, &id);
    }
    ValueAttractors {
        index,
        value,
        attractors: known,
        assignment,
    }
}

/// Attractor continuation of a one-parameter family of systems (any system that can be
/// identified, e.g. a gear system of your own with [`crate::attractor::describe_gear`]): the
/// attractors at every value of `opts.values` from the same initial states (in `slice`), linked
/// into branches with their events and intervals ([`link`]; `opts.param` names the parameter).
/// In parallel, the same result on any thread count.
pub fn continuation_of<F, const N: usize>(
    fam: &F,
    opts: &ContinuationOptions,
    slice: &Slice<N>,
) -> Result<ContinuationResult, crate::simulate::SimError>
where
    F: crate::generic::Family<N>,
    F::System: Recordable<N>,
{
    check_options(opts)?;
    let per_value: Vec<ValueAttractors<N>> = (0..opts.values.len())
        .into_par_iter()
        .map(|i| attractors_of(&fam.at(opts.values[i]), i, opts.values[i], opts, slice))
        .collect();
    Ok(link(&opts.param, &per_value, opts.identify.match_tol))
}

/// Checks the options a caller built by hand: initial-state ranges finite and ordered, a phase
/// in `[0, 1)`, at least one initial state (the CLI and Python check theirs in their requests).
fn check_options(opts: &ContinuationOptions) -> Result<(), crate::simulate::SimError> {
    let bad = |field: &'static str, value: String, allowed: &'static str| {
        Err(crate::simulate::SimError::Setting {
            field,
            value,
            allowed,
        })
    };
    for (field, (lo, hi)) in [("x0_range", opts.x0_range), ("v0_range", opts.v0_range)] {
        if !(lo.is_finite() && hi.is_finite() && lo <= hi) {
            return bad(
                field,
                format!("({lo}, {hi})"),
                "finite bounds, the first not above the second",
            );
        }
    }
    if !(0.0..1.0).contains(&opts.phase) {
        return bad(
            "phase",
            opts.phase.to_string(),
            "[0, 1) (fraction of the excitation period)",
        );
    }
    if opts.ics == 0 {
        return bad("ics", "0".into(), "at least 1 initial state");
    }
    Ok(())
}

/// Runs the continuation. `done` holds values finished by an interrupted run; `on_done` receives
/// each newly finished value.
pub fn continuation<F>(
    base: &Scenario,
    opts: &ContinuationOptions,
    done: &HashMap<usize, ValueAttractors>,
    on_done: F,
) -> Result<ContinuationResult, ScenarioError>
where
    F: Fn(&ValueAttractors) + Sync,
{
    continuation_dyn(base, opts, done, &on_done)
}

/// [`continuation`], compiled once (not generic over the callback).
fn continuation_dyn(
    base: &Scenario,
    opts: &ContinuationOptions,
    done: &HashMap<usize, ValueAttractors>,
    on_done: &(dyn Fn(&ValueAttractors) + Sync),
) -> Result<ContinuationResult, ScenarioError> {
    let models: Vec<MeshModel> = opts
        .values
        .iter()
        .map(|&v| base.with(&opts.param, v).map(|s| s.model().clone()))
        .collect::<Result<_, _>>()?;
    for (m, v) in models.iter().zip(&opts.values) {
        let t0 = opts.phase * m.excitation_period();
        crate::sweep_settings::check_box(opts.x0_range, opts.v0_range, |y| m.admissible(t0, y))
            .map_err(|reason| ScenarioError::Key {
                key: "x0_range".into(),
                reason: format!("at {} = {v}: {reason}", opts.param),
            })?;
    }
    let per_value: Vec<ValueAttractors> = (0..opts.values.len())
        .into_par_iter()
        .map(|i| {
            if let Some(v) = done.get(&i) {
                return v.clone();
            }
            let r = attractors_at(&models[i], i, opts.values[i], opts);
            // a run cut by a stop request (geardyn_solvers::cancel) is not finished work
            if !geardyn_solvers::cancel::requested() {
                on_done(&r);
            }
            r
        })
        .collect();
    Ok(link(&opts.param, &per_value, opts.identify.match_tol))
}

/// Links the attractors of consecutive values into branches and derives events and intervals.
pub fn link<const N: usize>(
    param: &str,
    per_value: &[ValueAttractors<N>],
    match_tol: f64,
) -> ContinuationResult {
    let mut points = Vec::new();
    let mut events = Vec::new();
    let mut lost = Vec::new();
    let mut next_branch = 0usize;
    let mut prev_branch: Vec<usize> = Vec::new();
    for (j, va) in per_value.iter().enumerate() {
        let branch = if j == 0 {
            let first: Vec<usize> = (next_branch..next_branch + va.attractors.len()).collect();
            next_branch += first.len();
            first
        } else {
            let step = Step::new(&per_value[j - 1], va, &prev_branch);
            let (mut branch, taken_old) = step.continued(match_tol);
            step.appearances(&mut branch, &mut next_branch, &mut events);
            step.losses(&branch, &taken_old, &mut events);
            step.changes(&branch, &mut events);
            branch
        };
        let lost_frac = va.assignment.iter().filter(|&&x| x < 0).count() as f64
            / va.assignment.len().max(1) as f64;
        lost.push((va.value, lost_frac));
        for (a, d) in va.attractors.iter().enumerate() {
            let p0 = d.points.first().map_or([f64::NAN; 2], |p| [p[0], p[1]]);
            points.push(BranchPoint {
                value: va.value,
                branch: branch[a],
                label: d.label.clone(),
                period: d.period,
                healthy: d.healthy,
                fraction: va.fraction(a),
                max_force: d.max_force,
                x: p0[0],
                v: p0[1],
            });
        }
        prev_branch = branch;
    }
    let intervals = intervals(per_value, &points);
    ContinuationResult {
        param: param.to_string(),
        points,
        events,
        intervals,
        lost,
    }
}

/// One step of [`link`]: the attractors `va` of a value against those `pv` of the value before,
/// whose branches are `prev_branch`. A new attractor without a branch has `usize::MAX`.
struct Step<'a, const N: usize> {
    pv: &'a ValueAttractors<N>,
    va: &'a ValueAttractors<N>,
    prev_branch: &'a [usize],
    /// `overlap[a][b]`: initial states that went to old attractor b and now go to a.
    overlap: Vec<Vec<usize>>,
}

impl<'a, const N: usize> Step<'a, N> {
    fn new(
        pv: &'a ValueAttractors<N>,
        va: &'a ValueAttractors<N>,
        prev_branch: &'a [usize],
    ) -> Self {
        let mut overlap = vec![vec![0usize; pv.attractors.len()]; va.attractors.len()];
        for (now, before) in va.assignment.iter().zip(&pv.assignment) {
            if *now >= 0 && *before >= 0 {
                overlap[*now as usize][*before as usize] += 1;
            }
        }
        Step {
            pv,
            va,
            prev_branch,
            overlap,
        }
    }

    /// An event between the two values.
    fn event(&self, kind: &str, branches: Vec<usize>, text: String) -> ContinuationEvent {
        ContinuationEvent {
            from: self.pv.value,
            to: self.va.value,
            kind: kind.into(),
            branches,
            text,
        }
    }

    /// The branch each new attractor continues (`usize::MAX`: none yet) and which old
    /// attractors have a successor; a branch continues at most once.
    fn continued(&self, match_tol: f64) -> (Vec<usize>, Vec<bool>) {
        let (pv, va, prev_branch) = (self.pv, self.va, self.prev_branch);
        let n = va.attractors.len();
        let mut branch = vec![usize::MAX; n];
        // a periodic orbit described at both values (the same label, every point near one
        // of the other) continues its branch whatever the basin overlap: its initial states
        // may all have moved to a neighbouring attractor
        let mut taken_old = vec![false; pv.attractors.len()];
        for a in 0..n {
            let d = &va.attractors[a];
            if d.period == 0 {
                continue;
            }
            if let Some(b) = (0..pv.attractors.len()).find(|&b| {
                let o = &pv.attractors[b];
                !taken_old[b] && o.label == d.label && o.matches(d, 10.0 * match_tol)
            }) {
                branch[a] = prev_branch[b];
                taken_old[b] = true;
            }
        }
        // then greedy by basin overlap, pairs of the same periodic label first (an orbit
        // that kept its label and some of its initial states has not turned into another)
        let mut pairs: Vec<(bool, usize, usize, usize)> = Vec::new();
        for (a, row) in self.overlap.iter().enumerate() {
            for (b, &o) in row.iter().enumerate() {
                if o > 0 {
                    let (d, e) = (&va.attractors[a], &pv.attractors[b]);
                    let same = d.period > 0 && d.label == e.label;
                    pairs.push((same, o, a, b));
                }
            }
        }
        pairs.sort_by(|x, y| {
            y.0.cmp(&x.0)
                .then(y.1.cmp(&x.1))
                .then(x.2.cmp(&y.2))
                .then(x.3.cmp(&y.3))
        });
        for &(_, _, a, b) in &pairs {
            if branch[a] == usize::MAX && !taken_old[b] {
                branch[a] = prev_branch[b];
                taken_old[b] = true;
            }
        }
        // no shared initial state: fall back to descriptor distance
        for a in 0..n {
            if branch[a] == usize::MAX {
                if let Some(b) = (0..pv.attractors.len()).find(|&b| {
                    !taken_old[b] && pv.attractors[b].matches(&va.attractors[a], 10.0 * match_tol)
                }) {
                    branch[a] = prev_branch[b];
                    taken_old[b] = true;
                }
            }
        }
        // last: a periodic attractor left without a branch whose label is that of exactly
        // one old attractor left without a successor (and of no other new one) is that orbit,
        // moved farther than the match tolerance over a coarse step (classic, omega 1.8 ->
        // 2.0: one 3-1-1 orbit had been reported as one branch disappearing and another
        // appearing)
        for a in 0..n {
            let d = &va.attractors[a];
            if branch[a] != usize::MAX || d.period == 0 {
                continue;
            }
            let olds: Vec<usize> = (0..pv.attractors.len())
                .filter(|&b| !taken_old[b] && pv.attractors[b].label == d.label)
                .collect();
            let news = (0..n)
                .filter(|&k| branch[k] == usize::MAX && va.attractors[k].label == d.label)
                .count();
            if let ([b], 1) = (olds.as_slice(), news) {
                branch[a] = prev_branch[*b];
                taken_old[*b] = true;
            }
        }
        (branch, taken_old)
    }

    /// New branches for the attractors left without one, each an appearance (an incomplete
    /// bifurcation while others persist).
    fn appearances(
        &self,
        branch: &mut [usize],
        next_branch: &mut usize,
        events: &mut Vec<ContinuationEvent>,
    ) {
        let persisting = branch.iter().filter(|b| **b != usize::MAX).count();
        for a in 0..branch.len() {
            if branch[a] == usize::MAX {
                branch[a] = *next_branch;
                *next_branch += 1;
                let d = &self.va.attractors[a];
                let kind = if persisting > 0 {
                    "incomplete_bifurcation"
                } else {
                    "appearance"
                };
                events.push(self.event(
                    kind,
                    vec![branch[a]],
                    format!(
                        "{} attractor {} (branch {}) appears{}",
                        crate::simulate::health_text(d.healthy, d.period > 0),
                        d.label,
                        branch[a],
                        if persisting > 0 {
                            " while others persist"
                        } else {
                            ""
                        }
                    ),
                ));
            }
        }
    }

    /// Old attractors without a successor: merged into a chaotic attractor, or disappeared.
    fn losses(&self, branch: &[usize], taken_old: &[bool], events: &mut Vec<ContinuationEvent>) {
        let (pv, va, prev_branch, overlap) = (self.pv, self.va, self.prev_branch, &self.overlap);
        for b in 0..pv.attractors.len() {
            let merged_into: Vec<usize> =
                (0..branch.len()).filter(|&a| overlap[a][b] > 0).collect();
            if !taken_old[b] {
                // merged into another attractor, or disappeared
                let target = merged_into.iter().max_by_key(|&&a| overlap[a][b]).copied();
                match target {
                    Some(a) if va.attractors[a].period == 0 => events.push(self.event(
                        "merger_into_chaos",
                        vec![prev_branch[b], branch[a]],
                        format!(
                            "branch {} ({}) merges into the chaotic attractor of branch {}",
                            prev_branch[b], pv.attractors[b].label, branch[a]
                        ),
                    )),
                    _ => events.push(self.event(
                        "disappearance",
                        vec![prev_branch[b]],
                        format!(
                            "branch {} ({}) disappears",
                            prev_branch[b], pv.attractors[b].label
                        ),
                    )),
                }
            }
        }
    }

    /// Continued branches whose period changed (doubling, to or from chaos, other).
    fn changes(&self, branch: &[usize], events: &mut Vec<ContinuationEvent>) {
        for (a, &br) in branch.iter().enumerate() {
            if let Some(b) = self.prev_branch.iter().position(|&x| x == br) {
                let (old, new) = (&self.pv.attractors[b], &self.va.attractors[a]);
                let kind = match (old.period, new.period) {
                    (p, q) if p > 0 && q == 2 * p => Some("period_doubling"),
                    (p, 0) if p > 0 => Some("transition_to_chaos"),
                    (0, q) if q > 0 => Some("exit_from_chaos"),
                    (p, q) if p != q => Some("period_change"),
                    _ => None,
                };
                if let Some(kind) = kind {
                    events.push(self.event(
                        kind,
                        vec![br],
                        format!("branch {}: {} -> {}", br, old.label, new.label),
                    ));
                }
            }
        }
    }
}

fn intervals<const N: usize>(
    per_value: &[ValueAttractors<N>],
    points: &[BranchPoint],
) -> Vec<Interval> {
    let mut out: Vec<Interval> = Vec::new();
    let mut last_key: Option<Vec<(usize, String)>> = None;
    for va in per_value {
        let here: Vec<&BranchPoint> = points.iter().filter(|p| p.value == va.value).collect();
        let mut key: Vec<(usize, String)> =
            here.iter().map(|p| (p.branch, p.label.clone())).collect();
        key.sort();
        if last_key.as_ref() == Some(&key) {
            let iv = out.last_mut().expect("interval open");
            iv.to = va.value;
            for p in &here {
                let list = if p.healthy {
                    &mut iv.healthy
                } else {
                    &mut iv.non_healthy
                };
                if let Some(e) = list.iter_mut().find(|e| e.0 == p.branch) {
                    e.2 = e.2.min(p.fraction);
                    e.3 = e.3.max(p.fraction);
                }
            }
        } else {
            let mut iv = Interval {
                from: va.value,
                to: va.value,
                healthy: vec![],
                non_healthy: vec![],
            };
            for p in &here {
                let e = (p.branch, p.label.clone(), p.fraction, p.fraction);
                if p.healthy {
                    iv.healthy.push(e);
                } else {
                    iv.non_healthy.push(e);
                }
            }
            out.push(iv);
            last_key = Some(key);
        }
    }
    out
}
