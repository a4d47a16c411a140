//! Automatic attractor identification on the stroboscopic section (docs/model.md §5).
//!
//! A trajectory is integrated period by period. After every period its stroboscopic point is
//! compared with the known periodic attractors: when `2n` consecutive points (n = the attractor's
//! period) each lie within `capture_tol` of the attractor's points, in cyclic order, and the
//! distance has not grown over the last period, the run stops early and is assigned to that
//! attractor. This is a strong (not a formal) proof of convergence: the orbit is stable (it was
//! found as an attractor) and the trajectory sits in a contracting neighbourhood of it; the
//! tolerance (default 1e-4 of the state scale) is far below typical basin sizes.
//! Otherwise, after `max_transient` periods, `record` periods are recorded and summarised into a
//! [`Descriptor`] (period, `n-p-q-r-s` label, healthy flag, section points, bounding box).
//!
//! # One motion, one attractor
//!
//! Recorded descriptors are merged into attractors by their recurrent sets, never by statistics
//! of their crossings (a chaotic record of 64 periods may happen to hold no back-side contact):
//!
//! - **periodic / periodic**: the same period and every point of one within `match_tol` of a
//!   point of the other (`match_tol` = 10 × the capture tolerance, far above the integrator's
//!   error at the identification tolerance and far below the distance between coexisting
//!   orbits);
//! - **not periodic / periodic**: the last points of the non-periodic record all lie within
//!   `match_tol` of the periodic orbit (a slow transient that had nearly arrived);
//! - **not periodic / not periodic**: at least [`CONTAINED`] of the points of one record lie near
//!   a point of the other (the stroboscopic map is invertible, so two distinct attractors are
//!   disjoint sets: one cloud sitting on another is one attractor seen over two records). "Near"
//!   is [`NEAR`] × the diagonal of the two clouds' joint bounding box, or [`NN_FACTOR`] × the
//!   clouds' own spacing (the larger of their median nearest-neighbour distances) where that is
//!   more: a cloud of at most [`MAX_CLOUD`] points on an attractor of a higher-dimensional
//!   state (a planetary stage's chaotic section) is sparse, its points farther apart than a
//!   fixed share of its size, and two records of one attractor then interleave at their own
//!   spacing, not closer.
//!
//! [`consolidate`](crate::identify::consolidate) first decides every new non-periodic descriptor (the gear model: the decided
//! classification of `crate::classify` continued from a point of the record, so a slowly settling
//! orbit is given its period and a chaotic one its Lyapunov exponent), then merges matching
//! descriptors (transitively) and renumbers the assignments. Merged chaotic clouds keep the
//! union of their points, so later records are compared with the whole attractor.

use crate::classify::{simulate_decided, Decide, Motion};
use crate::driver::{run_periods, Observer};
use crate::engine::Engine;
use crate::period::minimal_period;
use crate::simulate::{simulate, summarize, SimError, SimOptions};
use geardyn_model::MeshModel;
use geardyn_solvers::{EventAction, Guards, HybridSystem, Integrator, Scheme};
use serde::{Deserialize, Serialize};

/// A system whose attractors can be identified: an `N`-dimensional [`HybridSystem`] with a
/// stroboscopic period and a way to record and describe a steady state. A gear system records
/// labels, P_ID and forces ([`describe_gear`], [`decide_gear`]: the pair, the toy, a system of
/// your own with a one-line impl); [`StrobeOnly`] describes any system by its stroboscopic points.
pub trait Recordable<const N: usize>: HybridSystem<N> + Sync {
    /// Stroboscopic period.
    fn strobe_period(&self) -> f64;
    /// Integration scheme for these settings.
    fn scheme(&self, sim: &SimOptions) -> Scheme;
    /// Records `sim.record_periods` periods from `(t0, y0)` and describes the steady state.
    fn describe(&self, t0: f64, y0: [f64; N], sim: &SimOptions) -> Result<Descriptor<N>, SimError>;
    /// The gear model, when the system is one (its cells can then run in lockstep lanes,
    /// [`crate::lanes`]). Default: none.
    fn as_mesh(&self) -> Option<&MeshModel> {
        None
    }
    /// Decides the motion of a descriptor (non-periodic, or periodic with a record that may
    /// still hold an approach): continues from one of its points and returns the decided
    /// description (it may turn out periodic, or of a lower period, after a longer transient).
    /// Default: the descriptor as it is.
    fn decide(&self, d: &Descriptor<N>, _sim: &SimOptions) -> Descriptor<N> {
        d.clone()
    }
}

/// [`Recordable::decide`] of a gear system: the decided classification of [`simulate_decided`]
/// continued from the last point of the record (it may turn out periodic, or of a lower period,
/// after a longer transient).
pub fn decide_gear<S: Engine<N>, const N: usize>(
    sys: &S,
    d: &Descriptor<N>,
    sim: &SimOptions,
) -> Descriptor<N> {
    let Some(&y0) = d.points.last() else {
        return d.clone();
    };
    // a point of the stroboscopic record: its time is tau0 plus whole excitation periods
    let opts = SimOptions {
        transient_periods: 0,
        record_periods: sim.record_periods.max(DECIDE_RECORD),
        trajectory: false,
        ..*sim
    };
    match simulate_decided(sys, y0, &opts, Decide::default()) {
        Ok((res, s, _)) => {
            let pts = res.strobe_states();
            let mut out = Descriptor::new(s.period, s.label, s.healthy, &pts, s.max_force, s.p_id);
            out.motion = s.motion;
            out.mesh_period = s.mesh_period;
            out
        }
        Err(_) => d.clone(),
    }
}

/// [`Recordable::describe`] of a gear system: [`simulate`] and [`summarize`] of the record.
pub fn describe_gear<S: Engine<N>, const N: usize>(
    sys: &S,
    t0: f64,
    y0: [f64; N],
    sim: &SimOptions,
) -> Result<Descriptor<N>, SimError> {
    let rec_opts = SimOptions {
        transient_periods: 0,
        tau0: t0,
        ..*sim
    };
    let res = simulate(sys, y0, &rec_opts)?;
    let s = summarize(sys, &res, &rec_opts);
    let pts = res.strobe_states();
    let mut d = Descriptor::new(s.period, s.label, s.healthy, &pts, s.max_force, s.p_id);
    d.motion = s.motion;
    d.mesh_period = s.mesh_period;
    Ok(d)
}

/// The toy gear system of the tests and examples, identified as any gear system.
impl Recordable<4> for geardyn_model::reference::TwoMassClearance {
    fn strobe_period(&self) -> f64 {
        geardyn_model::GearSystem::excitation_period(self)
    }
    fn scheme(&self, sim: &SimOptions) -> Scheme {
        sim.method.scheme(self)
    }
    fn decide(&self, d: &Descriptor<4>, sim: &SimOptions) -> Descriptor<4> {
        decide_gear(self, d, sim)
    }
    fn describe(&self, t0: f64, y0: [f64; 4], sim: &SimOptions) -> Result<Descriptor<4>, SimError> {
        describe_gear(self, t0, y0, sim)
    }
}

/// A gear train's dynamic model, identified as any gear system (basins on a slice of its state,
/// attractor continuation).
impl<const N: usize> Recordable<N> for geardyn_train::dynamics::TrainModel<N>
where
    geardyn_train::dynamics::TrainModel<N>: Engine<N>,
{
    fn strobe_period(&self) -> f64 {
        geardyn_model::GearSystem::excitation_period(self)
    }
    fn scheme(&self, sim: &SimOptions) -> Scheme {
        sim.method.scheme(self)
    }
    fn decide(&self, d: &Descriptor<N>, sim: &SimOptions) -> Descriptor<N> {
        decide_gear(self, d, sim)
    }
    fn describe(&self, t0: f64, y0: [f64; N], sim: &SimOptions) -> Result<Descriptor<N>, SimError> {
        describe_gear(self, t0, y0, sim)
    }
}

impl Recordable<2> for MeshModel {
    fn as_mesh(&self) -> Option<&MeshModel> {
        Some(self)
    }
    fn strobe_period(&self) -> f64 {
        self.excitation_period()
    }
    fn scheme(&self, sim: &SimOptions) -> Scheme {
        sim.method.scheme(self)
    }
    fn decide(&self, d: &Descriptor, sim: &SimOptions) -> Descriptor {
        decide_gear(self, d, sim)
    }
    fn describe(&self, t0: f64, y0: [f64; 2], sim: &SimOptions) -> Result<Descriptor, SimError> {
        describe_gear(self, t0, y0, sim)
    }
}

/// Any system described by its stroboscopic points alone (label `P<n>` or `chaotic`; "healthy" =
/// periodic).
pub struct StrobeOnly<S> {
    /// The system.
    pub sys: S,
    /// Stroboscopic period.
    pub period: f64,
    /// Integration scheme.
    pub scheme: Scheme,
}

impl<S: HybridSystem<N>, const N: usize> HybridSystem<N> for StrobeOnly<S> {
    type Mode = S::Mode;
    type TimeTerms = S::TimeTerms;
    geardyn_solvers::forward_methods! { to field sys;
        fn initial_mode(&self, t: f64, y: &mut [f64; N]) -> S::Mode;
        fn time_terms(&self, t: f64) -> S::TimeTerms;
        fn rhs(&self, t: f64, tt: &S::TimeTerms, y: &[f64; N], m: &S::Mode, dy: &mut [f64; N]);
        fn guards(&self, t: f64, y: &[f64; N], m: &S::Mode, g: &mut Guards);
        fn on_event(&self, t: f64, y: &mut [f64; N], m: &mut S::Mode, i: usize) -> EventAction;
        fn next_breakpoint(&self, t: f64, m: &S::Mode) -> f64;
        fn on_breakpoint(&self, t: f64, y: &mut [f64; N], m: &mut S::Mode);
        fn max_step(&self) -> f64;
        fn active_dim(&self) -> usize;
        fn admissible(&self, t: f64, y: &[f64; N]) -> bool;
        fn guard_lipschitz(&self, m: &S::Mode) -> Option<f64>;
    }
}

struct Collect<const N: usize>(Vec<[f64; N]>);
impl<S: HybridSystem<N>, const N: usize> Observer<S, N> for Collect<N> {
    fn on_strobe(&mut self, _t: f64, y: &[f64; N]) {
        self.0.push(*y);
    }
}

impl<S: HybridSystem<N> + Sync, const N: usize> Recordable<N> for StrobeOnly<S> {
    fn strobe_period(&self) -> f64 {
        self.period
    }
    fn scheme(&self, _sim: &SimOptions) -> Scheme {
        self.scheme
    }
    fn describe(&self, t0: f64, y0: [f64; N], sim: &SimOptions) -> Result<Descriptor<N>, SimError> {
        let mut it = Integrator::new(self, self.scheme, t0, y0)?;
        let mut c = Collect(Vec::new());
        run_periods(&mut it, self.period, sim.record_periods, &mut c)?;
        let n = minimal_period(&c.0, sim.max_period).unwrap_or(0);
        let label = if n > 0 {
            format!("P{n}")
        } else {
            "chaotic".to_string()
        };
        Ok(Descriptor::new(n, label, n > 0, &c.0, 0.0, 0.0))
    }
}

/// Compact description of an attractor.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Descriptor<const N: usize = 2> {
    /// Period in excitation periods (0: chaotic or quasi-periodic).
    pub period: usize,
    /// Motion label.
    pub label: String,
    /// Healthy (periodic, no back-side contact or impact).
    pub healthy: bool,
    /// Stroboscopic points (full states): the `period` points of a periodic orbit, or up to 128
    /// points of a chaotic one.
    #[serde(with = "states")]
    pub points: Vec<[f64; N]>,
    /// Bounding box `[min_0, max_0, min_1, max_1, ...]` of the points (the pair:
    /// `[xmin, xmax, vmin, vmax]`).
    pub bbox: Vec<f64>,
    /// Maximum mesh force on the attractor.
    pub max_force: f64,
    /// Dynamic instability proportion.
    pub p_id: f64,
    /// The decided class (`Unsettled` without an exponent until [`consolidate`](crate::identify::consolidate) has decided a
    /// non-periodic record).
    #[serde(default)]
    pub motion: Motion,
    /// Period in mesh cycles from the mesh-cycle strobe, where the excitation period spans several
    /// mesh cycles (breakage) and the motion is periodic (the second clock).
    #[serde(default)]
    pub mesh_period: Option<usize>,
    /// A non-periodic attractor already followed to confirm that it persists ([`consolidate`](crate::identify::consolidate)).
    #[serde(skip)]
    pub persistence_checked: bool,
}

/// Share of one cloud's points that must lie near the other for two non-periodic descriptors to
/// be one attractor.
pub const CONTAINED: f64 = 0.8;
/// "Near" for non-periodic clouds: this fraction of the diagonal of their joint bounding box.
pub const NEAR: f64 = 0.05;
/// "Near" for non-periodic clouds is at least this many times their own median nearest-neighbour
/// distance (a sample of one attractor lies among another sample of it at about their spacing).
pub const NN_FACTOR: f64 = 2.0;
/// Recorded periods (at least) of the run that decides a new non-periodic attractor, so that its
/// cloud is dense enough to be matched even when the cells record only a few periods.
pub const DECIDE_RECORD: u64 = 128;
/// Points kept for a merged non-periodic attractor.
pub const MAX_CLOUD: usize = 256;

/// A section phase outside `[0, 1)`.
#[derive(Debug, thiserror::Error)]
#[error("bad phase {}: allowed [0, 1) (fraction of the excitation period)", geardyn_model::error::num(*.0))]
pub struct PhaseError(pub f64);

/// Checks the phase of a set of initial states (a fraction of the excitation period, `[0, 1)`;
/// NaN is refused).
///
/// ```
/// use geardyn_analysis::attractor::check_phase;
/// assert_eq!(check_phase(0.25).unwrap(), 0.25);
/// assert!(check_phase(1.0).is_err() && check_phase(f64::NAN).is_err());
/// ```
pub fn check_phase(phase: f64) -> Result<f64, PhaseError> {
    if (0.0..1.0).contains(&phase) {
        Ok(phase)
    } else {
        Err(PhaseError(phase))
    }
}

/// Tolerances and lengths of the identification.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct IdentifyOptions {
    /// Simulation settings (method; `transient_periods` is the most before recording;
    /// `record_periods` the recorded length of a new attractor).
    pub sim: SimOptions,
    /// Early-capture tolerance (absolute, in state units).
    pub capture_tol: f64,
    /// Matching tolerance of periodic descriptors.
    pub match_tol: f64,
    /// `|x|` or `|x'|` beyond which a run counts as divergent.
    pub divergence: f64,
    /// Allow early capture.
    pub early_capture: bool,
}

impl Default for IdentifyOptions {
    fn default() -> Self {
        IdentifyOptions {
            sim: SimOptions {
                transient_periods: 300,
                record_periods: 64,
                ..Default::default()
            },
            capture_tol: 1e-4,
            match_tol: 1e-3,
            divergence: 1e3,
            early_capture: true,
        }
    }
}

/// An identification setting out of range ([`IdentifyRequest::options`]); the message names the
/// setting as the CLI spells it (Python's keywords are the same names in snake case).
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum IdentifyError {
    /// The adaptive integrator's relative tolerance (`--ident-rtol`, `ident_rtol`).
    #[error("bad --ident-rtol {}: allowed (0, 1e-3)", geardyn_model::error::num(*.0))]
    Rtol(f64),
    /// The early-capture tolerance (`--capture-tol`, `capture_tol`).
    #[error("bad --capture-tol {}: allowed (0, 1)", geardyn_model::error::num(*.0))]
    CaptureTol(f64),
}

/// The attractor-identification settings a caller chooses (`geardyn basins` and `geardyn
/// continuation`: `--capture-tol`, `--ident-rtol`, `--no-early-stop`; Python's `capture_tol`,
/// `ident_rtol`, `early_stop`): their defaults and limits in one place, turned into the
/// [`IdentifyOptions`] of a run by [`IdentifyRequest::options`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IdentifyRequest {
    /// Early-capture tolerance, absolute in state units (dimensionless lengths and velocities),
    /// in `(0, 1)`; the matching of periodic descriptors uses ten times it.
    pub capture_tol: f64,
    /// Relative tolerance of the adaptive integrator during identification, in `(0, 1e-3)`
    /// (the capture test needs ~1e-5 in the state; 1e-7 leaves a factor 100). Ignored with a
    /// fixed-step integrator.
    pub ident_rtol: f64,
    /// Stop a run early once it is captured by a known attractor (`false`: every run is
    /// integrated for the whole transient).
    pub early_capture: bool,
}

impl IdentifyRequest {
    /// The defaults of the CLI and of Python.
    pub const DEFAULT: IdentifyRequest = IdentifyRequest {
        capture_tol: 1e-4,
        ident_rtol: 1e-7,
        early_capture: true,
    };

    /// The identification options of a run with simulation settings `sim` (the configuration's):
    /// with the adaptive integrator, its relative tolerance becomes `ident_rtol` and its absolute
    /// tolerance at least `ident_rtol * 1e-3`. Checks `ident_rtol` (only with the adaptive
    /// integrator) and then `capture_tol`.
    ///
    /// ```
    /// use geardyn_analysis::attractor::IdentifyRequest;
    /// use geardyn_analysis::simulate::SimOptions;
    /// let o = IdentifyRequest::DEFAULT.options(SimOptions::default()).unwrap();
    /// assert_eq!(o.match_tol, 10.0 * o.capture_tol);
    /// let bad = IdentifyRequest { capture_tol: 2.0, ..IdentifyRequest::DEFAULT };
    /// assert!(bad.options(SimOptions::default()).unwrap_err().to_string().contains("--capture-tol 2"));
    /// ```
    pub fn options(&self, mut sim: SimOptions) -> Result<IdentifyOptions, IdentifyError> {
        if let crate::simulate::Method::Dopri { rtol, atol } = &mut sim.method {
            if !(self.ident_rtol > 0.0 && self.ident_rtol < 1e-3) {
                return Err(IdentifyError::Rtol(self.ident_rtol));
            }
            *rtol = self.ident_rtol;
            *atol = atol.max(self.ident_rtol * 1e-3);
        }
        if !(self.capture_tol > 0.0 && self.capture_tol < 1.0) {
            return Err(IdentifyError::CaptureTol(self.capture_tol));
        }
        Ok(IdentifyOptions {
            sim,
            capture_tol: self.capture_tol,
            match_tol: 10.0 * self.capture_tol,
            early_capture: self.early_capture,
            ..Default::default()
        })
    }
}

impl Default for IdentifyRequest {
    fn default() -> Self {
        IdentifyRequest::DEFAULT
    }
}

/// Cell code of an [`Outcome::Inadmissible`] initial state in a basin grid (beside -1 divergent,
/// -2 failed).
pub const INADMISSIBLE: i64 = -3;

/// Outcome of one trajectory.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Outcome<const N: usize = 2> {
    /// Captured early by known attractor `id` after `periods` periods.
    Captured {
        /// Attractor index in the known list.
        id: usize,
        /// Periods integrated.
        periods: u64,
    },
    /// Ran the whole transient and was recorded.
    Recorded(Descriptor<N>),
    /// Left the bounded region.
    Diverged,
    /// The integrator failed.
    Failed(String),
    /// Not a state of the model (behind a rigid stop): not integrated
    /// ([`geardyn_solvers::HybridSystem::admissible`]).
    Inadmissible,
}

fn bbox<const N: usize>(points: &[[f64; N]]) -> Vec<f64> {
    let mut b: Vec<f64> = (0..2 * N)
        .map(|i| {
            if i % 2 == 0 {
                f64::INFINITY
            } else {
                f64::NEG_INFINITY
            }
        })
        .collect();
    for p in points {
        for i in 0..N {
            b[2 * i] = b[2 * i].min(p[i]);
            b[2 * i + 1] = b[2 * i + 1].max(p[i]);
        }
    }
    b
}

/// Median distance (max norm) from each point of a cloud to its nearest other point (0 for fewer
/// than two points).
fn median_spacing<const N: usize>(points: &[[f64; N]]) -> f64 {
    if points.len() < 2 {
        return 0.0;
    }
    let mut nn: Vec<f64> = points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            points
                .iter()
                .enumerate()
                .filter(|&(j, _)| j != i)
                .map(|(_, q)| dist(p, q))
                .fold(f64::INFINITY, f64::min)
        })
        .collect();
    nn.sort_by(f64::total_cmp);
    nn[nn.len() / 2]
}

/// Largest component difference (the max norm).
#[inline]
pub(crate) fn dist<const N: usize>(a: &[f64; N], b: &[f64; N]) -> f64 {
    // (|a_0 - b_0| first: the same arithmetic as `|dx|.max(|dv|)` for N = 2)
    (1..N).fold((a[0] - b[0]).abs(), |m, i| m.max((a[i] - b[i]).abs()))
}

/// Serialises a list of states as a list of lists (`[[x, v], ...]` for the pair) and reads one
/// back, checking each state's length.
mod states {
    use serde::{Deserialize, Deserializer, Serializer};
    pub fn serialize<const N: usize, S: Serializer>(
        v: &[[f64; N]],
        s: S,
    ) -> Result<S::Ok, S::Error> {
        s.collect_seq(v.iter().map(|y| &y[..]))
    }
    pub fn deserialize<'de, const N: usize, D: Deserializer<'de>>(
        d: D,
    ) -> Result<Vec<[f64; N]>, D::Error> {
        let rows: Vec<Vec<f64>> = Vec::deserialize(d)?;
        rows.into_iter()
            .map(|r| {
                <[f64; N]>::try_from(r.as_slice()).map_err(|_| {
                    serde::de::Error::custom(format!(
                        "a state of {} components where {N} were expected",
                        r.len()
                    ))
                })
            })
            .collect()
    }
}

impl<const N: usize> Outcome<N> {
    /// The same outcome of a system whose dimension is known to be `M` (= `N`; panics
    /// otherwise): the lanes of the pair speak `Outcome<2>`.
    pub fn resized<const M: usize>(self) -> Outcome<M> {
        match self {
            Outcome::Captured { id, periods } => Outcome::Captured { id, periods },
            Outcome::Recorded(d) => Outcome::Recorded(d.resized()),
            Outcome::Diverged => Outcome::Diverged,
            Outcome::Failed(e) => Outcome::Failed(e),
            Outcome::Inadmissible => Outcome::Inadmissible,
        }
    }
}

impl<const N: usize> Descriptor<N> {
    /// The same descriptor of a system whose dimension is known to be `M` (= `N`; panics
    /// otherwise).
    pub fn resized<const M: usize>(self) -> Descriptor<M> {
        assert_eq!(N, M, "a descriptor of dimension {N} read as {M}");
        Descriptor {
            period: self.period,
            label: self.label,
            healthy: self.healthy,
            points: self
                .points
                .iter()
                .map(|p| std::array::from_fn(|i| p[i]))
                .collect(),
            bbox: self.bbox,
            max_force: self.max_force,
            p_id: self.p_id,
            motion: self.motion,
            mesh_period: self.mesh_period,
            persistence_checked: self.persistence_checked,
        }
    }

    /// A descriptor from recorded stroboscopic points: the last `period` points of a periodic
    /// orbit, or up to 128 evenly spread points of a chaotic one.
    pub fn new(
        period: usize,
        label: String,
        healthy: bool,
        pts: &[[f64; N]],
        max_force: f64,
        p_id: f64,
    ) -> Self {
        let points: Vec<[f64; N]> = if period > 0 && pts.len() >= period {
            pts[pts.len() - period..].to_vec()
        } else {
            let step = (pts.len() / 128).max(1);
            pts.iter().step_by(step).copied().collect()
        };
        let motion = if period > 0 {
            Motion::Periodic { period }
        } else {
            Motion::default()
        };
        Descriptor {
            period,
            label,
            healthy,
            bbox: bbox(&points),
            points,
            max_force,
            p_id,
            motion,
            mesh_period: None,
            persistence_checked: false,
        }
    }

    /// Whether two descriptors describe the same attractor (see module doc).
    pub fn matches(&self, other: &Descriptor<N>, tol: f64) -> bool {
        let within = |a: &[[f64; N]], b: &[[f64; N]], r: f64| {
            a.iter().all(|p| b.iter().any(|q| dist(p, q) <= r))
        };
        match (self.period, other.period) {
            (0, 0) => {
                // the diagonal of the joint bounding box (hypot from the first extent on: the
                // pair's `dx.hypot(dv)` exactly)
                let diag = (0..N).fold(0.0f64, |d, i| {
                    let lo = self.bbox[2 * i].min(other.bbox[2 * i]);
                    let hi = self.bbox[2 * i + 1].max(other.bbox[2 * i + 1]);
                    if i == 0 {
                        hi - lo
                    } else {
                        d.hypot(hi - lo)
                    }
                });
                let spacing = median_spacing(&self.points).max(median_spacing(&other.points));
                let r = (NEAR * diag).max(NN_FACTOR * spacing).max(tol);
                let share = |a: &[[f64; N]], b: &[[f64; N]]| {
                    let n = a
                        .iter()
                        .filter(|p| b.iter().any(|q| dist(p, q) <= r))
                        .count();
                    n as f64 / a.len().max(1) as f64
                };
                share(&self.points, &other.points) >= CONTAINED
                    || share(&other.points, &self.points) >= CONTAINED
            }
            (0, n) | (n, 0) => {
                let (cloud, orbit) = if self.period == 0 {
                    (self, other)
                } else {
                    (other, self)
                };
                let tail = &cloud.points[cloud.points.len().saturating_sub(2 * n)..];
                !tail.is_empty() && within(tail, &orbit.points, tol)
            }
            (n, m) => {
                n == m
                    && within(&self.points, &other.points, tol)
                    && within(&other.points, &self.points, tol)
            }
        }
    }

    /// Merges `other` (the same attractor) into `self`: a periodic description wins over a
    /// non-periodic one; two clouds keep the union of their points (at most [`MAX_CLOUD`],
    /// evenly thinned) and the decided class of either.
    pub(crate) fn absorb(&mut self, other: &Descriptor<N>) {
        if self.period > 0 {
            return;
        }
        if other.period > 0 {
            *self = other.clone();
            return;
        }
        let mut pts = self.points.clone();
        pts.extend_from_slice(&other.points);
        if pts.len() > MAX_CLOUD {
            let step = pts.len() as f64 / MAX_CLOUD as f64;
            pts = (0..MAX_CLOUD)
                .map(|i| pts[(i as f64 * step) as usize])
                .collect();
        }
        self.bbox = bbox(&pts);
        self.points = pts;
        self.max_force = self.max_force.max(other.max_force);
        let undecided = |m: &Motion| matches!(m, Motion::Unsettled { tle: None, .. });
        if undecided(&self.motion) && !undecided(&other.motion) {
            self.motion = other.motion.clone();
            self.label = other.label.clone();
            self.healthy = other.healthy;
            self.p_id = other.p_id;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    /// `n` points uniform in a unit cube of 4 of the 8 state components, shifted by `offset` in
    /// the first: a stand-in for the stroboscopic cloud of a chaotic attractor of dimension ~4.
    fn cloud(seed: u64, n: usize, offset: f64) -> Descriptor<8> {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let pts: Vec<[f64; 8]> = (0..n)
            .map(|_| {
                let mut p = [0.0; 8];
                p[0] = offset + rng.gen::<f64>();
                p[3] = rng.gen();
                p[5] = rng.gen();
                p[6] = rng.gen();
                p
            })
            .collect();
        Descriptor::new(0, "chaotic".into(), false, &pts, 1.0, 0.5)
    }

    #[test]
    fn two_sparse_records_of_one_high_dimensional_cloud_are_one_attractor() {
        let (a, b) = (cloud(1, 128, 0.0), cloud(2, 128, 0.0));
        // the clouds' own spacing exceeds NEAR x their diagonal: the fixed share alone splits them
        let spacing = median_spacing(&a.points);
        assert!(spacing > NEAR * 2.0, "{spacing}");
        assert!(a.matches(&b, 1e-3) && b.matches(&a, 1e-3));
        // a cloud beside it, one cube's width away, stays another attractor
        let c = cloud(3, 128, 2.0);
        assert!(!a.matches(&c, 1e-3) && !c.matches(&a, 1e-3));
    }

    #[test]
    fn the_spacing_of_a_cloud_is_its_median_nearest_neighbour_distance() {
        // points on a line at unit steps: every nearest neighbour at 1
        let pts: Vec<[f64; 2]> = (0..9).map(|i| [f64::from(i), 0.0]).collect();
        assert_eq!(median_spacing(&pts), 1.0);
        assert_eq!(median_spacing(&pts[..1]), 0.0);
    }
}
