//! Identifying the attractor a trajectory reaches (docs/model.md §5): a run integrated period by
//! period and captured early by a known periodic attractor (or by the labelled cells of a basin
//! grid), else recorded and described ([`identify`], [`identify_in`]); the new descriptors merged
//! into the known attractors ([`assign`]) and made one attractor per motion ([`consolidate`]:
//! decided, merged by their recurrent sets, non-periodic ones followed to confirm that they
//! persist). What a descriptor is and when two match: [`crate::attractor`].

use crate::attractor::{dist, Descriptor, IdentifyOptions, Outcome, Recordable, INADMISSIBLE};
use crate::driver::{run_periods, Discard, Observer};
use crate::simulate::SimOptions;
use geardyn_solvers::{HybridSystem, Integrator};

/// Makes one attractor of one motion (see module doc): decides the descriptors from
/// `first_new` on ([`Recordable::decide`]), merges matching
/// descriptors of `known` (the earliest index survives) and renumbers `ids` (entries `< 0` are
/// left alone). Deterministic: sequential, in index order.
pub fn consolidate<S: Recordable<N>, const N: usize>(
    sys: &S,
    known: &mut Vec<Descriptor<N>>,
    first_new: usize,
    ids: &mut [i64],
    opts: &IdentifyOptions,
) {
    for d in known.iter_mut().skip(first_new) {
        // every new attractor is decided as `simulate` decides a run: a non-periodic record, and
        // a periodic one too, whose record may still be the slow approach to an orbit of a lower
        // period (a decaying flip mode read as a doubled period: the internal pair at
        // omega = 0.7 had shown 99.94 % of its basin as a period-4 "attractor" beside the
        // period-2 orbit it was approaching) or hold the end of the approach (forces and health
        // of the transient: the broken pair at omega = 1.43 had listed its healthy period-1
        // motion also as "non-healthy, max force 1.49")
        *d = sys.decide(d, &opts.sim);
    }
    merge_all(known, ids, opts.match_tol);
    // an attractor persists: a non-periodic one is followed for PERSIST_FACTOR transients more,
    // and if it lands on a periodic orbit it was transient chaos (long chaotic transients are
    // common near crises); the cells that reached it go to that orbit
    loop {
        let periodic: Vec<Descriptor<N>> = known.iter().filter(|d| d.period > 0).cloned().collect();
        let mut changed = false;
        for d in known.iter_mut() {
            if d.period > 0 || d.persistence_checked {
                continue;
            }
            d.persistence_checked = true;
            let Some(&y0) = d.points.last() else { continue };
            let follow = IdentifyOptions {
                sim: SimOptions {
                    transient_periods: PERSIST_FACTOR * opts.sim.transient_periods.max(100),
                    ..opts.sim
                },
                early_capture: true,
                ..*opts
            };
            match identify(sys, y0, &periodic, &follow) {
                Outcome::Captured { id, .. } => {
                    *d = periodic[id].clone();
                    changed = true;
                }
                Outcome::Recorded(r) if r.period > 0 => {
                    *d = r;
                    changed = true;
                }
                Outcome::Recorded(r) if !r.points.is_empty() => {
                    // still not periodic: where it is now (a chaotic transient has reached the
                    // attractor it feeds, and merges with it; a persistent one stays itself)
                    d.bbox = r.bbox;
                    d.points = r.points;
                    changed = true;
                }
                _ => {}
            }
        }
        if !changed {
            break;
        }
        merge_all(known, ids, opts.match_tol);
    }
}

/// Transients (of the identification's length, at least 100 periods) a non-periodic attractor is
/// followed to confirm that it persists.
pub const PERSIST_FACTOR: u64 = 10;

/// Merges matching descriptors of `known` transitively (the earliest index survives) and
/// renumbers `ids`.
fn merge_all<const N: usize>(known: &mut Vec<Descriptor<N>>, ids: &mut [i64], match_tol: f64) {
    // union-find over the table, earliest index as the root
    let n = known.len();
    let mut root: Vec<usize> = (0..n).collect();
    fn find(root: &mut [usize], mut i: usize) -> usize {
        while root[i] != i {
            root[i] = root[root[i]];
            i = root[i];
        }
        i
    }
    // until nothing merges: a grown cloud may now reach a descriptor it missed before
    let mut merged = true;
    while merged {
        merged = false;
        for j in 1..n {
            for i in 0..j {
                let (ri, rj) = (find(&mut root, i), find(&mut root, j));
                if ri != rj && known[ri].matches(&known[rj], match_tol) {
                    let (lo, hi) = (ri.min(rj), ri.max(rj));
                    let other = known[hi].clone();
                    known[lo].absorb(&other);
                    root[hi] = lo;
                    merged = true;
                }
            }
        }
    }
    let mut remap = vec![0i64; n];
    let mut kept = Vec::new();
    for i in 0..n {
        if find(&mut root, i) == i {
            remap[i] = kept.len() as i64;
            kept.push(known[i].clone());
        }
    }
    for i in 0..n {
        remap[i] = remap[find(&mut root, i)];
    }
    for id in ids.iter_mut() {
        if *id >= 0 {
            *id = remap[*id as usize];
        }
    }
    *known = kept;
}

/// Labels of the cells of a basin grid finished in earlier passes, for capture by the grid
/// ("cell capture"): a trajectory whose stroboscopic point (at the phase of the grid's initial
/// states) lands inside the square of labelled cell centres whose corners and ring of neighbours
/// ([`CellLabels::RING`]) all carry attractor `k`, in [`CellLabels::HITS`] consecutive periods,
/// goes to `k` — the basin is uniform there at the resolution of the labelled lattice, so only a
/// trajectory passing within a lattice spacing of a basin boundary can be misjudged, and such a
/// trajectory starts next to a boundary (the boundary is invariant under the map).
#[derive(Clone, Debug)]
pub struct CellLabels {
    /// `x` axis of the grid.
    pub x: crate::grid::Axis,
    /// `v` axis of the grid.
    pub v: crate::grid::Axis,
    /// Spacing (in cells) of the labelled lattice: cells `(ix, iv)` with `ix % stride == 0` and
    /// `iv % stride == 0` are labelled.
    pub stride: usize,
    /// Attractor id per cell (`labels[iv * nx + ix]`); negative: not an attractor (divergent,
    /// failed, not yet computed).
    pub labels: Vec<i64>,
}

impl CellLabels {
    /// Lattice nodes around the square that must agree, on each side (0: the four corners only).
    pub const RING: usize = 1;
    /// Consecutive periods a trajectory must land in uniform squares of one attractor.
    pub const HITS: u32 = 2;

    /// The attractor of the uniform labelled square holding `y`, if there is one.
    pub fn lookup(&self, y: &[f64; 2]) -> Option<usize> {
        let s = self.stride.max(1) as f64;
        let node = |a: &crate::grid::Axis, u: f64| -> Option<(usize, usize)> {
            // fractional cell index (centres at integers), in lattice units
            let f = ((u - a.min) / (a.max - a.min) * a.n as f64 - 0.5) / s;
            if !f.is_finite() || f < 0.0 {
                return None;
            }
            let i = f.floor() as usize;
            let (lo, hi) = (i.checked_sub(Self::RING)?, i + 1 + Self::RING);
            // the last node of the lattice is (n - 1) / stride
            (hi <= (a.n - 1) / self.stride.max(1)).then_some((lo, hi))
        };
        let (x0, x1) = node(&self.x, y[0])?;
        let (v0, v1) = node(&self.v, y[1])?;
        let st = self.stride.max(1);
        let first = self.labels[v0 * st * self.x.n + x0 * st];
        if first < 0 {
            return None;
        }
        for iv in v0..=v1 {
            for ix in x0..=x1 {
                if self.labels[iv * st * self.x.n + ix * st] != first {
                    return None;
                }
            }
        }
        Some(first as usize)
    }
}

pub(crate) struct Capture<'a, const N: usize = 2> {
    pub(crate) known: &'a [Descriptor<N>],
    pub(crate) tol: f64,
    pub(crate) divergence: f64,
    /// per known periodic attractor: (consecutive matches, phase index, last distance)
    pub(crate) state: Vec<(usize, usize, f64)>,
    pub(crate) captured: Option<usize>,
    pub(crate) diverged: bool,
    /// Labels of finished cells, and the run of consecutive uniform squares (attractor, count).
    pub(crate) cells: Option<&'a CellLabels>,
    pub(crate) cell_run: (usize, u32),
}

impl<'a, const N: usize> Capture<'a, N> {
    pub(crate) fn new(
        known: &'a [Descriptor<N>],
        cells: Option<&'a CellLabels>,
        opts: &IdentifyOptions,
    ) -> Self {
        Capture {
            known,
            tol: opts.capture_tol,
            divergence: opts.divergence,
            state: vec![(0, 0, f64::INFINITY); known.len()],
            captured: None,
            diverged: false,
            cells,
            cell_run: (0, 0),
        }
    }
}

/// Whether every component of `y` is below `divergence` in magnitude (NaN is not).
fn bounded<const N: usize>(y: &[f64; N], divergence: f64) -> bool {
    y.iter().all(|v| v.abs() < divergence)
}

impl<S: HybridSystem<N>, const N: usize> Observer<S, N> for Capture<'_, N> {
    fn on_strobe(&mut self, _t: f64, y: &[f64; N]) {
        if !bounded(y, self.divergence) {
            self.diverged = true;
            return;
        }
        for (k, a) in self.known.iter().enumerate() {
            let n = a.period;
            if n == 0 || self.captured.is_some() {
                continue;
            }
            let (run, phase, last) = self.state[k];
            let (next_run, next_phase, d) = if run == 0 {
                // look for the nearest point of the orbit
                match a
                    .points
                    .iter()
                    .enumerate()
                    .map(|(i, p)| (i, dist(y, p)))
                    .min_by(|x, y| x.1.total_cmp(&y.1))
                {
                    Some((i, d)) if d <= self.tol => (1, (i + 1) % n, d),
                    _ => (0, 0, f64::INFINITY),
                }
            } else {
                let d = dist(y, &a.points[phase]);
                if d <= self.tol {
                    (run + 1, (phase + 1) % n, d)
                } else {
                    (0, 0, f64::INFINITY)
                }
            };
            self.state[k] = (next_run, next_phase, d);
            if next_run >= 2 * n && d <= last * 1.5 + 1e-14 {
                self.captured = Some(k);
            }
        }
        if self.captured.is_some() {
            return;
        }
        // (labelled cells are a plane of the state: the pair's whole state)
        if let Some(cells) = self.cells.filter(|_| N == 2) {
            self.cell_run = match cells.lookup(&[y[0], y[1]]) {
                Some(k) if k < self.known.len() => {
                    let run = if self.cell_run.0 == k {
                        self.cell_run.1 + 1
                    } else {
                        1
                    };
                    if run >= CellLabels::HITS {
                        self.captured = Some(k);
                    }
                    (k, run)
                }
                _ => (0, 0),
            };
        }
    }
}

/// Integrates from `y0` and identifies the attractor reached (see module doc). `known` are the
/// attractors found so far; the system is borrowed, not cloned.
pub fn identify<S: Recordable<N>, const N: usize>(
    sys: &S,
    y0: [f64; N],
    known: &[Descriptor<N>],
    opts: &IdentifyOptions,
) -> Outcome<N> {
    identify_in(sys, y0, known, None, opts)
}

/// As [`identify`], also captured by the labelled cells of a basin grid (see [`CellLabels`];
/// early capture must be on). `cells` labels are ids into `known`.
pub fn identify_in<S: Recordable<N>, const N: usize>(
    sys: &S,
    y0: [f64; N],
    known: &[Descriptor<N>],
    cells: Option<&CellLabels>,
    opts: &IdentifyOptions,
) -> Outcome<N> {
    let run = || -> Result<Outcome<N>, crate::simulate::SimError> {
        let mut it = Integrator::new(sys, sys.scheme(&opts.sim), opts.sim.tau0, y0)?;
        let period = sys.strobe_period();
        let mut cap = Capture::new(known, cells, opts);
        let mut done = 0u64;
        while done < opts.sim.transient_periods {
            if opts.early_capture && !known.is_empty() {
                run_periods(&mut it, period, 1, &mut cap)?;
            } else {
                let chunk = opts.sim.transient_periods - done;
                run_periods(&mut it, period, chunk, &mut Discard)?;
                done += chunk;
                continue;
            }
            done += 1;
            if cap.diverged {
                return Ok(Outcome::Diverged);
            }
            if let Some(id) = cap.captured {
                return Ok(Outcome::Captured { id, periods: done });
            }
        }
        let y = *it.y();
        if !bounded(&y, opts.divergence) {
            return Ok(Outcome::Diverged);
        }
        // the record continues the run (an impact in progress keeps its hysteresis)
        let sim = SimOptions {
            start_memory: sys.memory(it.mode()),
            ..opts.sim
        };
        Ok(Outcome::Recorded(sys.describe(it.t(), y, &sim)?))
    };
    match run() {
        Ok(o) => o,
        Err(e) => Outcome::Failed(e.to_string()),
    }
}

/// Merges the new descriptors of `outcomes` (in order) into `known`, returning for each outcome
/// its attractor index, or `-1` (diverged) / `-2` (failed).
pub fn assign<const N: usize>(
    known: &mut Vec<Descriptor<N>>,
    outcomes: &[Outcome<N>],
    match_tol: f64,
) -> Vec<i64> {
    outcomes
        .iter()
        .map(|o| match o {
            Outcome::Captured { id, .. } => *id as i64,
            Outcome::Recorded(d) => match known.iter().position(|k| k.matches(d, match_tol)) {
                Some(i) => i as i64,
                None => {
                    known.push(d.clone());
                    (known.len() - 1) as i64
                }
            },
            Outcome::Diverged => -1,
            Outcome::Failed(_) => -2,
            Outcome::Inadmissible => INADMISSIBLE,
        })
        .collect()
}
