//! What a simulation records over its recorded periods, and the observer that records it:
//! stroboscopic points of the full state, and per mesh the level crossings (impact sections),
//! contact-state durations, events with velocities and impact forces, mesh-force extrema and
//! time integrals, and the trajectory.
//!
//! Generic over [`GearSystem`]: a system of `N` states and any number of meshes. Mesh
//! quantities are read along each mesh's line of action ([`GearSystem::mesh_state`]), so the
//! counting rules of docs/analyses.md hold mesh by mesh.

use geardyn_model::{ContactState, EventKind, GearSystem};
use geardyn_solvers::{Step, Stop};
use serde::Serialize;

use crate::driver::Observer;

/// One trajectory sample.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct TrajectoryPoint {
    /// Dimensionless time.
    pub tau: f64,
    /// Displacement.
    pub x: f64,
    /// Velocity.
    pub v: f64,
    /// Dynamic mesh force `F_m`.
    pub mesh_force: f64,
    /// Contact state code (drive 1, separated 0, back -1, stuck -2).
    pub state: i8,
}

/// A located event.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct EventRecord {
    /// Time.
    pub tau: f64,
    /// Position in the excitation period, in mesh cycles.
    pub cycle_position: f64,
    /// Kind.
    pub kind: EventKind,
    /// Displacement at the event (before any reset).
    pub x: f64,
    /// Velocity before the event.
    pub v_before: f64,
    /// Velocity after the event.
    pub v_after: f64,
    /// Peak impact force (impacts only, else 0).
    pub peak_force: f64,
}

/// Section levels of docs/model.md §5.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, PartialOrd, Ord, Hash)]
#[serde(rename_all = "snake_case")]
pub enum Level {
    /// `x = D_s`, upward.
    DsUp,
    /// `x = -D_s`, downward.
    DsDown,
    /// `x = D_d`, upward.
    DdUp,
    /// `x = -D_d`, downward.
    DdDown,
}

impl Level {
    /// All four, in label order `p, q, r, s`.
    pub const ALL: [Level; 4] = [Level::DsUp, Level::DsDown, Level::DdUp, Level::DdDown];
    /// Short name used on the command line and in CSV (`ds_up`, ...).
    pub fn name(self) -> &'static str {
        match self {
            Level::DsUp => "ds_up",
            Level::DsDown => "ds_down",
            Level::DdUp => "dd_up",
            Level::DdDown => "dd_down",
        }
    }
}

/// A section crossing: the state where `x` crosses a level in its direction.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Crossing {
    /// Level crossed.
    pub level: Level,
    /// Time.
    pub tau: f64,
    /// Displacement (the level).
    pub x: f64,
    /// Velocity.
    pub v: f64,
}

/// A stroboscopic point: the full state at an integer number of excitation periods.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Strobe<const N: usize> {
    /// Time (dimensionless).
    pub tau: f64,
    /// State.
    pub y: [f64; N],
}

/// Component `0` is the time, `1..=N` the state: the layout `[tau, y_0, .., y_{N-1}]` of the
/// stroboscopic tables.
impl<const N: usize> std::ops::Index<usize> for Strobe<N> {
    type Output = f64;
    fn index(&self, i: usize) -> &f64 {
        if i == 0 {
            &self.tau
        } else {
            &self.y[i - 1]
        }
    }
}

/// As the sequence `[tau, y_0, .., y_{N-1}]`.
impl<const N: usize> Serialize for Strobe<N> {
    fn serialize<Se: serde::Serializer>(&self, s: Se) -> Result<Se::Ok, Se::Error> {
        use serde::ser::SerializeSeq;
        let mut q = s.serialize_seq(Some(N + 1))?;
        q.serialize_element(&self.tau)?;
        for v in &self.y {
            q.serialize_element(v)?;
        }
        q.end()
    }
}

fn ser_states<const N: usize, Se: serde::Serializer>(
    v: &[[f64; N]],
    s: Se,
) -> Result<Se::Ok, Se::Error> {
    s.collect_seq(v.iter().map(|y| &y[..]))
}

fn ser_final<const N: usize, Se: serde::Serializer>(
    v: &(f64, [f64; N]),
    s: Se,
) -> Result<Se::Ok, Se::Error> {
    use serde::ser::SerializeTuple;
    let mut t = s.serialize_tuple(2)?;
    t.serialize_element(&v.0)?;
    t.serialize_element(&v.1[..])?;
    t.end()
}

/// Everything recorded of one mesh over the recorded periods (its line-of-action displacement
/// `x`, velocity `v`, mesh force `F_m`; docs/model.md §5).
#[derive(Clone, Debug, Default, Serialize)]
pub struct MeshRecord {
    /// Trajectory of the mesh (if requested): uniform samples and both sides of every event and
    /// contact change of any mesh, aligned with the other meshes' trajectories sample by sample.
    pub trajectory: Vec<TrajectoryPoint>,
    /// State events of this mesh.
    pub events: Vec<EventRecord>,
    /// Section crossings.
    pub crossings: Vec<Crossing>,
    /// Crossing counts `[p, q, r, s]` per recorded excitation period.
    pub counts_per_period: Vec<[u32; 4]>,
    /// Largest impact force in each recorded excitation period (0 if none).
    pub impact_force_per_period: Vec<f64>,
    /// Time in drive contact, separated, and back contact (stuck included).
    pub durations: [f64; 3],
    /// Maximum mesh force.
    pub max_force: f64,
    /// Minimum mesh force (most negative = back-side load).
    pub min_force: f64,
    /// Number of back-side impacts.
    pub impacts: u64,
    /// Time integrals of `x`, `x^2`, `F_m`, `F_m^2` over the recorded periods.
    pub integrals: [f64; 4],
    /// Smallest and largest `x`.
    pub x_range: (f64, f64),
}

impl MeshRecord {
    fn empty() -> Self {
        MeshRecord {
            max_force: f64::NEG_INFINITY,
            min_force: f64::INFINITY,
            x_range: (f64::INFINITY, f64::NEG_INFINITY),
            ..Default::default()
        }
    }

    /// Means, RMS and peak-to-peak values over the recorded periods.
    pub fn amplitudes(&self) -> Amplitudes {
        let total: f64 = self.durations.iter().sum();
        let t = if total > 0.0 { total } else { 1.0 };
        let mx = self.integrals[0] / t;
        let mf = self.integrals[2] / t;
        Amplitudes {
            mean_x: mx,
            rms_x: (self.integrals[1] / t - mx * mx).max(0.0).sqrt(),
            p2p_x: self.x_range.1 - self.x_range.0,
            mean_force: mf,
            rms_force: (self.integrals[3] / t - mf * mf).max(0.0).sqrt(),
            p2p_force: self.max_force - self.min_force,
        }
    }
}

/// Everything recorded over the recorded periods of a system of `N` states (the single pair:
/// `N = 2`, one mesh).
#[derive(Clone, Debug, Serialize)]
pub struct SimResult<const N: usize = 2> {
    /// Stroboscopic points, one per recorded excitation period (end of period).
    pub strobe: Vec<Strobe<N>>,
    /// States at the end of every mesh cycle of the record, when the excitation period spans
    /// several mesh cycles (tooth breakage); empty otherwise.
    #[serde(serialize_with = "ser_states")]
    pub mesh_strobe: Vec<[f64; N]>,
    /// Per mesh, in the system's mesh order.
    pub meshes: Vec<MeshRecord>,
    /// Final time and state (for continuation).
    #[serde(serialize_with = "ser_final")]
    pub final_state: (f64, [f64; N]),
    /// Memory of the final mode (the hysteresis factor of an impact in progress at the end, 0
    /// otherwise): a continuation starts with it ([`SimOptions::start_memory`]).
    ///
    /// [`SimOptions::start_memory`]: crate::simulate::SimOptions::start_memory
    pub final_memory: f64,
    /// Solver work counters.
    pub steps: u64,
    /// Right-hand-side evaluations.
    pub rhs_evals: u64,
}

impl<const N: usize> Default for SimResult<N> {
    fn default() -> Self {
        SimResult {
            strobe: Vec::new(),
            mesh_strobe: Vec::new(),
            meshes: vec![MeshRecord::default()],
            final_state: (0.0, [0.0; N]),
            final_memory: 0.0,
            steps: 0,
            rhs_evals: 0,
        }
    }
}

impl<const N: usize> SimResult<N> {
    /// The record of the first mesh (the only one of a single pair).
    pub fn mesh(&self) -> &MeshRecord {
        &self.meshes[0]
    }

    /// Means, RMS and peak-to-peak values of the first mesh over the recorded periods.
    pub fn amplitudes(&self) -> Amplitudes {
        self.mesh().amplitudes()
    }

    /// The stroboscopic states (without their times).
    pub fn strobe_states(&self) -> Vec<[f64; N]> {
        self.strobe.iter().map(|p| p.y).collect()
    }
}

/// Response amplitudes over the recorded periods (for frequency-response curves).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, serde::Deserialize)]
pub struct Amplitudes {
    /// Mean of `x`.
    pub mean_x: f64,
    /// RMS of `x - mean(x)` (the alternating part of the dynamic transmission error).
    pub rms_x: f64,
    /// Peak-to-peak of `x`.
    pub p2p_x: f64,
    /// Mean mesh force.
    pub mean_force: f64,
    /// RMS of `F_m - mean(F_m)`.
    pub rms_force: f64,
    /// Peak-to-peak of `F_m`.
    pub p2p_force: f64,
}

/// Whether `x` crosses the section level `lv` on a step from `x0` to `x1` in the level's
/// direction: upward (`up`) `x0 <= lv < x1`, downward `x0 >= lv > x1` (the counting rule of
/// docs/analyses.md, for the scalar recorder and the lanes' copy of its step). Plain boolean
/// operators, so that a loop over lanes vectorises.
#[inline(always)]
pub(crate) fn crosses_level(up: bool, x0: f64, x1: f64, lv: f64) -> bool {
    if up {
        (x0 <= lv) & (x1 > lv)
    } else {
        (x0 >= lv) & (x1 < lv)
    }
}

/// Whether the middle one of three equally spaced samples is strictly extreme (a flat, clamped
/// run must not be extrapolated). Plain boolean operators, so that a loop over lanes vectorises.
#[inline(always)]
pub(crate) fn extreme_middle(a: f64, b: f64, c: f64) -> bool {
    (a - 2.0 * b + c != 0.0) & (((b > a) & (b > c)) | ((b < a) & (b < c)))
}

/// Extremum of the parabola through three equally spaced samples whose middle one is extreme.
#[inline]
pub(crate) fn parabola_peak(a: f64, b: f64, c: f64) -> Option<f64> {
    if extreme_middle(a, b, c) {
        let curv = a - 2.0 * b + c;
        Some(b - (c - a) * (c - a) / (8.0 * curv))
    } else {
        None
    }
}

/// Fewest trajectory samples per natural period of the stiffest contact state
/// ([`GearSystem::natural_period`]): a curve drawn through the samples stays smooth where a mesh
/// cycle spans many natural oscillations (the broken pair at `omega` = 0.1: ten per mesh cycle,
/// which 24 samples per cycle drew as a star of straight lines).
pub const MIN_SAMPLES_PER_NATURAL_PERIOD: u32 = 32;

/// Time between trajectory samples: `samples_per_cycle` per mesh cycle, or finer when the
/// natural period asks for it ([`MIN_SAMPLES_PER_NATURAL_PERIOD`]; only when the trajectory is
/// kept, so that other runs pay nothing for the stiffness scan).
fn sample_step<S: GearSystem<N>, const N: usize>(
    sys: &S,
    samples_per_cycle: u32,
    keep_traj: bool,
) -> f64 {
    let per_cycle = sys.mesh_cycle_time() / samples_per_cycle.max(1) as f64;
    if !keep_traj {
        return per_cycle;
    }
    let natural = sys.natural_period();
    if natural.is_finite() {
        per_cycle.min(natural / MIN_SAMPLES_PER_NATURAL_PERIOD as f64)
    } else {
        per_cycle
    }
}

/// Section levels and counting switches of one mesh.
#[derive(Clone, Copy, Debug)]
pub(crate) struct MeshLevels {
    pub(crate) levels: [f64; 4],
    pub(crate) count: [bool; 4],
}

/// The observer of [`crate::simulate::simulate`] (and of the lanes' rare steps).
pub(crate) struct Recorder<S: GearSystem<N>, const N: usize> {
    pub(crate) sys: S,
    pub(crate) res: SimResult<N>,
    pub(crate) keep_traj: bool,
    /// Recorded periods completed, and the first one whose trajectory is kept.
    pub(crate) period: u64,
    pub(crate) traj_from: u64,
    /// Mode and time at the end of the previous step, whose mesh forces `last_force` holds
    /// (reused at the next start).
    pub(crate) last_end: Option<(f64, S::Mode)>,
    pub(crate) last_force: Vec<f64>,
    pub(crate) sample_dt: f64,
    pub(crate) next_sample: u64,
    pub(crate) sample_origin: f64,
    pub(crate) levels: Vec<MeshLevels>,
    pub(crate) counts: Vec<[u32; 4]>,
    pub(crate) impact_max: Vec<f64>,
    /// Mesh-cycle strobe (only when an excitation period spans several mesh cycles).
    pub(crate) mesh_on: bool,
    pub(crate) mesh_dt: f64,
    pub(crate) next_mesh: u64,
    /// The stroboscopic points only ([`SimOptions::strobe_only`]).
    ///
    /// [`SimOptions::strobe_only`]: crate::simulate::SimOptions::strobe_only
    pub(crate) strobe_only: bool,
}

impl<S: GearSystem<N>, const N: usize> Recorder<S, N> {
    pub(crate) fn new(
        sys: S,
        keep_traj: bool,
        samples_per_cycle: u32,
        t_start: f64,
        traj_from: u64,
    ) -> Self {
        let m = sys.mesh_count();
        let levels = (0..m)
            .map(|k| {
                let (dd, ds) = sys.backlash_levels(k);
                let distinct = dd != ds;
                MeshLevels {
                    levels: [ds, -ds, dd, -dd],
                    count: [true, true, distinct, distinct],
                }
            })
            .collect();
        Recorder {
            res: SimResult {
                meshes: (0..m).map(|_| MeshRecord::empty()).collect(),
                ..Default::default()
            },
            keep_traj,
            period: 0,
            traj_from,
            last_end: None,
            last_force: vec![0.0; m],
            sample_dt: sample_step(&sys, samples_per_cycle, keep_traj),
            next_sample: 0,
            sample_origin: t_start,
            levels,
            counts: vec![[0; 4]; m],
            impact_max: vec![0.0; m],
            mesh_on: sys.cycles_per_period() > 1,
            mesh_dt: sys.mesh_cycle_time(),
            next_mesh: 1,
            strobe_only: false,
            sys,
        }
    }

    /// The recorder of the stroboscopic points only ([`SimOptions::strobe_only`]).
    ///
    /// [`SimOptions::strobe_only`]: crate::simulate::SimOptions::strobe_only
    pub(crate) fn strobe_only(mut self, on: bool) -> Self {
        self.strobe_only = on;
        self
    }

    /// The finished record: `x_range` of a record of the stroboscopic points only taken from
    /// them, and the force extremes of a record without a force set to zero.
    pub(crate) fn finish(self) -> SimResult<N> {
        let mut res = self.res;
        if self.strobe_only {
            for (k, m) in res.meshes.iter_mut().enumerate() {
                m.x_range =
                    res.strobe
                        .iter()
                        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                            let x = self.sys.mesh_state(p.tau, &p.y, k)[0];
                            (lo.min(x), hi.max(x))
                        });
            }
        }
        for m in res.meshes.iter_mut() {
            if m.max_force == f64::NEG_INFINITY {
                m.max_force = 0.0;
                m.min_force = 0.0;
            }
        }
        res
    }

    /// The force of mesh `k` after an event or a contact change (it counts in the extrema).
    fn force(&mut self, k: usize, t: f64, y: &[f64; N], mode: &S::Mode) -> f64 {
        let f = self.sys.mesh_force(t, y, mode, k);
        let r = &mut self.res.meshes[k];
        r.max_force = r.max_force.max(f);
        r.min_force = r.min_force.min(f);
        f
    }

    #[inline]
    fn traj_on(&self) -> bool {
        self.keep_traj && self.period >= self.traj_from
    }

    fn push_traj(&mut self, k: usize, tau: f64, y: &[f64; N], f: f64, mode: &S::Mode) {
        if self.traj_on() {
            let [x, v] = self.sys.mesh_state(tau, y, k);
            let state = self.sys.contact(mode, k).code();
            self.res.meshes[k].trajectory.push(TrajectoryPoint {
                tau,
                x,
                v,
                mesh_force: f,
                state,
            });
        }
    }

    /// Durations, integrals and extrema of mesh `k` over a step from interpolant samples.
    fn integrate_step(
        &mut self,
        k: usize,
        step: &Step<N>,
        before: &S::Mode,
        ths: &[f64],
        w: &[f64],
        ys: &[[f64; N]; 5],
    ) -> f64 {
        let (t0, t1) = (step.t0, step.t1);
        let dt = t1 - t0;
        let contact = matches!(
            self.sys.contact(before, k),
            ContactState::Drive | ContactState::Back
        );
        let mut xs = [0.0; 5];
        let mut fs = [0.0; 5];
        for (j, &th) in ths.iter().enumerate() {
            xs[j] = self.sys.mesh_state(t0 + th * dt, &ys[j], k)[0];
            if contact {
                // the start of a step continues the end of the previous one (same mode, no reset)
                fs[j] = match self.last_end {
                    Some((t, m)) if j == 0 && t == t0 && m == *before => self.last_force[k],
                    _ => self.sys.mesh_force(t0 + th * dt, &ys[j], before, k),
                };
            }
        }
        let n = ths.len();
        let r = &mut self.res.meshes[k];
        for j in 0..n {
            r.x_range = (r.x_range.0.min(xs[j]), r.x_range.1.max(xs[j]));
            r.max_force = r.max_force.max(fs[j]);
            r.min_force = r.min_force.min(fs[j]);
            r.integrals[0] += w[j] * dt * xs[j];
            r.integrals[1] += w[j] * dt * xs[j] * xs[j];
            r.integrals[2] += w[j] * dt * fs[j];
            r.integrals[3] += w[j] * dt * fs[j] * fs[j];
        }
        for j in 1..n - 1 {
            if let Some(p) = parabola_peak(xs[j - 1], xs[j], xs[j + 1]) {
                r.x_range = (r.x_range.0.min(p), r.x_range.1.max(p));
            }
            if contact {
                if let Some(p) = parabola_peak(fs[j - 1], fs[j], fs[j + 1]) {
                    r.max_force = r.max_force.max(p);
                    r.min_force = r.min_force.min(p);
                }
            }
        }
        fs[n - 1]
    }

    /// Level crossings of mesh `k` on a step (its `x` is continuous within it).
    fn count_crossings(&mut self, k: usize, step: &Step<N>) {
        let (t0, t1) = (step.t0, step.t1);
        let x0 = self.sys.mesh_state(t0, &step.y0(), k)[0];
        let x1 = self.sys.mesh_state(t1, &step.y1(), k)[0];
        let lv = self.levels[k];
        for (i, &level) in lv.levels.iter().enumerate() {
            if !lv.count[i] {
                continue;
            }
            let up = i % 2 == 0;
            if crosses_level(up, x0, x1, level) {
                self.counts[k][i] += 1;
                // locate on the interpolant for the section point
                let sys = &self.sys;
                let br = geardyn_solvers::root::illinois(
                    |t| sys.mesh_state(t, &step.interpolate(t), k)[0] - level,
                    t0,
                    x0 - level,
                    t1,
                    x1 - level,
                    1e-13 * t1.abs().max(1.0),
                    |g| if up { g > 0.0 } else { g < 0.0 },
                );
                let v = self.sys.mesh_state(br.b, &step.interpolate(br.b), k)[1];
                self.res.meshes[k].crossings.push(Crossing {
                    level: Level::ALL[i],
                    tau: br.b,
                    x: level,
                    v,
                });
            }
        }
    }
}

impl<S: GearSystem<N>, const N: usize> Observer<S, N> for Recorder<S, N> {
    fn on_step(
        &mut self,
        _sys: &S,
        step: &Step<N>,
        before: &S::Mode,
        stop: Stop,
        after: &S::Mode,
        y_after: &[f64; N],
    ) {
        if self.strobe_only {
            return;
        }
        let meshes = self.res.meshes.len();
        let (t0, t1) = (step.t0, step.t1);
        let dt = t1 - t0;
        for k in 0..meshes {
            let slot = match self.sys.contact(before, k) {
                ContactState::Drive => 0,
                ContactState::Separated => 1,
                ContactState::Back | ContactState::Stuck => 2,
            };
            self.res.meshes[k].durations[slot] += dt;
        }
        // time averages and extrema from interpolant samples: Simpson's rule on three for short
        // steps (fixed-step RK4), Boole's rule on five for long adaptive steps; a parabola through
        // the samples around an interior extremum refines the peak force.
        let y1 = step.y1();
        let long = dt > self.sample_dt * 2.0;
        let (ths, w): (&[f64], &[f64]) = if long {
            (
                &[0.0, 0.25, 0.5, 0.75, 1.0],
                &[
                    7.0 / 90.0,
                    32.0 / 90.0,
                    12.0 / 90.0,
                    32.0 / 90.0,
                    7.0 / 90.0,
                ],
            )
        } else {
            (&[0.0, 0.5, 1.0], &[1.0 / 6.0, 4.0 / 6.0, 1.0 / 6.0])
        };
        let mut ys = [[0.0; N]; 5];
        for (j, &th) in ths.iter().enumerate() {
            ys[j] = if th == 1.0 { y1 } else { step.at_theta(th) };
        }
        for k in 0..meshes {
            let f_end = self.integrate_step(k, step, before, ths, w, &ys);
            self.last_force[k] = f_end;
        }
        self.last_end = if stop == Stop::Step {
            Some((t1, *before))
        } else {
            None
        };
        if self.traj_on() {
            // uniform samples from the dense output, times computed from an integer index
            loop {
                let ts = self.sample_origin + self.next_sample as f64 * self.sample_dt;
                if ts > t1 {
                    break;
                }
                if ts >= t0 {
                    let y = step.interpolate(ts);
                    for k in 0..meshes {
                        let f = self.sys.mesh_force(ts, &y, before, k);
                        self.push_traj(k, ts, &y, f, before);
                    }
                }
                self.next_sample += 1;
            }
        }
        if self.mesh_on {
            // the state at every mesh cycle, from the dense output (times from an integer index)
            loop {
                let tm = self.sample_origin + self.next_mesh as f64 * self.mesh_dt;
                if tm > t1 {
                    break;
                }
                if tm >= t0 {
                    self.res.mesh_strobe.push(step.interpolate(tm));
                }
                self.next_mesh += 1;
            }
        }
        for k in 0..meshes {
            self.count_crossings(k, step);
        }
        if let Stop::Event { index } = stop {
            let (k, kind) = self.sys.event(before, after, index);
            let [x, v_before] = self.sys.mesh_state(t1, &y1, k);
            let peak = if kind == EventKind::Impact {
                self.res.meshes[k].impacts += 1;
                let p = self.sys.impact_peak_force(k, v_before);
                self.impact_max[k] = self.impact_max[k].max(p);
                p
            } else {
                0.0
            };
            let u = self.sys.cycle_position(t1);
            let v_after = self.sys.mesh_state(t1, y_after, k)[1];
            self.res.meshes[k].events.push(EventRecord {
                tau: t1,
                cycle_position: u,
                kind,
                x,
                v_before,
                v_after,
                peak_force: peak,
            });
            for j in 0..meshes {
                let fb = self.sys.mesh_force(t1, &y1, before, j);
                self.push_traj(j, t1, &y1, fb, before);
                let fa = self.force(j, t1, y_after, after);
                self.push_traj(j, t1, y_after, fa, after);
            }
        } else if (0..meshes).any(|k| self.sys.contact(before, k) != self.sys.contact(after, k)) {
            // a contact change without a state event is a breakpoint (it may coincide with the
            // stroboscopic instant, reported as Tstop)
            // A backlash jump (time-varying D) that closes the gap is a contact entry: relative
            // to the moving contact surface, x crossed it. It counts as a crossing of the level
            // it enters at (docs/analyses.md, "Counting rule").
            for k in 0..meshes {
                let entry = match (self.sys.contact(before, k), self.sys.contact(after, k)) {
                    (ContactState::Separated, ContactState::Drive) => Some(0),
                    (ContactState::Separated, ContactState::Back | ContactState::Stuck) => Some(1),
                    _ => None,
                };
                if let Some(side) = entry {
                    // only a decrease of the backlash (D_s -> D_d) closes a gap: the entry is at D_d
                    let i = if self.levels[k].count[2] {
                        side + 2
                    } else {
                        side
                    };
                    self.counts[k][i] += 1;
                    let [x, v] = self.sys.mesh_state(t1, &y1, k);
                    self.res.meshes[k].crossings.push(Crossing {
                        level: Level::ALL[i],
                        tau: t1,
                        x,
                        v,
                    });
                }
            }
            for k in 0..meshes {
                let fa = self.force(k, t1, y_after, after);
                self.push_traj(k, t1, y_after, fa, after);
            }
        }
    }

    fn on_strobe(&mut self, t: f64, y: &[f64; N]) {
        self.res.strobe.push(Strobe { tau: t, y: *y });
        for k in 0..self.res.meshes.len() {
            let m = &mut self.res.meshes[k];
            m.counts_per_period.push(self.counts[k]);
            self.counts[k] = [0; 4];
            m.impact_force_per_period.push(self.impact_max[k]);
            self.impact_max[k] = 0.0;
        }
        self.period += 1;
        if self.period == self.traj_from {
            // the kept window starts here: uniform samples from this instant
            self.sample_origin = t;
            self.next_sample = 0;
        }
    }
}
