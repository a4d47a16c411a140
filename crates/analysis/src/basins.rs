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
//! merged: [`crate::identify::consolidate`]). Attractor ids are finally sorted by a canonical key (healthy first, then
//! period, then position of the first point), so they do not depend on the order of discovery
//! and stay the same under grid refinement. Divergent (`-1`) and failed (`-2`) cells are counted
//! explicitly; fractions, with them, sum to one over the admissible cells. A cell whose initial
//! state is no state of the model (behind the rigid back stop of the impact law:
//! [`geardyn_solvers::HybridSystem::admissible`]) is not integrated: it is marked
//! [`INADMISSIBLE`] (`-3`) and left out of every share, since the model would start it from its
//! projection onto the stop and count that state a second time.

pub use crate::attractor::INADMISSIBLE;
use crate::attractor::{Descriptor, IdentifyOptions, Outcome, Recordable};
use crate::identify::{assign, consolidate, identify_in, CellLabels};
use geardyn_model::MeshModel;
use rayon::prelude::*;
use serde::Serialize;

pub use crate::grid::{Axis, Slice, SliceError};
use std::collections::HashMap;

/// Settings of a basin computation.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct BasinOptions<const N: usize = 2> {
    /// Initial displacement axis (state component [`Slice::axes`]`.0`).
    pub x: Axis,
    /// Initial velocity axis (state component [`Slice::axes`]`.1`).
    pub v: Axis,
    /// Identification settings (`sim.tau0` sets the phase of the initial states).
    pub identify: IdentifyOptions,
    /// The 2-D slice of the state the grid lies in (the pair: its whole state; in the settings
    /// only when it is another).
    #[serde(skip_serializing_if = "Slice::is_default")]
    pub slice: Slice<N>,
}

/// An attractor with its basin.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BasinAttractor<const N: usize = 2> {
    /// Id (index into the table).
    pub id: usize,
    /// Description.
    pub descriptor: Descriptor<N>,
    /// Number of cells.
    pub cells: usize,
    /// Basin fraction (of the admissible cells).
    pub fraction: f64,
}

/// Basin result.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BasinResult<const N: usize = 2> {
    /// Grid.
    pub x: Axis,
    /// Grid.
    pub v: Axis,
    /// Attractor id per cell, row-major with `v` rows (`cells[iv * nx + ix]`); -1 divergent,
    /// -2 failed, -3 ([`INADMISSIBLE`]) no state of the model.
    pub cells: Vec<i64>,
    /// Attractor table.
    pub attractors: Vec<BasinAttractor<N>>,
    /// Fraction of divergent cells (of the admissible cells, as every share).
    pub diverged: f64,
    /// Fraction of failed cells.
    pub failed: f64,
    /// Fraction of the grid's cells that are no state of the model (behind a rigid stop), left
    /// out of every other share.
    pub inadmissible: f64,
    /// Fraction of the admissible cells on a basin boundary (an admissible neighbour belongs to
    /// another basin).
    pub boundary_fraction: f64,
    /// Cells captured early.
    pub captured_early: usize,
    /// Excitation periods integrated in all.
    pub periods: u64,
}

/// Most cells of the first pass (every cell of it runs the whole transient and is recorded): its
/// stride is the first of 16, 32, 64, ... that keeps it within this (16 on grids up to 304 x 304).
const FIRST_PASS_CELLS: usize = 361;

fn canonical_order<const N: usize>(known: &[Descriptor<N>]) -> Vec<usize> {
    let mut idx: Vec<usize> = (0..known.len()).collect();
    let key = |d: &Descriptor<N>| {
        let p0 = d.points.iter().fold([f64::INFINITY, 0.0], |m, p| {
            if p[0] < m[0] {
                [p[0], p[1]]
            } else {
                m
            }
        });
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
/// ([`crate::lanes_identify::identify_lanes`]: the same outcomes as [`identify`](crate::identify::identify)).
pub fn basins<S, F, const N: usize>(
    model: &S,
    opts: &BasinOptions<N>,
    done: &HashMap<usize, Outcome<N>>,
    on_cell: F,
) -> BasinResult<N>
where
    S: Recordable<N>,
    F: Fn(usize, &Outcome<N>) + Sync,
{
    basins_with(model, opts, done, &on_cell, true)
}

/// As [`basins`], every cell integrated by the scalar integrator (for comparisons and
/// benchmarks).
pub fn basins_scalar<S, F, const N: usize>(
    model: &S,
    opts: &BasinOptions<N>,
    done: &HashMap<usize, Outcome<N>>,
    on_cell: F,
) -> BasinResult<N>
where
    S: Recordable<N>,
    F: Fn(usize, &Outcome<N>) + Sync,
{
    basins_with(model, opts, done, &on_cell, false)
}

fn basins_with<S, const N: usize>(
    model: &S,
    opts: &BasinOptions<N>,
    done: &HashMap<usize, Outcome<N>>,
    on_cell: &(dyn Fn(usize, &Outcome<N>) + Sync),
    lanes: bool,
) -> BasinResult<N>
where
    S: Recordable<N>,
{
    // a run cut by a stop request (geardyn_solvers::cancel) is not finished work
    let on_cell = |c: usize, o: &Outcome<N>| {
        if !geardyn_solvers::cancel::requested() {
            on_cell(c, o)
        }
    };
    let (nx, nv) = (opts.x.n, opts.v.n);
    let total = nx * nv;
    let mut outcomes: Vec<Option<Outcome<N>>> = vec![None; total];
    let mut known: Vec<Descriptor<N>> = Vec::new();
    let mut assigned: Vec<i64> = vec![i64::MIN; total];
    let t0 = opts.identify.sim.tau0;
    for c in 0..total {
        let y0 = opts.slice.state(opts.x.value(c % nx), opts.v.value(c / nx));
        if !model.admissible(t0, &y0) {
            outcomes[c] = Some(Outcome::Inadmissible);
            assigned[c] = INADMISSIBLE;
        }
    }
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
        // (a grid of the whole state only: on a slice of a larger state the stroboscopic points
        // leave the plane of the labelled cells)
        let labels =
            (N == 2 && prev_stride > 0 && opts.identify.early_capture && !snapshot.is_empty())
                .then(|| CellLabels {
                    x: opts.x,
                    v: opts.v,
                    stride: prev_stride,
                    labels: assigned.clone(),
                });
        prev_stride = stride;
        let pass = Pass {
            opts,
            done,
            cells: &cells,
            snapshot: &snapshot,
            labels: labels.as_ref(),
        };
        let mesh = model
            .as_mesh()
            .filter(|_| lanes && opts.slice == Slice::default())
            .zip(crate::lanes_identify::LaneIdentify::new(&opts.identify));
        let fresh = match mesh {
            Some((mesh, lane)) => pass.run_lanes(mesh, lane, &on_cell),
            None => pass.run_scalar(model, &on_cell),
        };
        let outs: Vec<Outcome<N>> = fresh.iter().map(|(_, o)| o.clone()).collect();
        let first_new = known.len();
        let ids = assign(&mut known, &outs, opts.identify.match_tol);
        for ((c, o), id) in fresh.into_iter().zip(ids) {
            outcomes[c] = Some(o);
            assigned[c] = id;
        }
        consolidate(model, &mut known, first_new, &mut assigned, &opts.identify);
    }
    tally(opts, &known, &assigned, &outcomes)
}

/// One pass over a sub-grid: its cells, the attractors and labelled cells it captures by.
struct Pass<'a, const N: usize> {
    opts: &'a BasinOptions<N>,
    done: &'a HashMap<usize, Outcome<N>>,
    cells: &'a [usize],
    snapshot: &'a [Descriptor<N>],
    labels: Option<&'a CellLabels>,
}

impl<const N: usize> Pass<'_, N> {
    /// A saved outcome is reused only if it can belong to this pass (a capture by an attractor
    /// this pass knows); anything else is recomputed.
    fn saved(&self, c: usize) -> Option<Outcome<N>> {
        match self.done.get(&c) {
            Some(Outcome::Captured { id, .. }) if *id >= self.snapshot.len() => None,
            Some(o) => Some(o.clone()),
            None => None,
        }
    }

    /// Fixed-step RK4 on the gear model: the cells of the pass in lockstep lanes.
    fn run_lanes(
        &self,
        mesh: &MeshModel,
        lane: crate::lanes_identify::LaneIdentify<'_>,
        on_cell: &(dyn Fn(usize, &Outcome<N>) + Sync),
    ) -> Vec<(usize, Outcome<N>)> {
        let (opts, nx) = (self.opts, self.opts.x.n);
        let saved: Vec<Option<Outcome<N>>> = self.cells.iter().map(|&c| self.saved(c)).collect();
        let todo: Vec<(usize, [f64; 2])> = self
            .cells
            .iter()
            .zip(&saved)
            .filter(|(_, s)| s.is_none())
            .map(|(&c, _)| (c, [opts.x.value(c % nx), opts.v.value(c / nx)]))
            .collect();
        let y0s: Vec<[f64; 2]> = todo.iter().map(|t| t.1).collect();
        // (the pair's lanes speak its own dimension: N = 2 here)
        let pair_snapshot: Vec<Descriptor> =
            self.snapshot.iter().map(|d| d.clone().resized()).collect();
        let computed = crate::lanes_identify::identify_lanes(
            mesh,
            &y0s,
            &pair_snapshot,
            self.labels,
            lane,
            |i, o| on_cell(todo[i].0, &o.clone().resized()),
        );
        let mut computed = computed.into_iter().map(Outcome::resized);
        self.cells
            .iter()
            .zip(saved)
            .map(|(&c, s)| match s {
                Some(o) => (c, o),
                None => (c, computed.next().expect("one outcome per cell")),
            })
            .collect()
    }

    /// Any model: every cell of the pass by the scalar integrator, in parallel.
    fn run_scalar<S: Recordable<N>>(
        &self,
        model: &S,
        on_cell: &(dyn Fn(usize, &Outcome<N>) + Sync),
    ) -> Vec<(usize, Outcome<N>)> {
        let (opts, nx) = (self.opts, self.opts.x.n);
        self.cells
            .par_iter()
            .map(|&c| {
                if let Some(o) = self.saved(c) {
                    return (c, o);
                }
                let y0 = opts.slice.state(opts.x.value(c % nx), opts.v.value(c / nx));
                let o = identify_in(model, y0, self.snapshot, self.labels, &opts.identify);
                on_cell(c, &o);
                (c, o)
            })
            .collect()
    }
}

/// The result of the passes: canonical ids, basin sizes, boundary and effort.
fn tally<const N: usize>(
    opts: &BasinOptions<N>,
    known: &[Descriptor<N>],
    assigned: &[i64],
    outcomes: &[Option<Outcome<N>>],
) -> BasinResult<N> {
    let (nx, nv) = (opts.x.n, opts.v.n);
    let total = nx * nv;
    // canonical ids
    let order = canonical_order(known);
    let mut remap = vec![0i64; known.len()];
    for (new, &old) in order.iter().enumerate() {
        remap[old] = new as i64;
    }
    let cells: Vec<i64> = assigned
        .iter()
        .map(|&a| if a >= 0 { remap[a as usize] } else { a })
        .collect();
    let mut counts = vec![0usize; known.len()];
    let (mut div, mut fail, mut out) = (0usize, 0usize, 0usize);
    for &c in &cells {
        match c {
            -1 => div += 1,
            -2 => fail += 1,
            INADMISSIBLE => out += 1,
            i => counts[i as usize] += 1,
        }
    }
    // shares of the admissible cells (a grid wholly behind the stop: all shares 0)
    let admissible = (total - out).max(1) as f64;
    let attractors = order
        .iter()
        .enumerate()
        .map(|(new, &old)| BasinAttractor {
            id: new,
            descriptor: known[old].clone(),
            cells: counts[new],
            fraction: counts[new] as f64 / admissible,
        })
        .collect();
    let boundary = boundary_cells(&cells, nx, nv);
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
        diverged: div as f64 / admissible,
        failed: fail as f64 / admissible,
        inadmissible: out as f64 / total.max(1) as f64,
        boundary_fraction: boundary as f64 / admissible,
        captured_early,
        periods,
    }
}

/// Admissible cells with an admissible neighbour (left, right, above, below) in another basin
/// (the edge of a rigid stop is no basin boundary).
fn boundary_cells(cells: &[i64], nx: usize, nv: usize) -> usize {
    let mut boundary = 0usize;
    for iv in 0..nv {
        for ix in 0..nx {
            let c = cells[iv * nx + ix];
            let other = |n: i64| n != c && n != INADMISSIBLE;
            let differs = c != INADMISSIBLE
                && ((ix + 1 < nx && other(cells[iv * nx + ix + 1]))
                    || (ix > 0 && other(cells[iv * nx + ix - 1]))
                    || (iv + 1 < nv && other(cells[(iv + 1) * nx + ix]))
                    || (iv > 0 && other(cells[(iv - 1) * nx + ix])));
            if differs {
                boundary += 1;
            }
        }
    }
    boundary
}

/// A basin grid as a caller states it (`geardyn basins --grid x:MIN:MAX:N --grid v:... --phase`,
/// Python's `basins(x=, v=, phase=)`), before it is checked: the defaults and limits of the two
/// axes and of the phase live here, and [`BasinsRequest::options`] turns it into the
/// [`BasinOptions`] of a model.
///
/// ```
/// use geardyn_analysis::basins::BasinsRequest;
/// let r = BasinsRequest { x: Some((-1.0, 1.0, 50)), ..Default::default() };
/// let (x, v) = r.axes(0.5).unwrap();
/// assert_eq!((x.min, x.max, x.n), (-1.0, 1.0, 50));
/// assert_eq!((v.min, v.max, v.n), (-1.5, 1.5, 200)); // the default velocity axis
/// let bad = BasinsRequest { v: Some((1.0, -1.0, 10)), ..Default::default() };
/// assert!(bad.axes(0.5).unwrap_err().to_string().contains("v axis"));
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BasinsRequest {
    /// Initial displacement axis `(MIN, MAX, N)` (dimensionless, in length scales); `None`:
    /// `±`[`BasinsRequest::DEFAULT_X_HALF_BACKLASHES`] half backlashes, [`BasinsRequest::DEFAULT_CELLS`] cells.
    pub x: Option<(f64, f64, usize)>,
    /// Initial velocity axis `(MIN, MAX, N)` (dimensionless); `None`:
    /// `±`[`BasinsRequest::DEFAULT_V`], [`BasinsRequest::DEFAULT_CELLS`] cells.
    pub v: Option<(f64, f64, usize)>,
    /// Phase of the initial states as a fraction of the excitation period, in `[0, 1)`.
    pub phase: f64,
}

/// Why a basin grid was refused.
#[derive(Debug, thiserror::Error)]
pub enum BasinsRequestError {
    /// An axis out of its limits.
    #[error("bad {axis} axis ({min}, {max}, {n}): MIN < MAX within ±{lim} (initial states in length scales and their rates) and 1 <= N <= {cells}", lim = BasinsRequest::MAX_ABS, cells = BasinsRequest::MAX_CELLS, min = geardyn_model::error::num(*.min), max = geardyn_model::error::num(*.max))]
    Axis {
        /// `x` or `v`.
        axis: &'static str,
        /// Given minimum.
        min: f64,
        /// Given maximum.
        max: f64,
        /// Given count.
        n: usize,
    },
    /// The phase out of `[0, 1)`.
    #[error(transparent)]
    Phase(#[from] crate::attractor::PhaseError),
}

impl BasinsRequest {
    /// Cells per axis by default.
    pub const DEFAULT_CELLS: usize = 200;
    /// Half width of the default displacement axis, in half backlashes: it covers both tooth
    /// flanks and the impacting motions that reach past them.
    pub const DEFAULT_X_HALF_BACKLASHES: f64 = 2.0;
    /// Half width of the default velocity axis (dimensionless).
    pub const DEFAULT_V: f64 = 1.5;
    /// Most cells per axis.
    pub const MAX_CELLS: usize = 4000;
    /// Largest |MIN| and |MAX| of an axis.
    pub const MAX_ABS: f64 = 1e3;

    /// The two axes for a pair of half backlash `d` (the default displacement axis scales with
    /// it), checked.
    pub fn axes(&self, d: f64) -> Result<(Axis, Axis), BasinsRequestError> {
        let hx = Self::DEFAULT_X_HALF_BACKLASHES * d;
        let x = self.x.unwrap_or((-hx, hx, Self::DEFAULT_CELLS));
        let v = self
            .v
            .unwrap_or((-Self::DEFAULT_V, Self::DEFAULT_V, Self::DEFAULT_CELLS));
        Ok((Self::axis("x", x)?, Self::axis("v", v)?))
    }

    fn axis(
        axis: &'static str,
        (min, max, n): (f64, f64, usize),
    ) -> Result<Axis, BasinsRequestError> {
        let ok = min.is_finite()
            && max.is_finite()
            && min < max
            && min.abs() <= Self::MAX_ABS
            && max.abs() <= Self::MAX_ABS
            && (1..=Self::MAX_CELLS).contains(&n);
        if ok {
            Ok(Axis { min, max, n })
        } else {
            Err(BasinsRequestError::Axis { axis, min, max, n })
        }
    }

    /// The basin options on `model` with identification settings `identify` (the phase sets the
    /// start time of every cell; the default displacement axis is that of its half backlash
    /// `d_single`). Checks the phase, then the axes.
    pub fn options(
        &self,
        model: &geardyn_model::MeshModel,
        mut identify: IdentifyOptions,
    ) -> Result<BasinOptions, BasinsRequestError> {
        let phase = crate::attractor::check_phase(self.phase)?;
        let (x, v) = self.axes(model.params().d_single)?;
        identify.sim.tau0 = phase * model.excitation_period();
        Ok(BasinOptions {
            x,
            v,
            identify,
            slice: Slice::default(),
        })
    }
}
