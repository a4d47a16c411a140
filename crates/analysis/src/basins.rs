//! Basins of attraction on a grid of initial states `(x0, x0')` at a given phase (docs/model.md §5).
//!
//! Deterministic for any thread count: cells are processed in passes over nested sub-grids
//! (every 16th cell — every 32nd, 64th, ... on grids larger than 304 x 304 — then every 8th, 4th,
//! 2nd, and all). Within a pass the table of known attractors and the
//! labels of the cells of earlier passes are fixed; cells run in parallel with early capture
//! against the attractors and against the labelled cells (a trajectory landing, at the grid's
//! phase, in a square of the labelled lattice whose corners and neighbours all belong to one
//! attractor, in two consecutive periods: [`CellLabels`]), and new attractors are merged in cell
//! order afterwards, then consolidated (new non-periodic records decided, records of one motion
//! merged: [`crate::attractor::consolidate`]). Attractor ids are finally sorted by a canonical key (healthy first, then
//! period, then position of the first point), so they do not depend on the order of discovery
//! and stay the same under grid refinement. Divergent (`-1`) and failed (`-2`) cells are counted
//! explicitly; fractions, with them, sum to one.

use crate::attractor::{
    assign, consolidate, identify_in, CellLabels, Descriptor, IdentifyOptions, Outcome, Recordable,
};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;

/// A grid axis `MIN:MAX:N`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Axis {
    /// Minimum.
    pub min: f64,
    /// Maximum.
    pub max: f64,
    /// Number of cells.
    pub n: usize,
}

impl Axis {
    /// Cell centre `i`.
    pub fn value(&self, i: usize) -> f64 {
        self.min + (self.max - self.min) * (i as f64 + 0.5) / self.n as f64
    }
}

/// Settings of a basin computation.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct BasinOptions {
    /// Initial displacement axis.
    pub x: Axis,
    /// Initial velocity axis.
    pub v: Axis,
    /// Identification settings (`sim.tau0` sets the phase of the initial states).
    pub identify: IdentifyOptions,
}

/// An attractor with its basin.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BasinAttractor {
    /// Id (index into the table).
    pub id: usize,
    /// Description.
    pub descriptor: Descriptor,
    /// Number of cells.
    pub cells: usize,
    /// Basin fraction.
    pub fraction: f64,
}

/// Basin result.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BasinResult {
    /// Grid.
    pub x: Axis,
    /// Grid.
    pub v: Axis,
    /// Attractor id per cell, row-major with `v` rows (`cells[iv * nx + ix]`); -1 divergent,
    /// -2 failed.
    pub cells: Vec<i64>,
    /// Attractor table.
    pub attractors: Vec<BasinAttractor>,
    /// Fraction of divergent cells.
    pub diverged: f64,
    /// Fraction of failed cells.
    pub failed: f64,
    /// Fraction of cells on a basin boundary (a neighbour belongs to another basin).
    pub boundary_fraction: f64,
    /// Cells captured early.
    pub captured_early: usize,
    /// Excitation periods integrated in all.
    pub periods: u64,
}

/// Most cells of the first pass (every cell of it runs the whole transient and is recorded): its
/// stride is the first of 16, 32, 64, ... that keeps it within this (16 on grids up to 304 x 304).
const FIRST_PASS_CELLS: usize = 361;

fn canonical_order(known: &[Descriptor]) -> Vec<usize> {
    let mut idx: Vec<usize> = (0..known.len()).collect();
    let key = |d: &Descriptor| {
        let p0 = d.points.iter().fold(
            [f64::INFINITY, 0.0],
            |m, p| if p[0] < m[0] { *p } else { m },
        );
        (
            !d.healthy,
            if d.period == 0 { usize::MAX } else { d.period },
            p0[0],
            p0[1],
        )
    };
    idx.sort_by(|&a, &b| {
        let (ka, kb) = (key(&known[a]), key(&known[b]));
        ka.0.cmp(&kb.0)
            .then(ka.1.cmp(&kb.1))
            .then(ka.2.total_cmp(&kb.2))
            .then(ka.3.total_cmp(&kb.3))
    });
    idx
}

/// Computes the basins. `done` holds outcomes of cells finished by an interrupted run (keyed by
/// cell index); `on_cell` receives every newly finished cell. The outcome of a cell depends only
/// on the passes before it, so a resumed run reproduces the uninterrupted one exactly.
///
/// With fixed-step RK4 on the gear model the cells of a pass run in lockstep lanes
/// ([`crate::lanes::identify_lanes`]: the same outcomes as [`identify`](crate::attractor::identify)).
pub fn basins<S, F>(
    model: &S,
    opts: &BasinOptions,
    done: &HashMap<usize, Outcome>,
    on_cell: F,
) -> BasinResult
where
    S: Recordable,
    F: Fn(usize, &Outcome) + Sync,
{
    basins_with(model, opts, done, on_cell, true)
}

/// As [`basins`], every cell integrated by the scalar integrator (for comparisons and
/// benchmarks).
pub fn basins_scalar<S, F>(
    model: &S,
    opts: &BasinOptions,
    done: &HashMap<usize, Outcome>,
    on_cell: F,
) -> BasinResult
where
    S: Recordable,
    F: Fn(usize, &Outcome) + Sync,
{
    basins_with(model, opts, done, on_cell, false)
}

fn basins_with<S, F>(
    model: &S,
    opts: &BasinOptions,
    done: &HashMap<usize, Outcome>,
    on_cell: F,
    lanes: bool,
) -> BasinResult
where
    S: Recordable,
    F: Fn(usize, &Outcome) + Sync,
{
    // a run cut by a stop request (geardyn_solvers::cancel) is not finished work
    let on_cell = |c: usize, o: &Outcome| {
        if !geardyn_solvers::cancel::requested() {
            on_cell(c, o)
        }
    };
    let (nx, nv) = (opts.x.n, opts.v.n);
    let total = nx * nv;
    let mut outcomes: Vec<Option<Outcome>> = vec![None; total];
    let mut known: Vec<Descriptor> = Vec::new();
    let mut assigned: Vec<i64> = vec![i64::MIN; total];
    let mut prev_stride = 0usize;
    // halving the stride from pass to pass: each pass captures by a lattice twice as fine
    let mut first = 16usize;
    while nx.div_ceil(first) * nv.div_ceil(first) > FIRST_PASS_CELLS {
        first *= 2;
    }
    let strides = std::iter::successors(Some(first), |&s| (s > 1).then_some(s / 2));
    for stride in strides {
        let cells: Vec<usize> = (0..total)
            .filter(|&c| outcomes[c].is_none() && (c % nx) % stride == 0 && (c / nx) % stride == 0)
            .collect();
        let snapshot = known.clone();
        // the cells of the earlier passes, as labelled lattice for capture by the grid
        let labels =
            (prev_stride > 0 && opts.identify.early_capture && !snapshot.is_empty()).then(|| {
                CellLabels {
                    x: opts.x,
                    v: opts.v,
                    stride: prev_stride,
                    labels: assigned.clone(),
                }
            });
        prev_stride = stride;
        let mesh = model
            .as_mesh()
            .filter(|_| lanes && crate::lanes::identify_lanes_apply(&opts.identify));
        let fresh: Vec<(usize, Outcome)> = if let Some(mesh) = mesh {
            // fixed-step RK4 on the gear model: the cells of the pass in lockstep lanes (the
            // same reuse rule for saved outcomes as below)
            let reuse = |c: usize| match done.get(&c) {
                Some(Outcome::Captured { id, .. }) if *id >= snapshot.len() => None,
                Some(o) => Some(o.clone()),
                None => None,
            };
            let saved: Vec<Option<Outcome>> = cells.iter().map(|&c| reuse(c)).collect();
            let todo: Vec<(usize, [f64; 2])> = cells
                .iter()
                .zip(&saved)
                .filter(|(_, s)| s.is_none())
                .map(|(&c, _)| (c, [opts.x.value(c % nx), opts.v.value(c / nx)]))
                .collect();
            let y0s: Vec<[f64; 2]> = todo.iter().map(|t| t.1).collect();
            let computed = crate::lanes::identify_lanes_in(
                mesh,
                &y0s,
                &snapshot,
                labels.as_ref(),
                &opts.identify,
                |i, o| on_cell(todo[i].0, o),
            );
            let mut computed = computed.into_iter();
            cells
                .iter()
                .zip(saved)
                .map(|(&c, s)| match s {
                    Some(o) => (c, o),
                    None => (c, computed.next().expect("one outcome per cell")),
                })
                .collect()
        } else {
            cells
                .par_iter()
                .map(|&c| {
                    // a saved outcome is reused only if it can belong to this pass (a capture by an
                    // attractor this pass knows); anything else is recomputed
                    match done.get(&c) {
                        Some(Outcome::Captured { id, .. }) if *id >= snapshot.len() => {}
                        Some(o) => return (c, o.clone()),
                        None => {}
                    }
                    let y0 = [opts.x.value(c % nx), opts.v.value(c / nx)];
                    let o = identify_in(model, y0, &snapshot, labels.as_ref(), &opts.identify);
                    on_cell(c, &o);
                    (c, o)
                })
                .collect()
        };
        let outs: Vec<Outcome> = fresh.iter().map(|(_, o)| o.clone()).collect();
        let first_new = known.len();
        let ids = assign(&mut known, &outs, opts.identify.match_tol);
        for ((c, o), id) in fresh.into_iter().zip(ids) {
            outcomes[c] = Some(o);
            assigned[c] = id;
        }
        consolidate(model, &mut known, first_new, &mut assigned, &opts.identify);
    }
    // canonical ids
    let order = canonical_order(&known);
    let mut remap = vec![0i64; known.len()];
    for (new, &old) in order.iter().enumerate() {
        remap[old] = new as i64;
    }
    let cells: Vec<i64> = assigned
        .iter()
        .map(|&a| if a >= 0 { remap[a as usize] } else { a })
        .collect();
    let mut counts = vec![0usize; known.len()];
    let (mut div, mut fail) = (0usize, 0usize);
    for &c in &cells {
        match c {
            -1 => div += 1,
            -2 => fail += 1,
            i => counts[i as usize] += 1,
        }
    }
    let attractors = order
        .iter()
        .enumerate()
        .map(|(new, &old)| BasinAttractor {
            id: new,
            descriptor: known[old].clone(),
            cells: counts[new],
            fraction: counts[new] as f64 / total as f64,
        })
        .collect();
    let mut boundary = 0usize;
    for iv in 0..nv {
        for ix in 0..nx {
            let c = cells[iv * nx + ix];
            let differs = (ix + 1 < nx && cells[iv * nx + ix + 1] != c)
                || (ix > 0 && cells[iv * nx + ix - 1] != c)
                || (iv + 1 < nv && cells[(iv + 1) * nx + ix] != c)
                || (iv > 0 && cells[(iv - 1) * nx + ix] != c);
            if differs {
                boundary += 1;
            }
        }
    }
    let mut captured_early = 0;
    let mut periods = 0u64;
    for o in outcomes.iter().flatten() {
        match o {
            Outcome::Captured { periods: p, .. } => {
                captured_early += 1;
                periods += p;
            }
            Outcome::Recorded(_) => {
                periods += opts.identify.sim.transient_periods + opts.identify.sim.record_periods
            }
            _ => {}
        }
    }
    BasinResult {
        x: opts.x,
        v: opts.v,
        cells,
        attractors,
        diverged: div as f64 / total as f64,
        failed: fail as f64 / total as f64,
        boundary_fraction: boundary as f64 / total as f64,
        captured_early,
        periods,
    }
}
