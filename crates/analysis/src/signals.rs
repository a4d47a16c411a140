//! Vibration signals of a physical gear pair and its healthy twin (docs/analyses.md, "Fault
//! signatures"): the dynamic transmission error, the mesh force and the relative acceleration
//! along the line of action, in physical units, sampled uniformly over whole pinion
//! revolutions, with their spectra in orders and the condition indicators of
//! [`crate::indicators`].
//!
//! Units: the model integrates dimensionless `x`, `tau` (docs/model.md §1); the signals are
//! `x b_c` (µm), `F_m k_av b_c` (N) and `x'' b_c omega_n^2` (m/s²) with the pair's `b_c`, `k_av`
//! and `omega_n`. The pinion turns at its constant nominal speed in the model (no shaft
//! dynamics), so samples uniform in time are uniform in pinion angle: a revolution is `z1` mesh
//! cycles and `samples_per_cycle * z1` samples.

use crate::driver::{run_periods, Discard, Observer};
use crate::indicators::{
    decompose, indicators, Decomposition, IndicatorOptions, Indicators, RemovedOrders, ResidualKind,
};
use crate::record::Recorder;
use crate::simulate::{summarize, Method, SimError, SimOptions, Summary};
use crate::spectrum::{setting, welch_orders, SettingError, Spectrum};
use geardyn_model::{MeshMode, MeshModel};
use geardyn_scenario::{Scenario, ScenarioError};
use geardyn_solvers::{Integrator, Step, Stop};
use serde::Serialize;

/// The signals, by their column names in `signals.csv`.
pub const SIGNAL_NAMES: [&str; 3] = ["dte_um", "mesh_force_N", "acceleration_m_s2"];

/// NA4's and NB4's denominator (the literature disagrees: docs/analyses.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Na4Reference {
    /// Each record's own variance (NA4 is then the kurtosis of the residual).
    Own,
    /// The variance averaged over the run: the healthy twin is the first record of the run and
    /// the broken pair the second (Zakrajsek et al. 1993: the mean over the records so far).
    Run,
}

impl Na4Reference {
    /// The name used in options and files (`own`, `run`).
    pub fn name(self) -> &'static str {
        match self {
            Na4Reference::Own => "own",
            Na4Reference::Run => "run",
        }
    }
    /// From its name.
    pub fn from_name(s: &str) -> Result<Self, SettingError> {
        match s {
            "own" => Ok(Na4Reference::Own),
            "run" => Ok(Na4Reference::Run),
            _ => Err(setting("na4_reference", s, "own or run")),
        }
    }
}

/// One request of `geardyn signals` / `geardyn.signals()`: its settings, ranges and defaults in
/// one place ([`SignalsRequest::check`]), run by [`run_signals`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SignalsRequest {
    /// Pinion revolutions recorded (default 16).
    pub revolutions: u64,
    /// Pinion revolutions discarded first (default 300, the seeds' transient).
    pub transient: u64,
    /// Samples per mesh cycle (default 32; `z1` times that per revolution).
    pub samples_per_cycle: u32,
    /// Revolutions per Welch segment of the spectra (default 4: 0.25-order resolution).
    pub segment_revolutions: u64,
    /// Shaft sidebands of every mesh harmonic removed from the difference signal (default 1).
    pub sidebands: usize,
    /// Shaft orders `1 ..= shaft_orders` removed from the difference (and residual) signal.
    pub shaft_orders: usize,
    /// Residual definition (default [`ResidualKind::MeshAndShaft`]).
    pub residual: ResidualKind,
    /// NA4's / NB4's denominator (default [`Na4Reference::Run`]).
    pub na4_reference: Na4Reference,
    /// Initial state `(x0, x0')` of both pairs (dimensionless).
    pub y0: [f64; 2],
    /// Start time `tau0` of both pairs (dimensionless).
    pub tau0: f64,
    /// Integrator.
    pub method: Method,
}

impl Default for SignalsRequest {
    fn default() -> Self {
        SignalsRequest {
            revolutions: 16,
            transient: 300,
            samples_per_cycle: 32,
            segment_revolutions: 4,
            sidebands: 1,
            shaft_orders: 1,
            residual: ResidualKind::MeshAndShaft,
            na4_reference: Na4Reference::Run,
            y0: [0.0, 0.0],
            tau0: 0.0,
            method: Method::default(),
        }
    }
}

/// Most samples of one pair's record (about 80 MB of signals in memory).
pub const MAX_SAMPLES: u64 = 10_000_000;
/// Samples per mesh cycle accepted.
pub const SAMPLES_PER_CYCLE: std::ops::RangeInclusive<u32> = 4..=4096;

/// Failure of a signals request.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SignalsError {
    /// A setting out of its range.
    #[error(transparent)]
    Setting(#[from] SettingError),
    /// A scenario without the physical pair that gives the signals their units.
    #[error("{0}")]
    NoPair(String),
    /// The healthy twin could not be built.
    #[error(transparent)]
    Scenario(#[from] ScenarioError),
    /// The integration failed.
    #[error(transparent)]
    Sim(#[from] SimError),
}

impl From<geardyn_solvers::SolverError> for SignalsError {
    fn from(e: geardyn_solvers::SolverError) -> Self {
        SignalsError::Sim(e.into())
    }
}

/// The pair's scales that turn the dimensionless model into physical signals.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Scales {
    /// Characteristic length `b_c` (m): `x = 1` is `b_c`.
    pub b_c_m: f64,
    /// Mean mesh stiffness `k_av` (N/m): a mesh force of 1 is `k_av b_c`.
    pub k_av_n_per_m: f64,
    /// Natural frequency `omega_n` (rad/s): `tau = omega_n t`.
    pub omega_n_rad_s: f64,
    /// Pinion teeth `z1`: mesh cycles per pinion revolution, the mesh order.
    pub z1: u32,
}

impl Scales {
    /// The scales of `sc`'s physical pair, or an error naming `[pair]`.
    pub fn of(sc: &Scenario) -> Result<Scales, SignalsError> {
        let pm = sc.pair_model().ok_or_else(|| {
            SignalsError::NoPair(
                "this configuration has no physical [pair]: the signals need its b_c, k_av, omega_n and tooth number z1 for their units and their revolution (use --preset breakage or internal, or a configuration with a [pair] table)".into(),
            )
        })?;
        Ok(Scales {
            b_c_m: pm.b_c,
            k_av_n_per_m: pm.k_av,
            omega_n_rad_s: pm.omega_n,
            z1: pm.geom.z1,
        })
    }
}

impl SignalsRequest {
    /// The indicator options of this request for `z1` teeth.
    pub fn indicator_options(&self, z1: u32) -> IndicatorOptions {
        IndicatorOptions {
            samples_per_rev: self.samples_per_cycle as usize * z1 as usize,
            mesh_order: z1 as usize,
            sidebands: self.sidebands,
            shaft_orders: self.shaft_orders,
            residual: self.residual,
        }
    }

    /// Refuses a setting outside its range (naming it and the range), and a scenario without a
    /// physical pair.
    pub fn check(&self, sc: &Scenario) -> Result<Scales, SignalsError> {
        let scales = Scales::of(sc)?;
        if !(2..=100_000).contains(&self.revolutions) {
            return Err(setting("revolutions", self.revolutions, "2 ..= 100000").into());
        }
        if !SAMPLES_PER_CYCLE.contains(&self.samples_per_cycle) {
            return Err(setting(
                "samples_per_cycle",
                self.samples_per_cycle,
                format!(
                    "{} ..= {}",
                    SAMPLES_PER_CYCLE.start(),
                    SAMPLES_PER_CYCLE.end()
                ),
            )
            .into());
        }
        let z1 = u64::from(scales.z1);
        let max_transient = crate::simulate::MAX_PERIODS / z1.max(1);
        if self.transient > max_transient {
            return Err(setting(
                "transient",
                self.transient,
                format!("0 ..= {max_transient} revolutions"),
            )
            .into());
        }
        let samples = self.revolutions * z1 * u64::from(self.samples_per_cycle);
        if samples > MAX_SAMPLES {
            return Err(setting(
                "revolutions",
                self.revolutions,
                format!(
                    "at most {MAX_SAMPLES} samples per pair: revolutions * z1 * samples_per_cycle = {samples}"
                ),
            )
            .into());
        }
        if self.segment_revolutions == 0 || self.segment_revolutions > self.revolutions {
            return Err(setting(
                "segment_revolutions",
                self.segment_revolutions,
                format!("1 ..= {} (the revolutions recorded)", self.revolutions),
            )
            .into());
        }
        if !(self.y0[0].is_finite() && self.y0[1].is_finite()) {
            return Err(setting(
                "y0",
                format!("({}, {})", self.y0[0], self.y0[1]),
                "finite numbers",
            )
            .into());
        }
        if !self.tau0.is_finite() {
            return Err(setting("tau0", self.tau0, "a finite number").into());
        }
        let o = self.indicator_options(scales.z1);
        o.check(o.samples_per_rev)?;
        Ok(scales)
    }
}

/// What the pair's motion is while the signals are recorded: the multi-state context.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MotionContext {
    /// Motion label (`n-p-q`, or the class word).
    pub label: String,
    /// Period in the model's excitation periods (0: none found up to 32).
    pub period: usize,
    /// Period in pinion revolutions (0: none).
    pub period_revolutions: usize,
    /// Attractor class compared between the pairs: `back-side contact` (impacts or back-flank
    /// contact in the record) or `no back-side contact` (the period is in `label`: a record too
    /// short to show a period is not a different attractor).
    pub class: String,
    /// Drive-side contact entries per revolution (upward crossings of `D_s` and `D_d`: each one
    /// follows a separation).
    pub reentries_per_rev: f64,
    /// Back-side impacts over the record.
    pub impacts: u64,
    /// Back-side impacts per revolution.
    pub impacts_per_rev: f64,
    /// Whether the back flank is touched (impacts, back contact, back-side crossings).
    pub back_side: bool,
    /// Dynamic instability proportion P_ID over the record.
    pub p_id: f64,
    /// Largest impact force (dimensionless, units of `k_av b_c`).
    pub max_impact_force: f64,
}

impl MotionContext {
    fn of(s: &Summary, per_rev: u64, revolutions: u64) -> Self {
        let back = (!s.healthy && s.period > 0) || s.impacts > 0 || s.counts[1] > 0;
        // the multi-state class that shapes the signals: whether the back flank is touched
        let class = if back {
            "back-side contact"
        } else {
            "no back-side contact"
        };
        let per_rev = per_rev as usize;
        MotionContext {
            label: s.label.clone(),
            period: s.period,
            period_revolutions: if s.period == 0 {
                0
            } else {
                lcm(s.period, per_rev) / per_rev
            },
            class: class.into(),
            reentries_per_rev: (s.rates[0] + s.rates[2]) * per_rev as f64,
            impacts: s.impacts,
            impacts_per_rev: s.impacts as f64 / revolutions.max(1) as f64,
            back_side: back,
            p_id: s.p_id,
            max_impact_force: s.max_impact_force,
        }
    }
}

/// Most drive-side contact entries per revolution by which two records of the healthy pair on
/// one attractor differ (a periodic orbit repeats them exactly; a chaotic one nearly).
pub const LIKE_REENTRIES: f64 = 2.0;

impl MotionContext {
    /// Whether two records of one pair are on the same attractor: the same back-side class, and
    /// drive-side contact entries per revolution within [`LIKE_REENTRIES`].
    pub fn like(&self, other: &MotionContext) -> bool {
        self.class == other.class
            && (self.reentries_per_rev - other.reentries_per_rev).abs() <= LIKE_REENTRIES
    }

    fn text(&self) -> String {
        format!(
            "{}, {} ({} drive-side entries per revolution)",
            self.label,
            self.class,
            (self.reentries_per_rev * 1000.0).round() / 1000.0
        )
    }
}

fn lcm(a: usize, b: usize) -> usize {
    fn gcd(a: usize, b: usize) -> usize {
        if b == 0 {
            a
        } else {
            gcd(b, a % b)
        }
    }
    if a == 0 || b == 0 {
        return 0;
    }
    a / gcd(a, b) * b
}

/// One pair's signals, spectra and indicators.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PairSignals {
    /// `broken` or `healthy`.
    pub pair: String,
    /// Where the record's transient started: `initial state`, or `broken pair's final state`
    /// (the healthy twin moved onto the broken pair's attractor class).
    pub start: String,
    /// Sample times (dimensionless `tau`; seconds: `tau / omega_n`): sample `i` at
    /// `tau_rec + (i + 1/2) dt`, `dt` a mesh cycle over `samples_per_cycle`.
    #[serde(skip)]
    pub tau: Vec<f64>,
    /// The three signals of [`SIGNAL_NAMES`] (µm, N, m/s²). The acceleration of sample `i` is
    /// the mean acceleration over `[tau_i - dt/2, tau_i + dt/2]`, `(x'(tau_i + dt/2) -
    /// x'(tau_i - dt/2)) / dt`: the vector field between events, and it keeps the velocity jump
    /// of a back-side impact (a Dirac in the instantaneous acceleration) as a sampled pulse.
    #[serde(skip)]
    pub signals: [Vec<f64>; 3],
    /// Welch spectra of the three signals.
    #[serde(skip)]
    pub spectra: [Spectrum; 3],
    /// TSA and its parts of the three signals.
    #[serde(skip)]
    pub decompositions: [Decomposition; 3],
    /// Indicators of the three signals.
    pub indicators: [Indicators; 3],
    /// RMS of the difference signal over the TSA's standard deviation, per signal (below
    /// [`crate::indicators::NOISE_FLOOR`]: no content besides the mesh orders).
    pub difference_fraction: [f64; 3],
    /// The motion recorded.
    pub motion: MotionContext,
}

/// The result of [`run_signals`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SignalsResult {
    /// Scales used.
    pub scales: Scales,
    /// Samples per pinion revolution.
    pub samples_per_rev: usize,
    /// Revolutions recorded.
    pub revolutions: u64,
    /// The pairs: the healthy twin first, then the broken pair (only the healthy one when the
    /// scenario has no broken tooth).
    pub pairs: Vec<PairSignals>,
    /// Whether the scenario has a broken tooth.
    pub broken: bool,
    /// Whether both pairs were recorded on the same attractor class (like with like).
    pub comparable: bool,
    /// What was done about attractors and breakage, in words.
    pub notes: Vec<String>,
    /// The orders of the regular, difference and residual signals.
    pub orders: RemovedOrders,
    /// The indicator options used.
    pub options: IndicatorOptions,
    /// NA4's / NB4's denominator used.
    pub na4_reference: Na4Reference,
}

/// Uniform samples of `x`, `F_m` and the velocity half a sample before and after each.
struct Sampler<'a> {
    model: &'a MeshModel,
    origin: f64,
    half: f64,
    next: u64,
    last: u64,
    tau: Vec<f64>,
    x: Vec<f64>,
    force: Vec<f64>,
    v_mid: Vec<f64>,
}

impl Sampler<'_> {
    fn on_step(&mut self, step: &Step<2>, before: &MeshMode) {
        // grid times from an integer index: even indices are the velocity points, odd ones the
        // samples
        while self.next <= self.last {
            let t = self.origin + self.next as f64 * self.half;
            if t > step.t1 {
                break;
            }
            let y = step.interpolate(t);
            if self.next.is_multiple_of(2) {
                self.v_mid.push(y[1]);
            } else {
                self.tau.push(t);
                self.x.push(y[0]);
                self.force.push(self.model.mesh_force(t, &y, before));
            }
            self.next += 1;
        }
    }
}

struct Both<'a> {
    rec: Recorder<&'a MeshModel, 2>,
    sampler: Sampler<'a>,
}

impl<'m> Observer<&'m MeshModel, 2> for Both<'_> {
    fn on_step(
        &mut self,
        _sys: &&'m MeshModel,
        step: &Step<2>,
        before: &MeshMode,
        stop: Stop,
        after: &MeshMode,
        y_after: &[f64; 2],
    ) {
        let own = self.rec.sys;
        self.rec.on_step(&own, step, before, stop, after, y_after);
        self.sampler.on_step(step, before);
    }
    fn on_strobe(&mut self, t: f64, y: &[f64; 2]) {
        Observer::<&MeshModel, 2>::on_strobe(&mut self.rec, t, y);
    }
}

/// A record of one model: dimensionless samples, the motion, and the final time and state.
struct Raw {
    tau: Vec<f64>,
    x: Vec<f64>,
    force: Vec<f64>,
    accel: Vec<f64>,
    summary: Summary,
    per_rev: u64,
    end: (f64, [f64; 2]),
}

fn record(
    model: &MeshModel,
    z1: u32,
    req: &SignalsRequest,
    start: (f64, [f64; 2]),
) -> Result<Raw, SignalsError> {
    let per_rev = u64::from(z1 / model.cycles_per_period().max(1)).max(1);
    let opts = SimOptions {
        method: req.method,
        transient_periods: req.transient * per_rev,
        record_periods: req.revolutions * per_rev,
        tau0: start.0,
        ..SimOptions::default()
    };
    let mut integ = Integrator::new(model, req.method.scheme(model), start.0, start.1)?;
    let period = model.excitation_period();
    run_periods(&mut integ, period, opts.transient_periods, &mut Discard)?;
    let spc = u64::from(req.samples_per_cycle);
    let n = req.revolutions * u64::from(z1) * spc;
    let dt = model.mesh_cycle_time() / spc as f64;
    let t_rec = integ.t();
    let mut obs = Both {
        rec: Recorder::new(model, false, 1, t_rec, 0),
        sampler: Sampler {
            model,
            origin: t_rec,
            half: dt / 2.0,
            next: 0,
            last: 2 * n,
            tau: Vec::with_capacity(n as usize),
            x: Vec::with_capacity(n as usize),
            force: Vec::with_capacity(n as usize),
            v_mid: Vec::with_capacity(n as usize + 1),
        },
    };
    run_periods(&mut integ, period, opts.record_periods, &mut obs)?;
    let Both { rec, mut sampler } = obs;
    // the last grid point is the end of the record, which rounding may put just past it
    if sampler.v_mid.len() as u64 == n {
        sampler.v_mid.push(integ.y()[1]);
    }
    if sampler.x.len() as u64 != n || sampler.v_mid.len() as u64 != n + 1 {
        return Err(setting(
            "samples_per_cycle",
            req.samples_per_cycle,
            format!(
                "a grid the record covers ({} of {n} samples taken)",
                sampler.x.len()
            ),
        )
        .into());
    }
    let accel = sampler
        .v_mid
        .windows(2)
        .map(|w| (w[1] - w[0]) / dt)
        .collect();
    let res = rec.finish();
    let summary = summarize(model, &res, &opts);
    Ok(Raw {
        tau: sampler.tau,
        x: sampler.x,
        force: sampler.force,
        accel,
        summary,
        per_rev,
        end: (integ.t(), *integ.y()),
    })
}

/// Three values, one per signal (the vectors are built with three elements).
fn arr<T>(v: Vec<T>) -> [T; 3] {
    v.try_into()
        .unwrap_or_else(|_| unreachable!("one value per signal"))
}

fn process(
    name: &str,
    start: &str,
    raw: Raw,
    sc: &Scales,
    req: &SignalsRequest,
    o: &IndicatorOptions,
    run: Option<&PairSignals>,
) -> Result<PairSignals, SignalsError> {
    let b = sc.b_c_m;
    let signals = [
        raw.x.iter().map(|v| v * b * 1e6).collect::<Vec<f64>>(),
        raw.force.iter().map(|v| v * sc.k_av_n_per_m * b).collect(),
        raw.accel
            .iter()
            .map(|v| v * b * sc.omega_n_rad_s * sc.omega_n_rad_s)
            .collect(),
    ];
    let spr = o.samples_per_rev;
    let mut spectra = Vec::with_capacity(3);
    let mut decs = Vec::with_capacity(3);
    for s in &signals {
        spectra.push(welch_orders(s, spr, req.segment_revolutions as usize)?);
        decs.push(decompose(s, o)?);
    }
    let mut ind = Vec::with_capacity(3);
    let mut frac = [0.0; 3];
    for k in 0..3 {
        let prior: Vec<&Decomposition> = run.iter().map(|p| &p.decompositions[k]).collect();
        ind.push(indicators(&signals[k], &decs[k], o, &prior));
        frac[k] = decs[k].difference_fraction();
    }
    Ok(PairSignals {
        pair: name.into(),
        start: start.into(),
        tau: raw.tau,
        motion: MotionContext::of(&raw.summary, raw.per_rev, req.revolutions),
        signals,
        spectra: arr(spectra),
        decompositions: arr(decs),
        indicators: arr(ind),
        difference_fraction: frac,
    })
}

/// Records the scenario's pair and its healthy twin ([`Scenario::healthy`]) from the same
/// initial state at the same operating point, and reads their signals, spectra and indicators.
///
/// **Like with like.** The healthy twin is recorded twice: from the initial state and from the
/// broken pair's final state (same phase of the revolution: the chip removed from the broken
/// pair's motion). When both records are on one attractor ([`MotionContext::like`]) the healthy
/// pair has one attractor in play and the record from the initial state is compared (a change of
/// class is then the chip's doing, and a note says so). When they differ (coexisting healthy
/// attractors), the one on the broken pair's class is compared, the restarted one first
/// (`start` says which); when neither is, [`SignalsResult::comparable`] is false.
///
/// Without a broken tooth only the healthy pair is recorded (a note says so).
pub fn run_signals(sc: &Scenario, req: &SignalsRequest) -> Result<SignalsResult, SignalsError> {
    let scales = req.check(sc)?;
    let o = req.indicator_options(scales.z1);
    let broken = sc.params().breakage.is_some();
    let healthy_sc = if broken { sc.healthy()? } else { sc.clone() };
    let start = (req.tau0, req.y0);
    let mut notes = Vec::new();
    let (b_raw, h_raw) = if broken {
        let (b, h) = rayon::join(
            || record(sc.model(), scales.z1, req, start),
            || record(healthy_sc.model(), scales.z1, req, start),
        );
        (Some(b?), h?)
    } else {
        notes.push(
            "no broken tooth in this configuration (pair.breakage is not set): only the healthy pair is recorded".into(),
        );
        (None, record(sc.model(), scales.z1, req, start)?)
    };
    let mut h_raw = h_raw;
    let mut h_start = "initial state";
    let mut comparable = true;
    if let Some(b) = &b_raw {
        let ctx = |r: &Raw| MotionContext::of(&r.summary, r.per_rev, req.revolutions);
        // the healthy twin again, from the broken pair's final state (the chip removed from the
        // broken pair's motion): does the healthy pair have one attractor here, or several?
        let again = record(healthy_sc.model(), scales.z1, req, b.end)?;
        let (cb, c1, c2) = (ctx(b), ctx(&h_raw), ctx(&again));
        if c1.like(&c2) {
            notes.push(format!(
                "both pairs from the same initial state; the healthy twin moves alike from it ({}) and from the broken pair's final state ({}): one healthy attractor in play; broken pair {}",
                c1.text(), c2.text(), cb.text()
            ));
            if cb.class != c1.class {
                notes.push(format!(
                    "the chip changes the attractor class: broken pair '{}', healthy twin '{}'",
                    cb.class, c1.class
                ));
            }
        } else if c2.class == cb.class {
            notes.push(format!(
                "coexisting healthy attractors: from the initial state the healthy twin moves as {}, from the broken pair's final state as {}; the latter, on the broken pair's class ({}), is compared (like with like)",
                c1.text(), c2.text(), cb.text()
            ));
            h_raw = again;
            h_start = "broken pair's final state";
        } else if c1.class == cb.class {
            notes.push(format!(
                "coexisting healthy attractors: from the initial state the healthy twin moves as {}, from the broken pair's final state as {}; the former, on the broken pair's class ({}), is compared (like with like)",
                c1.text(), c2.text(), cb.text()
            ));
        } else {
            comparable = false;
            notes.push(format!(
                "coexisting healthy attractors ({} from the initial state, {} from the broken pair's final state), neither on the broken pair's class ({}): the pairs differ in attractor, not only in the chip",
                c1.text(), c2.text(), cb.text()
            ));
        }
    }
    let healthy = process("healthy", h_start, h_raw, &scales, req, &o, None)?;
    let mut pairs = Vec::with_capacity(2);
    if let Some(b) = b_raw {
        let run = match req.na4_reference {
            Na4Reference::Run => Some(&healthy),
            Na4Reference::Own => None,
        };
        let bp = process("broken", "initial state", b, &scales, req, &o, run)?;
        pairs.push(healthy);
        pairs.push(bp);
    } else {
        pairs.push(healthy);
    }
    Ok(SignalsResult {
        scales,
        samples_per_rev: o.samples_per_rev,
        revolutions: req.revolutions,
        pairs,
        broken,
        comparable,
        notes,
        orders: o.orders(),
        options: o,
        na4_reference: req.na4_reference,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_configuration_without_a_pair_is_refused_by_name() {
        let sc = geardyn_scenario::ScenarioSpec::preset("classic")
            .unwrap()
            .resolve()
            .unwrap();
        let e = run_signals(&sc, &SignalsRequest::default()).unwrap_err();
        assert!(e.to_string().contains("[pair]"), "{e}");
    }

    #[test]
    fn settings_out_of_range_are_named() {
        let sc = geardyn_scenario::ScenarioSpec::preset("breakage")
            .unwrap()
            .resolve()
            .unwrap();
        for (req, field) in [
            (
                SignalsRequest {
                    revolutions: 1,
                    ..Default::default()
                },
                "revolutions",
            ),
            (
                SignalsRequest {
                    samples_per_cycle: 2,
                    ..Default::default()
                },
                "samples_per_cycle",
            ),
            (
                SignalsRequest {
                    segment_revolutions: 17,
                    ..Default::default()
                },
                "segment_revolutions",
            ),
            (
                SignalsRequest {
                    y0: [f64::NAN, 0.0],
                    ..Default::default()
                },
                "y0",
            ),
        ] {
            let e = req.check(&sc).unwrap_err();
            assert!(e.to_string().contains(field), "{e}");
        }
    }
}
