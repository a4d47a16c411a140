//! Vibration signals of a planetary stage as a fixed transducer sees them, and their spectra in
//! orders of the carrier (docs/analyses.md, "Signals of a planetary stage").
//!
//! **The transducer** sits on the fixed ring at angle 0. Each ring–planet mesh force reaches it
//! through the ring, weighed by the planet's angular distance `phi` from it: the transfer window
//! `w(phi) = (1 + cos phi) / 2` (1 with the planet under the transducer, 0 opposite it; a Hann
//! window over the circle, the form McFadden & Smith 1985 and Inalpolat & Kahraman 2009 use).
//! The planets ride the carrier: planet `i` is at `phi_i = psi_i - 2 pi c(tau)` with `c` the
//! carrier's revolutions — the carrier turns opposite to the sense in which the meshes' phases
//! count the orbit angles `psi` (the sense the ring turns relative to the carrier, see
//! `geardyn_train::fault`). The signal is `sum_i F_ring,i(tau) w(phi_i(tau))`, dimensionless
//! (units `k_ref b_c`, like every mesh force of a train). Beside it: the **sun torque** `sum_i
//! F_sun,i` (per unit base radius: every sun mesh acts at the sun's base radius), which a torque
//! transducer on the input shaft reads.
//!
//! **The record** is a whole number of carrier revolutions and of excitation periods, so that a
//! periodic motion gives lines on the grid of orders exactly (no window, no leakage): the
//! amplitude of carrier order `j / R` of an `R`-revolution record is bin `j` of its Fourier
//! transform ([`crate::spectrum::line_amplitudes`]). Two properties hold exactly for a
//! cyclically symmetric stage (identical, equally spaced planets) and test the phasing: the
//! transducer sees only orders that are multiples of the number of planets (McFadden & Smith
//! 1985: the mesh order `Z_r` itself vanishes unless `N` divides it), and a chipped sun tooth's
//! signature in the sun torque lies on multiples of its characteristic order `N Z_r / Z_s`
//! carrier orders (the tooth meets a planet `N` times per turn of the sun relative to the
//! carrier).

use crate::driver::{run_periods, Discard, Observer};
use crate::simulate::Method;
use crate::spectrum::line_amplitudes;
use geardyn_model::GearSystem;
use geardyn_solvers::{Integrator, Step, Stop};
use geardyn_train::dynamics::TrainModel;
use geardyn_train::kinematics::Kinematics;
use geardyn_train::TrainSpec;
use serde::Serialize;
use std::f64::consts::TAU;

/// Most excitation periods a record may need to close on whole carrier revolutions.
const MAX_RECORD_PERIODS: u64 = 10_000;
/// Most samples of a record.
const MAX_SAMPLES: u64 = 20_000_000;

/// Settings of a stage's signals.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct StageSignalsRequest {
    /// Carrier revolutions discarded first (rounded up to whole excitation periods).
    pub transient_revolutions: u64,
    /// Records of whole carrier revolutions and excitation periods (the record is this many
    /// times the shortest such span).
    pub records: u64,
    /// Samples per cycle of mesh 0; 0: the least multiple of the number of planets from 16 up.
    /// A multiple of it makes the planets' samples shifted copies of each other (planet `i` is
    /// planet 0 delayed by `i Z_r / N` or `i Z_s / N` mesh cycles), so that the cancellations
    /// above hold in the sampled signal too; the rectangular stiffness's harmonics above half the
    /// sampling rate alias onto lower orders.
    pub samples_per_cycle: u32,
    /// Integrator.
    pub method: Method,
    /// Period of the motion in excitation periods (from its decision; 1 when not periodic): the
    /// record holds whole periods of it, so that its lines fall on the grid too.
    pub motion_periods: u64,
}

impl Default for StageSignalsRequest {
    /// 5 carrier revolutions of transient, one record, samples per mesh cycle from the planet
    /// count, Dormand–Prince.
    fn default() -> Self {
        StageSignalsRequest {
            transient_revolutions: 5,
            records: 1,
            samples_per_cycle: 0,
            method: Method::default(),
            motion_periods: 1,
        }
    }
}

/// The signals of a stage and their spectra.
#[derive(Clone, Debug, Serialize)]
pub struct StageSignals {
    /// Carrier revolutions recorded (`R`).
    pub carrier_revolutions: f64,
    /// Excitation periods recorded.
    pub periods: u64,
    /// Planets.
    pub planets: usize,
    /// The ring's mesh order in carrier orders (`Z_r` with the ring fixed).
    pub mesh_order: f64,
    /// A faulted gear's characteristic order in carrier orders (its tooth's meshings per carrier
    /// revolution), if the train has a fault.
    pub fault_order: Option<f64>,
    /// Sample times (dimensionless).
    pub tau: Vec<f64>,
    /// Carrier revolutions at each sample (from `tau = 0`).
    pub carrier: Vec<f64>,
    /// The ring transducer's signal.
    pub sensor: Vec<f64>,
    /// The sun torque (sum of the sun's mesh forces).
    pub sun_torque: Vec<f64>,
    /// Carrier orders of the spectra's bins (`j / R`).
    pub orders: Vec<f64>,
    /// Amplitude spectrum of `sensor`.
    pub sensor_spectrum: Vec<f64>,
    /// Amplitude spectrum of `sun_torque`.
    pub sun_spectrum: Vec<f64>,
}

/// Where the stage's parts are: ring meshes with their planets' orbit angles, sun meshes.
struct Layout {
    ring: Vec<(usize, f64)>,
    sun: Vec<usize>,
    carrier: usize,
}

fn layout(spec: &TrainSpec) -> Result<Layout, String> {
    let fixed = |b: &str| {
        spec.supports
            .iter()
            .any(|s| s.body == b && s.stiffness_nm_per_rad.is_none())
    };
    let mut ring = Vec::new();
    let mut sun = Vec::new();
    let mut carrier = None;
    for (k, m) in spec.meshes.iter().enumerate() {
        let Some(c) = m.carrier.as_deref() else {
            continue;
        };
        carrier = spec.body_index(c);
        let planet = m
            .gears
            .iter()
            .filter_map(|g| spec.body_index(g))
            .find(|&b| spec.bodies[b].carrier.is_some());
        let Some(p) = planet else { continue };
        let psi = spec.bodies[p].orbit_angle_deg.to_radians();
        let other = m.gears.iter().find(|g| **g != spec.bodies[p].name);
        if m.is_internal() {
            if other.is_some_and(|g| fixed(g)) {
                ring.push((k, psi));
            }
        } else {
            sun.push(k);
        }
    }
    match carrier {
        Some(carrier) if !ring.is_empty() => Ok(Layout { ring, sun, carrier }),
        _ => Err("the transducer sits on a fixed ring: the train has no planets meshing with a held ring (a planetary stage with its ring supported without stiffness)".into()),
    }
}

/// Uniform samples of every mesh force.
struct Sampler<'a, S> {
    sys: &'a S,
    origin: f64,
    dt: f64,
    next: u64,
    count: u64,
    tau: Vec<f64>,
    forces: Vec<Vec<f64>>,
}

impl<S: GearSystem<N>, const N: usize> Observer<S, N> for Sampler<'_, S> {
    fn on_step(
        &mut self,
        _sys: &S,
        step: &Step<N>,
        before: &S::Mode,
        _stop: Stop,
        _after: &S::Mode,
        _y_after: &[f64; N],
    ) {
        while self.next < self.count {
            // (mid-sample times: a sample on a zone border would take either side's stiffness)
            let t = self.origin + (self.next as f64 + 0.5) * self.dt;
            if t > step.t1 {
                break;
            }
            let y = step.interpolate(t);
            self.tau.push(t);
            for (k, f) in self.forces.iter_mut().enumerate() {
                f.push(self.sys.mesh_force(t, &y, before, k));
            }
            self.next += 1;
        }
    }
}

/// The stage's transducer and sun-torque signals over whole carrier revolutions after a
/// transient from `start` (time, state), and their spectra.
pub fn stage_signals<const N: usize>(
    spec: &TrainSpec,
    model: &TrainModel<N>,
    start: (f64, [f64; N]),
    req: &StageSignalsRequest,
) -> Result<StageSignals, String>
where
    TrainModel<N>: GearSystem<N>,
{
    let lay = layout(spec)?;
    let kin = Kinematics::of(spec).map_err(|e| e.to_string())?;
    let r_c = kin.ratios[lay.carrier];
    // mesh-0 cycles per carrier revolution
    let per_rev = kin.mesh_orders[0] / r_c;
    let cycles = f64::from(model.cycles_per_period());
    let periods = (1..=MAX_RECORD_PERIODS)
        .map(|p| p * req.motion_periods.max(1))
        .find(|&p| {
            let r = p as f64 * cycles / per_rev;
            (r - r.round()).abs() < 1e-9 * r.max(1.0)
        })
        .ok_or_else(|| {
            format!("a record of whole carrier revolutions: {per_rev} mesh cycles per carrier revolution and {cycles} per excitation period have no common multiple within {MAX_RECORD_PERIODS} periods")
        })?
        * req.records.max(1);
    let n = lay.ring.len() as u64;
    let spc = match u64::from(req.samples_per_cycle) {
        0 => n * 16_u64.div_ceil(n),
        s if s >= 2 * n && s % n == 0 => s,
        s => {
            return Err(format!(
                "--samples-per-cycle {s}: a multiple of the {n} planets from {} up (the planets' samples are then shifted copies of each other), or 0 for {}",
                2 * n,
                n * 16_u64.div_ceil(n)
            ))
        }
    };
    let count = periods * model.cycles_per_period() as u64 * spc;
    if count > MAX_SAMPLES {
        return Err(format!(
            "--samples-per-cycle {spc}: the record of {periods} excitation periods would hold {count} samples (at most {MAX_SAMPLES}: up to {} per mesh cycle)",
            MAX_SAMPLES / (periods * model.cycles_per_period() as u64)
        ));
    }
    let mut integ = Integrator::new(model, req.method.scheme(model), start.0, start.1)
        .map_err(|e| e.to_string())?;
    let period = model.excitation_period();
    let transient = (req.transient_revolutions as f64 * per_rev / cycles).ceil() as u64;
    run_periods(&mut integ, period, transient, &mut Discard).map_err(|e| e.to_string())?;
    let origin = integ.t();
    let dt = model.mesh_cycle_time() / spc as f64;
    let mut s = Sampler {
        sys: &model,
        origin,
        dt,
        next: 0,
        count,
        tau: Vec::with_capacity(count as usize),
        forces: vec![Vec::with_capacity(count as usize); model.mesh_count()],
    };
    run_periods(&mut integ, period, periods, &mut s).map_err(|e| e.to_string())?;
    if (s.tau.len() as u64) < count {
        return Err(format!(
            "the record took {} of {count} samples",
            s.tau.len()
        ));
    }
    let omega0 = TAU / model.mesh_cycle_time();
    let carrier: Vec<f64> = s.tau.iter().map(|t| omega0 * t / TAU / per_rev).collect();
    let sensor: Vec<f64> = (0..s.tau.len())
        .map(|j| {
            lay.ring
                .iter()
                .map(|&(k, psi)| {
                    let phi = psi - TAU * carrier[j];
                    s.forces[k][j] * 0.5 * (1.0 + phi.cos())
                })
                .sum()
        })
        .collect();
    let sun_torque: Vec<f64> = (0..s.tau.len())
        .map(|j| lay.sun.iter().map(|&k| s.forces[k][j]).sum())
        .collect();
    // (whole by the choice of `periods`)
    let revs = (periods as f64 * cycles / per_rev).round();
    let sensor_spectrum = line_amplitudes(&sensor);
    let sun_spectrum = line_amplitudes(&sun_torque);
    let orders = (0..sensor_spectrum.len())
        .map(|j| j as f64 / revs)
        .collect();
    let ring_mesh = lay.ring[0].0;
    let fault_order = spec.fault.as_ref().and_then(|f| {
        spec.body_index(&f.gear)
            .map(|g| kin.fault_order(spec, g) / r_c)
    });
    Ok(StageSignals {
        carrier_revolutions: revs,
        periods,
        planets: lay.ring.len(),
        mesh_order: kin.mesh_orders[ring_mesh] / r_c,
        fault_order,
        tau: s.tau,
        carrier,
        sensor,
        sun_torque,
        orders,
        sensor_spectrum,
        sun_spectrum,
    })
}
