//! The nonlinear dynamic model of a train: every mesh with its backlash, time-varying stiffness
//! and contact state, in the train's elastic coordinates, as a [`GearSystem`] every analysis of
//! geardyn runs on.
//!
//! **Coordinates.** The bodies' rotations are `q = Omega t + P z`: the kinematic rotation at
//! constant input speed plus the deflection `z`, expanded on the elastic modes of the
//! mean-stiffness train ([`crate::modes`]), normalised so that `Pᵀ M P = m_ref I`. The rigid-body
//! motion drops out exactly: no mesh, shaft or support deflects along it and the input and
//! output torques do no net work on it (power balance), so it is not a coordinate. `m_ref` is
//! the equivalent mass of mesh 0 (`1 / sum_j a_0j² / I_j`), `k_ref` its mean stiffness; time is
//! `tau = omega_ref t`, `omega_ref = sqrt(k_ref / m_ref)`, and lengths are in units of `b_c`.
//! For a single pair this is exactly the pair model of `geardyn_model` (docs/model.md).
//!
//! **Equations** (dimensionless; state `y = [x, x']`, `x` of the train's elastic degrees of
//! freedom):
//!
//! `x'' + C_s x' + K_s x + sum_k b_k f_k = F`,
//!
//! with, per mesh `k`: the deflection `delta_k = b_k · x - e_k(tau)` (`b_k = Pᵀ a_k`, `a_k` the
//! mesh's coefficients, [`crate::linear::mesh_coefficients`]; `e_k = xi cos(theta_k)` the static
//! transmission error), the phase `theta_k = omega_k tau + 2 pi phi_k` (`omega_k` the mesh's
//! frequency, `phi_k` its phase from the geometry), the contact force `f_k = kappa_k k_k(tau)
//! g(delta_k) + c sqrt(kappa_k) delta_k'` in drive-side (`delta_k >= D`, `g = delta_k - D`) or
//! back-side contact (`delta_k <= -D`, `g = delta_k + D`) and 0 when separated; `kappa_k` the
//! mesh's mean stiffness over `k_ref`; `k_k(tau)` its relative stiffness (mean 1):
//! `1 + kappa cos(theta_k)` or a rectangular wave of its contact ratio `eps_k` (`k_double` on
//! the double-tooth part `[0, eps_k - 1)` of each mesh cycle, `k_double / k_single` given).
//! Shafts and elastic supports: `K_s = Pᵀ K_shafts P / k_ref`, damped in proportion,
//! `C_s = c K_s`. The load `F = Pᵀ T / (k_ref b_c)` is scaled so that mesh 0 carries the
//! static force `load` (units `k_ref b_c`) at mean stiffness.
//!
//! A localized tooth fault (a chipped sun tooth, say) softens each mesh of its gear while the
//! faulted tooth is in contact ([`crate::fault`]): more time breakpoints, and an excitation
//! period of whole turns of that gear.
//!
//! **Not in this model** (the single pair's model has them): back-side impacts with
//! restitution (trains use the continuous back-side contact), friction, nonlinear Hertz laws,
//! and the pair's potential-energy stiffness tables (trains take a harmonic or rectangular
//! stiffness of each mesh's contact ratio, and a fault's loss as a number).

use crate::description::TrainSpec;
use crate::kinematics::Kinematics;
use crate::linear::{mesh_coefficients, LinearModel};
use crate::TrainError;
use geardyn_model::{ContactState, EventKind, GearSystem};
use geardyn_solvers::{Direction, EventAction, Guards, HybridSystem, Variational};
use std::f64::consts::TAU;

pub use crate::operating::{MeshStiffness, TrainOperating};

/// Distance to its surface (relative to `max(D, 1)`) at which a mesh crosses together with the
/// mesh whose event is being handled.
const SIMULTANEOUS: f64 = 1e-9;
/// Most meshes a train's dynamic model holds (11 planets: 22 meshes).
pub const MAX_MESHES: usize = 24;
/// Longest excitation period in mesh-0 cycles: the meshes' frequencies must have a common period
/// within it.
pub const MAX_CYCLES: u32 = 1000;

/// Per-mesh constants.
#[derive(Clone, Debug)]
struct MeshDyn {
    /// `b_k` (length `dof`).
    b: Vec<f64>,
    /// Mean stiffness over `k_ref`.
    kappa: f64,
    /// Damping `c sqrt(kappa_k)`.
    damping: f64,
    /// Frequency over mesh 0's.
    rate: f64,
    /// Phase (mesh cycles).
    phase: f64,
    /// Double-tooth part of a cycle, `eps_k - 1`.
    double: f64,
    /// When the faulted tooth is in contact, if the mesh has it.
    fault: Option<crate::fault::FaultWindow>,
    /// Static offset of the deflection from a planet's pin error (units `b_c`; 0 without).
    offset: f64,
}

/// The discrete state: each mesh's contact, which meshes are in their double-tooth part, and
/// the start of the current time piece.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrainMode {
    contact: [ContactState; MAX_MESHES],
    double: u32,
    /// Meshes whose faulted tooth carries the load alone, and those where it shares it.
    chip_full: u32,
    chip_half: u32,
    piece_start: f64,
}

/// Per mesh `cos` and `sin` of its phase `theta_k` at one time.
#[derive(Clone, Copy, Debug)]
pub struct TrainTime {
    cos: [f64; MAX_MESHES],
    sin: [f64; MAX_MESHES],
}

/// A train's dynamic model of state dimension `N`: `[x, x']` of its `dof` elastic coordinates,
/// `x` in `y[..dof]` and `x'` in `y[N / 2..N / 2 + dof]`.
///
/// `N` may exceed `2 dof`: the components in between are padding that stays exactly zero (they
/// decay at the train's fastest natural rate, so a tangent vector in them never dominates an
/// exponent) and the integrator's error norm counts only the `2 dof` that move
/// ([`HybridSystem::active_dim`]), so a padded model steps exactly as an unpadded one. A front end
/// then compiles the analyses for a few sizes instead of one per train size.
#[derive(Clone, Debug)]
pub struct TrainModel<const N: usize> {
    names: Vec<String>,
    /// Elastic degrees of freedom (`2 dof <= N`).
    dof: usize,
    /// Decay rate of the padding (the fastest natural frequency, dimensionless).
    pad_rate: f64,
    meshes: Vec<MeshDyn>,
    op: TrainOperating,
    /// `K_s` and `C_s` (row-major, `dof x dof`).
    k_s: Vec<f64>,
    c_s: Vec<f64>,
    /// `F` (length `dof`).
    force: Vec<f64>,
    /// Mesh-0 cycles per excitation period.
    cycles: u32,
    /// Shortest natural period (dimensionless).
    natural_period: f64,
    /// `omega_ref` (rad/s) and mesh 0's tooth passes per input revolution: the physical speed.
    omega_ref: f64,
    order0: f64,
    /// The elastic modes' natural frequencies over `omega_ref`.
    frequencies: Vec<f64>,
    /// Static mesh forces at mean stiffness (units `k_ref b_c`).
    static_forces: Vec<f64>,
    /// The static deflection with every mesh in drive contact at mean stiffness.
    static_x: Vec<f64>,
    /// Whether the meshes' phases enter the field (a transmission error or a harmonic
    /// stiffness): else no trigonometry is evaluated.
    needs_phase: bool,
    /// Whether shafts or supports add stiffness.
    has_shafts: bool,
    /// The tooth fault's stiffness loss (0: none).
    loss: f64,
}

/// Elastic degrees of freedom of a train (its coordinates less its rigid-body motions).
pub fn elastic_dof(spec: &TrainSpec) -> usize {
    crate::Modes::of(spec)
        .modes
        .iter()
        .filter(|m| m.kind != crate::ModeKind::RigidBody)
        .count()
}

/// The common period of the rates `r` in cycles of rate 1: the least `p <= MAX_CYCLES` with every
/// `p r_k` whole.
fn common_cycles(rates: &[f64]) -> Option<u32> {
    (1..=MAX_CYCLES).find(|&p| {
        rates.iter().all(|r| {
            let x = f64::from(p) * r;
            (x - x.round()).abs() <= 1e-9 * x.abs().max(1.0)
        })
    })
}

/// The elastic basis of a train: `P` (coordinates x elastic modes of the mean-stiffness train,
/// lowest first) with `Pᵀ M P = m_ref I`, `m_ref` the equivalent mass of mesh 1 and `k_ref` its
/// mean stiffness. `state` must be twice the number of elastic modes.
struct Basis {
    p: nalgebra::DMatrix<f64>,
    m_ref: f64,
    k_ref: f64,
}

fn elastic_basis(spec: &TrainSpec, lin: &LinearModel, state: usize) -> Result<Basis, TrainError> {
    let n = lin.len();
    let inv_sqrt: Vec<f64> = lin.mass.iter().map(|m| 1.0 / m.sqrt()).collect();
    let a = nalgebra::DMatrix::from_fn(n, n, |i, j| {
        lin.stiffness[(i, j)] * inv_sqrt[i] * inv_sqrt[j]
    });
    let a = (&a + a.transpose()) * 0.5;
    let eig = a.symmetric_eigen();
    let mut elastic: Vec<usize> = (0..n).collect();
    elastic.sort_by(|&i, &j| eig.eigenvalues[i].total_cmp(&eig.eigenvalues[j]));
    let rigid = crate::modes::rigid_modes(spec, eig.eigenvalues.as_slice());
    let elastic: Vec<usize> = elastic.split_off(rigid.min(n));
    let dof = elastic.len();
    if 2 * dof > state {
        return Err(crate::error::invalid(
            "state dimension",
            state,
            format!("at least 2 x {dof} (the train's elastic degrees of freedom)"),
        ));
    }
    let a0 = mesh_coords(spec, lin, &spec.meshes[0]);
    let m_ref = 1.0 / (0..n).map(|i| a0[i] * a0[i] / lin.mass[i]).sum::<f64>();
    let p = nalgebra::DMatrix::from_fn(n, dof, |i, j| {
        inv_sqrt[i] * eig.eigenvectors[(i, elastic[j])] * m_ref.sqrt()
    });
    Ok(Basis {
        p,
        m_ref,
        k_ref: spec.meshes[0].stiffness_n_per_m,
    })
}

/// A mesh's deflection coefficients over the linear model's coordinates (m/rad).
fn mesh_coords(spec: &TrainSpec, lin: &LinearModel, m: &crate::Mesh) -> Vec<f64> {
    let mut v = vec![0.0; lin.len()];
    for (b, c) in mesh_coefficients(spec, m) {
        if let Some(d) = lin.bodies.iter().position(|&x| x == b) {
            v[d] += c;
        }
    }
    v
}

/// Shafts and elastic supports in the elastic coordinates, `K_s = Pᵀ K_shafts P / k_ref`
/// (row-major): the mean stiffness less the meshes'.
fn shaft_matrix(spec: &TrainSpec, lin: &LinearModel, basis: &Basis) -> Vec<f64> {
    let n = lin.len();
    let mut ks_full = lin.stiffness.clone();
    for m in &spec.meshes {
        let a = mesh_coords(spec, lin, m);
        for i in 0..n {
            for j in 0..n {
                ks_full[(i, j)] -= m.stiffness_n_per_m * a[i] * a[j];
            }
        }
    }
    let projected = basis.p.transpose() * ks_full * &basis.p / basis.k_ref;
    let dof = basis.p.ncols();
    let mut k_s = vec![0.0; dof * dof];
    for r in 0..dof {
        for c in 0..dof {
            k_s[r * dof + c] = projected[(r, c)];
        }
    }
    k_s
}

/// The static equilibrium at mean stiffness under the load `force` with half backlash `d`: the
/// state and each mesh's force. Every mesh is on its drive flank or separated: a mesh whose
/// force would be negative lets go and one whose gap closes takes load again (an active set,
/// changed one mesh at a time until it holds). A separated mesh keeps a residual stiffness, the
/// same for every mesh (`1e-9` of the mean), so that a body only separated meshes hold (an
/// unloaded planet) sits in the middle of its free play, its meshes' gaps equal; the residual's
/// force is refined away. Forces below `1e-12` of the largest are 0.
fn static_equilibrium(
    meshes: &[MeshDyn],
    k_s: &[f64],
    force: &[f64],
    d: f64,
) -> Result<(Vec<f64>, Vec<f64>), TrainError> {
    let dof = force.len();
    let soft = 1e-9 * meshes.iter().map(|m| m.kappa).sum::<f64>() / meshes.len().max(1) as f64;
    let mut active = vec![true; meshes.len()];
    for _ in 0..=4 * meshes.len() + 4 {
        // each mesh's stiffness in this active set
        let w = |k: usize| {
            if active[k] {
                meshes[k].kappa
            } else {
                soft
            }
        };
        let k_mat = nalgebra::DMatrix::from_fn(dof, dof, |r, s| {
            k_s[r * dof + s]
                + meshes
                    .iter()
                    .enumerate()
                    .map(|(k, m)| w(k) * m.b[r] * m.b[s])
                    .sum::<f64>()
        });
        let rhs = nalgebra::DVector::from_fn(dof, |r, _| {
            force[r]
                + meshes
                    .iter()
                    .enumerate()
                    .map(|(k, m)| w(k) * m.b[r] * (d - m.offset))
                    .sum::<f64>()
        });
        let lu = k_mat.lu();
        let mut x = lu
            .solve(&rhs)
            .ok_or_else(|| TrainError::Kinematics("the mean-stiffness train is singular".into()))?;
        if active.iter().any(|a| !a) {
            // the separated meshes' residual stiffness fixes only what nothing else holds: a few
            // refinements take its force out of the equilibrium (to 1e-9 each)
            for _ in 0..3 {
                let held = nalgebra::DVector::from_fn(dof, |r, _| {
                    rhs[r]
                        + meshes
                            .iter()
                            .enumerate()
                            .filter(|(k, _)| !active[*k])
                            .map(|(_, m)| {
                                let bx: f64 = m.b.iter().zip(x.iter()).map(|(b, x)| b * x).sum();
                                soft * m.b[r] * (bx - (d - m.offset))
                            })
                            .sum::<f64>()
                });
                x = lu.solve(&held).unwrap_or(x);
            }
        }
        // each mesh's deflection beyond its drive flank
        let gap: Vec<f64> = meshes
            .iter()
            .map(|m| m.b.iter().zip(x.iter()).map(|(b, x)| b * x).sum::<f64>() + m.offset - d)
            .collect();
        let scale = force
            .iter()
            .fold(d.abs(), |a, f| a.max(f.abs()))
            .max(1e-300);
        // (a mesh that touches without load lets go too: a planet only it would hold then floats
        // to the middle of its free play; taking load again needs a clear overlap, so the set
        // cannot cycle between the two)
        let release = (0..meshes.len())
            .filter(|&k| active[k] && gap[k] < 1e-9 * scale)
            .min_by(|&a, &b| gap[a].total_cmp(&gap[b]));
        let engage = (0..meshes.len())
            .filter(|&k| !active[k] && gap[k] > 1e-6 * scale)
            .max_by(|&a, &b| gap[a].total_cmp(&gap[b]));
        match (release, engage) {
            (Some(k), _) => active[k] = false,
            (None, Some(k)) => active[k] = true,
            (None, None) => {
                let mut forces: Vec<f64> = meshes
                    .iter()
                    .enumerate()
                    .map(|(k, m)| if active[k] { m.kappa * gap[k] } else { 0.0 })
                    .collect();
                // a mesh that touches without load (a planet that just lets go) carries 0
                let largest = forces.iter().fold(0.0f64, |a, f| a.max(f.abs()));
                forces
                    .iter_mut()
                    .filter(|f| f.abs() <= 1e-12 * largest)
                    .for_each(|f| *f = 0.0);
                return Ok((x.iter().copied().collect(), forces));
            }
        }
    }
    Err(TrainError::Kinematics(
        "no static equilibrium of the meshes' contacts was found".into(),
    ))
}

/// The deflection offset of mesh `m` (units `b_c`, the description's sign) from the pin error
/// of the planet it meshes with: for that planet's meshes the error is a carrier rotation of
/// `pin_error / orbit_radius`, so the offset is the mesh's carrier coefficient times it
/// (`-cos alpha' pin_error` on a sun–planet mesh of operating pressure angle `alpha'`).
fn pin_offset(spec: &TrainSpec, m: &crate::Mesh) -> f64 {
    let Some(carrier) = &m.carrier else {
        return 0.0;
    };
    let planet = m
        .gears
        .iter()
        .filter_map(|g| spec.body_index(g).map(|i| &spec.bodies[i]))
        .find(|b| b.carrier.as_ref() == Some(carrier));
    let (Some(planet), Some(ci)) = (planet, spec.body_index(carrier)) else {
        return 0.0;
    };
    if planet.pin_error == 0.0 {
        return 0.0;
    }
    let coefficient = crate::linear::mesh_coefficients(spec, m)
        .into_iter()
        .find(|c| c.0 == ci)
        .map_or(0.0, |c| c.1);
    coefficient / (planet.orbit_radius_mm * 1e-3) * planet.pin_error
}

impl<const N: usize> TrainModel<N> {
    /// The model of a validated train at `op` (`N` at least twice [`elastic_dof`]).
    pub fn new(spec: &TrainSpec, op: &TrainOperating) -> Result<Self, TrainError> {
        op.validate()?;
        let kin = Kinematics::of(spec)?;
        let lin = LinearModel::of(spec);
        let n = lin.len();
        let nm = spec.meshes.len();
        if nm > MAX_MESHES {
            return Err(crate::error::invalid(
                "mesh",
                nm,
                format!("at most {MAX_MESHES} meshes"),
            ));
        }
        let basis = elastic_basis(spec, &lin, N)?;
        let (dof, m_ref, k_ref) = (basis.p.ncols(), basis.m_ref, basis.k_ref);
        let omega_ref = (k_ref / m_ref).sqrt();
        let coords = |m: &crate::Mesh| mesh_coords(spec, &lin, m);
        let p = |i: usize, j: usize| basis.p[(i, j)];
        let project = |v: &[f64]| -> Vec<f64> {
            (0..dof)
                .map(|j| (0..n).map(|i| p(i, j) * v[i]).sum())
                .collect()
        };
        let eps_of = |m: &crate::Mesh| m.contact_ratio;
        let windows = crate::fault::windows(spec)?;
        let order0 = kin.mesh_orders[0];
        let meshes: Vec<MeshDyn> = spec
            .meshes
            .iter()
            .zip(&kin.mesh_orders)
            .zip(&windows)
            .map(|((m, &order), &fault)| {
                let kappa = m.stiffness_n_per_m / k_ref;
                MeshDyn {
                    b: project(&coords(m)),
                    kappa,
                    damping: op.c * kappa.sqrt(),
                    rate: order / order0,
                    phase: m.phase,
                    double: eps_of(m) - 1.0,
                    fault,
                    offset: 0.0,
                }
            })
            .collect();
        // (a faulted mesh repeats after its gear's teeth: the period holds whole turns of it)
        let rates: Vec<f64> = meshes
            .iter()
            .map(|m| m.rate / m.fault.map_or(1.0, |f| f.period))
            .collect();
        let cycles = common_cycles(&rates).ok_or_else(|| {
            crate::error::invalid(
                "mesh",
                format!("{rates:?}"),
                format!("mesh frequencies with a common period of at most {MAX_CYCLES} cycles of mesh 0 (their tooth counts' ratios)"),
            )
        })?;
        let k_s = shaft_matrix(spec, &lin, &basis);
        let c_s: Vec<f64> = k_s.iter().map(|k| op.c * k).collect();
        // the load: input torque +1, output torque balancing its power
        let input = spec.body_index(&spec.load.input).expect("validated");
        let output = spec.body_index(&spec.load.output).expect("validated");
        let mut torque = vec![0.0; n];
        for (d, &b) in lin.bodies.iter().enumerate() {
            if b == input {
                torque[d] = 1.0;
            } else if b == output {
                torque[d] = -1.0 / kin.ratios[output];
            }
        }
        let f_unit = project(&torque);
        // static deflection at mean stiffness: (sum kappa b bᵀ + K_s) x = f_unit
        let k_mean = nalgebra::DMatrix::from_fn(dof, dof, |r, s| {
            k_s[r * dof + s]
                + meshes
                    .iter()
                    .map(|m| m.kappa * m.b[r] * m.b[s])
                    .sum::<f64>()
        });
        let x_s = k_mean
            .clone()
            .lu()
            .solve(&nalgebra::DVector::from_vec(f_unit.clone()))
            .ok_or_else(|| TrainError::Kinematics("the mean-stiffness train is singular".into()))?;
        // each mesh's drive flank is the one the input torque loads: a mesh loaded on the other
        // side under the description's sign convention (the second stage of a drive turns the
        // other way) is turned round
        let mut meshes = meshes;
        for (m, spec_mesh) in meshes.iter_mut().zip(&spec.meshes) {
            let f: f64 = (0..dof).map(|j| m.b[j] * x_s[j]).sum();
            let sign = if f < 0.0 { -1.0 } else { 1.0 };
            if f < 0.0 {
                m.b.iter_mut().for_each(|b| *b = -*b);
            }
            m.offset = sign * pin_offset(spec, spec_mesh);
        }
        let f0: f64 = meshes[0].kappa * (0..dof).map(|j| meshes[0].b[j] * x_s[j]).sum::<f64>();
        if !(f0.abs() > 0.0 && f0.is_finite()) {
            return Err(TrainError::Kinematics(
                "no load path: the input torque loads no mesh 0".into(),
            ));
        }
        let force: Vec<f64> = f_unit.iter().map(|f| f * op.load / f0).collect();
        let (static_x, static_forces) = static_equilibrium(&meshes, &k_s, &force, op.d)?;
        // a pin error the backlash cannot take up jams its planet: refused, not run
        for (k, m) in meshes.iter().enumerate() {
            let deflection: f64 =
                m.b.iter().zip(&static_x).map(|(b, x)| b * x).sum::<f64>() + m.offset;
            if deflection < -op.d - 1e-9 * op.d.max(1.0) {
                let planet = spec.meshes[k]
                    .gears
                    .iter()
                    .filter_map(|g| spec.body_index(g))
                    .find(|&i| spec.bodies[i].carrier.is_some());
                return Err(match planet {
                    Some(i) => crate::error::invalid(
                        format!("body[{i}].pin_error ({})", spec.bodies[i].name),
                        spec.bodies[i].pin_error,
                        format!(
                            "an error the backlash takes up: at D = {} and F = {} it puts mesh {:?} on its back flank in the static state (the planet jams)",
                            op.d, op.load, spec.meshes[k].name
                        ),
                    ),
                    None => TrainError::Kinematics(format!(
                        "the static state puts mesh {:?} on its back flank",
                        spec.meshes[k].name
                    )),
                });
            }
        }
        let frequencies: Vec<f64> = k_mean
            .symmetric_eigen()
            .eigenvalues
            .iter()
            .map(|l| l.max(0.0).sqrt())
            .collect();
        let stiffest = match op.stiffness {
            MeshStiffness::Harmonic { kappa } => 1.0 + kappa,
            MeshStiffness::Rectangular { ratio } => ratio,
        };
        let wmax = frequencies.iter().cloned().fold(0.0, f64::max) * stiffest.sqrt();
        Ok(TrainModel {
            names: spec.meshes.iter().map(|m| m.name.clone()).collect(),
            dof,
            pad_rate: if wmax > 0.0 { wmax } else { 1.0 },
            meshes,
            op: *op,
            force,
            cycles,
            natural_period: if wmax > 0.0 {
                TAU / wmax
            } else {
                f64::INFINITY
            },
            omega_ref,
            order0,
            frequencies,
            static_forces,
            static_x,
            needs_phase: op.xi != 0.0 || matches!(op.stiffness, MeshStiffness::Harmonic { .. }),
            has_shafts: k_s.iter().any(|&k| k != 0.0),
            loss: spec.fault.as_ref().map_or(0.0, |f| f.loss),
            k_s,
            c_s,
        })
    }

    /// Elastic degrees of freedom.
    pub fn dof(&self) -> usize {
        self.dof
    }

    /// `omega_ref` (rad/s): the dimensionless time's unit.
    pub fn omega_ref(&self) -> f64 {
        self.omega_ref
    }

    /// Input speed (rpm) of the operating point.
    pub fn input_rpm(&self) -> f64 {
        60.0 * self.op.omega * self.omega_ref / (TAU * self.order0)
    }

    /// Natural frequencies of the mean-stiffness train over `omega_ref`, ascending.
    pub fn frequencies(&self) -> &[f64] {
        &self.frequencies
    }

    /// Static force of each mesh at mean stiffness (units `k_ref b_c`; mesh 0 carries `F`): the
    /// load sharing of the train without backlash or stiffness variation.
    pub fn static_forces(&self) -> &[f64] {
        &self.static_forces
    }

    /// The state at rest in the static deflection of the mean-stiffness train with every mesh
    /// on its drive flank (the start of a train's runs).
    pub fn static_state(&self) -> [f64; N] {
        let mut y = [0.0; N];
        y[..self.dof].copy_from_slice(&self.static_x);
        y
    }

    /// The displacement of the elastic coordinates (padded to `N`, in `[..dof]`) that changes
    /// mesh `k`'s deflection by one unit with the least mass-weighted size: `u = b_k / |b_k|²`
    /// (the coordinates are mass-normalised, so `|u|²` is `u`'s kinetic-energy metric). It moves
    /// the other meshes coupled to mesh `k` as that least-inertia motion does. A plane of
    /// initial states "mesh `k`'s deflection and its rate" through a state `y` is
    /// `y + (a - delta_k) u` in positions and `b u` in velocities.
    pub fn mesh_coordinate(&self, k: usize) -> [f64; N] {
        let b = &self.meshes[k].b;
        let norm: f64 = b.iter().map(|b| b * b).sum();
        let mut u = [0.0; N];
        for (u, b) in u.iter_mut().zip(b) {
            *u = b / norm;
        }
        u
    }

    /// Mechanical energy `|x'|² / 2 + xᵀ K_s x / 2 + sum_k kappa_k k_k g(delta_k)² / 2 - F · x`
    /// in `mode`: constant along a motion of the undamped train (`c = 0`) of constant stiffness
    /// (`kappa = 0`) without transmission error (`xi = 0`) — an invariant for tests.
    pub fn energy(&self, t: f64, y: &[f64; N], mode: &TrainMode) -> f64 {
        let dof = self.dof;
        let (x, v) = (&y[..dof], &y[N / 2..N / 2 + dof]);
        let mut e = 0.5 * v.iter().map(|v| v * v).sum::<f64>();
        for i in 0..dof {
            e -= self.force[i] * x[i];
            for j in 0..dof {
                e += 0.5 * x[i] * self.k_s[i * dof + j] * x[j];
            }
        }
        let tt = self.time_terms(t);
        for k in 0..self.meshes.len() {
            let dl = self.deflection(k, y, tt.cos[k], tt.sin[k])[0];
            let g = match mode.contact[k] {
                ContactState::Drive => dl - self.op.d,
                ContactState::Back => dl + self.op.d,
                _ => 0.0,
            };
            e += 0.5 * self.meshes[k].kappa * self.stiffness(k, tt.cos[k], mode) * g * g;
        }
        e
    }

    /// The operating point.
    pub fn operating(&self) -> &TrainOperating {
        &self.op
    }

    /// `omega_k` of mesh `k`.
    #[inline(always)]
    fn omega_k(&self, k: usize) -> f64 {
        self.op.omega * self.meshes[k].rate
    }

    /// `(sin, cos)` of mesh `k`'s phase at `t` (zeros where the phases do not enter).
    #[inline(always)]
    fn phase(&self, k: usize, t: f64) -> (f64, f64) {
        if !self.needs_phase {
            return (0.0, 0.0);
        }
        let s = self.cycles_at(k, t);
        (TAU * (s - s.floor())).sin_cos()
    }

    /// `theta_k / 2 pi` at `t` (mesh cycles of mesh `k`).
    #[inline(always)]
    fn cycles_at(&self, k: usize, t: f64) -> f64 {
        self.omega_k(k) * t / TAU + self.meshes[k].phase
    }

    #[inline(always)]
    fn dot(&self, k: usize, x: &[f64]) -> f64 {
        self.meshes[k].b.iter().zip(x).map(|(b, x)| b * x).sum()
    }

    /// `[delta_k, delta_k']` at `t` with the phase's `cos`, `sin`.
    #[inline(always)]
    fn deflection(&self, k: usize, y: &[f64; N], cos: f64, sin: f64) -> [f64; 2] {
        let (dof, h) = (self.dof, N / 2);
        let xi = self.op.xi;
        [
            self.dot(k, &y[..dof]) - xi * cos + self.meshes[k].offset,
            self.dot(k, &y[h..h + dof]) + xi * self.omega_k(k) * sin,
        ]
    }

    /// Relative stiffness of mesh `k` (mean 1) with the phase's `cos` and the mode's zone.
    #[inline(always)]
    fn stiffness(&self, k: usize, cos: f64, mode: &TrainMode) -> f64 {
        let chip = if (mode.chip_full | mode.chip_half) & (1 << k) == 0 {
            1.0
        } else if mode.chip_full & (1 << k) != 0 {
            1.0 - self.loss
        } else {
            1.0 - 0.5 * self.loss
        };
        chip * match self.op.stiffness {
            MeshStiffness::Harmonic { kappa } => 1.0 + kappa * cos,
            MeshStiffness::Rectangular { ratio } => {
                let e = self.meshes[k].double;
                let single = 1.0 / (ratio * e + (1.0 - e));
                if mode.double & (1 << k) != 0 {
                    ratio * single
                } else {
                    single
                }
            }
        }
    }

    /// Contact force of mesh `k` (units `k_ref b_c`).
    #[inline(always)]
    fn force_of(&self, k: usize, c: ContactState, kk: f64, dl: [f64; 2]) -> f64 {
        let d = self.op.d;
        let m = &self.meshes[k];
        match c {
            ContactState::Drive => m.kappa * kk * (dl[0] - d) + m.damping * dl[1],
            ContactState::Back => m.kappa * kk * (dl[0] + d) + m.damping * dl[1],
            _ => 0.0,
        }
    }

    fn contact_of(&self, dl: [f64; 2]) -> ContactState {
        let d = self.op.d;
        if dl[0] > d || (dl[0] == d && dl[1] > 0.0) {
            ContactState::Drive
        } else if dl[0] < -d || (dl[0] == -d && dl[1] < 0.0) {
            ContactState::Back
        } else {
            ContactState::Separated
        }
    }

    /// Next zone border of any mesh strictly after `t0` (rectangular stiffness).
    fn next_border(&self, t0: f64) -> f64 {
        let mut next = f64::INFINITY;
        for k in 0..self.meshes.len() {
            let w = self.omega_k(k);
            let s0 = self.cycles_at(k, t0);
            let tol = 1e-9 * s0.abs().max(1.0);
            let n = s0.floor();
            let e = self.meshes[k].double;
            let to_time = |b: f64| (b - self.meshes[k].phase) * TAU / w;
            if self.rectangular() {
                if let Some(b) = [n + e, n + 1.0, n + 1.0 + e]
                    .into_iter()
                    .find(|&b| b > s0 + tol)
                {
                    next = next.min(to_time(b));
                }
            }
            if let Some(f) = self.meshes[k].fault {
                next = next.min(to_time(f.next_border(s0, tol)));
            }
        }
        next
    }

    /// The zones in force on the piece starting at `t0` (judged at its middle): double-tooth
    /// meshes, and meshes whose faulted tooth carries the load alone or shares it.
    fn zones(&self, t0: f64) -> [u32; 3] {
        let t1 = self.next_border(t0);
        let tm = if t1.is_finite() { 0.5 * (t0 + t1) } else { t0 };
        let mut z = [0; 3];
        for k in 0..self.meshes.len() {
            let s = self.cycles_at(k, tm);
            if self.rectangular() && s - s.floor() < self.meshes[k].double {
                z[0] |= 1 << k;
            }
            if let Some(f) = self.meshes[k].fault {
                let w = f.weight(s);
                if w == 1.0 {
                    z[1] |= 1 << k;
                } else if w > 0.0 {
                    z[2] |= 1 << k;
                }
            }
        }
        z
    }

    /// Whether the stiffness has time breakpoints (rectangular zones or a tooth fault).
    fn piecewise(&self) -> bool {
        self.rectangular() || self.loss != 0.0
    }

    /// Mesh and local guard (0: drive surface, 1: back surface) of guard `index`.
    fn which(&self, mode: &TrainMode, index: usize) -> (usize, usize) {
        let mut i = index;
        for k in 0..self.meshes.len() {
            match mode.contact[k] {
                ContactState::Separated => {
                    if i < 2 {
                        return (k, i);
                    }
                    i -= 2;
                }
                c => {
                    if i == 0 {
                        return (k, if c == ContactState::Drive { 0 } else { 1 });
                    }
                    i -= 1;
                }
            }
        }
        (self.meshes.len(), 0)
    }

    fn rectangular(&self) -> bool {
        matches!(self.op.stiffness, MeshStiffness::Rectangular { .. })
    }
}

impl<const N: usize> HybridSystem<N> for TrainModel<N> {
    type Mode = TrainMode;
    type TimeTerms = TrainTime;

    fn active_dim(&self) -> usize {
        2 * self.dof
    }

    fn initial_mode(&self, t: f64, y: &mut [f64; N]) -> TrainMode {
        let tt = self.time_terms(t);
        let mut contact = [ContactState::Separated; MAX_MESHES];
        for (k, c) in contact.iter_mut().enumerate().take(self.meshes.len()) {
            *c = self.contact_of(self.deflection(k, y, tt.cos[k], tt.sin[k]));
        }
        let [double, chip_full, chip_half] = if self.piecewise() {
            self.zones(t)
        } else {
            [0; 3]
        };
        TrainMode {
            contact,
            double,
            chip_full,
            chip_half,
            piece_start: t,
        }
    }

    #[inline(always)]
    fn time_terms(&self, t: f64) -> TrainTime {
        let mut tt = TrainTime {
            cos: [0.0; MAX_MESHES],
            sin: [0.0; MAX_MESHES],
        };
        if !self.needs_phase {
            return tt;
        }
        for k in 0..self.meshes.len() {
            let s = self.cycles_at(k, t);
            let (sn, cs) = (TAU * (s - s.floor())).sin_cos();
            tt.cos[k] = cs;
            tt.sin[k] = sn;
        }
        tt
    }

    #[inline(always)]
    fn rhs(&self, _t: f64, tt: &TrainTime, y: &[f64; N], mode: &TrainMode, dy: &mut [f64; N]) {
        let (dof, h) = (self.dof, N / 2);
        for i in 0..dof {
            dy[i] = y[h + i];
            let mut acc = self.force[i];
            if self.has_shafts {
                for j in 0..dof {
                    acc -= self.k_s[i * dof + j] * y[j] + self.c_s[i * dof + j] * y[h + j];
                }
            }
            dy[h + i] = acc;
        }
        for i in dof..h {
            dy[i] = -self.pad_rate * y[i];
            dy[h + i] = -self.pad_rate * y[h + i];
        }
        for k in 0..self.meshes.len() {
            let c = mode.contact[k];
            if !matches!(c, ContactState::Drive | ContactState::Back) {
                continue;
            }
            let dl = self.deflection(k, y, tt.cos[k], tt.sin[k]);
            let f = self.force_of(k, c, self.stiffness(k, tt.cos[k], mode), dl);
            for (i, b) in self.meshes[k].b.iter().enumerate() {
                dy[h + i] -= b * f;
            }
        }
    }

    fn guards(&self, t: f64, y: &[f64; N], mode: &TrainMode, g: &mut Guards) {
        let tt = self.time_terms(t);
        let d = self.op.d;
        for k in 0..self.meshes.len() {
            let x = self.deflection(k, y, tt.cos[k], tt.sin[k])[0];
            match mode.contact[k] {
                ContactState::Separated => {
                    g.push(x - d, Direction::Rising);
                    g.push(x + d, Direction::Falling);
                }
                ContactState::Drive => g.push(x - d, Direction::Falling),
                _ => g.push(x + d, Direction::Rising),
            }
        }
    }

    fn on_event(
        &self,
        t: f64,
        y: &mut [f64; N],
        mode: &mut TrainMode,
        index: usize,
    ) -> EventAction {
        let (k, local) = self.which(mode, index);
        if k < self.meshes.len() {
            mode.contact[k] = match (mode.contact[k], local) {
                (ContactState::Separated, 0) => ContactState::Drive,
                (ContactState::Separated, _) => ContactState::Back,
                _ => ContactState::Separated,
            };
        }
        // meshes crossing at the same instant (equal planets move alike until their phases part
        // them): the event search reports one, the others sit on their surface and would go
        // through it unseen; each switches here as its own event would switch it
        let tol = SIMULTANEOUS * self.op.d.max(1.0);
        let tt = self.time_terms(t);
        let d = self.op.d;
        for j in (0..self.meshes.len()).filter(|&j| j != k) {
            let [x, v] = self.deflection(j, y, tt.cos[j], tt.sin[j]);
            mode.contact[j] = match mode.contact[j] {
                ContactState::Separated if x >= d - tol && v > 0.0 => ContactState::Drive,
                ContactState::Separated if x <= -d + tol && v < 0.0 => ContactState::Back,
                ContactState::Drive if x <= d + tol && v < 0.0 => ContactState::Separated,
                ContactState::Back if x >= -d - tol && v > 0.0 => ContactState::Separated,
                c => c,
            };
        }
        EventAction::Continue
    }

    fn next_breakpoint(&self, _t: f64, mode: &TrainMode) -> f64 {
        if self.piecewise() {
            self.next_border(mode.piece_start)
        } else {
            f64::INFINITY
        }
    }

    fn on_breakpoint(&self, t: f64, y: &mut [f64; N], mode: &mut TrainMode) {
        mode.piece_start = t;
        [mode.double, mode.chip_full, mode.chip_half] = self.zones(t);
        // a stiffness jump does not move the state: the contacts stay as they are unless a
        // deflection sits exactly on its surface (then re-judged as at a start)
        let tt = self.time_terms(t);
        for k in 0..self.meshes.len() {
            let dl = self.deflection(k, y, tt.cos[k], tt.sin[k]);
            if dl[0].abs() == self.op.d {
                mode.contact[k] = self.contact_of(dl);
            }
        }
    }
}

impl<const N: usize> Variational<N> for TrainModel<N> {
    fn jacobian(
        &self,
        _t: f64,
        tt: &TrainTime,
        _y: &[f64; N],
        mode: &TrainMode,
        j: &mut [[f64; N]; N],
    ) {
        let (dof, h) = (self.dof, N / 2);
        *j = [[0.0; N]; N];
        for i in 0..dof {
            j[i][h + i] = 1.0;
            for c in 0..dof {
                j[h + i][c] = -self.k_s[i * dof + c];
                j[h + i][h + c] = -self.c_s[i * dof + c];
            }
        }
        for i in dof..h {
            j[i][i] = -self.pad_rate;
            j[h + i][h + i] = -self.pad_rate;
        }
        for k in 0..self.meshes.len() {
            if !matches!(mode.contact[k], ContactState::Drive | ContactState::Back) {
                continue;
            }
            let m = &self.meshes[k];
            let kk = m.kappa * self.stiffness(k, tt.cos[k], mode);
            for i in 0..dof {
                for c in 0..dof {
                    j[h + i][c] -= kk * m.b[i] * m.b[c];
                    j[h + i][h + c] -= m.damping * m.b[i] * m.b[c];
                }
            }
        }
    }

    fn guard_gradient(
        &self,
        t: f64,
        _y: &[f64; N],
        mode: &TrainMode,
        index: usize,
    ) -> ([f64; N], f64) {
        let (k, _) = self.which(mode, index);
        let mut g = [0.0; N];
        if k >= self.meshes.len() {
            return (g, 0.0);
        }
        for (i, b) in self.meshes[k].b.iter().enumerate() {
            g[i] = *b;
        }
        let (sin, _) = self.phase(k, t);
        (g, self.op.xi * self.omega_k(k) * sin)
    }
}

impl<const N: usize> GearSystem<N> for TrainModel<N> {
    fn mesh_count(&self) -> usize {
        self.meshes.len()
    }

    fn mesh_name(&self, k: usize) -> String {
        self.names[k].clone()
    }

    fn excitation_period(&self) -> f64 {
        f64::from(self.cycles) * TAU / self.op.omega
    }

    fn cycles_per_period(&self) -> u32 {
        self.cycles
    }

    fn natural_period(&self) -> f64 {
        self.natural_period
    }

    #[inline(always)]
    fn mesh_state(&self, t: f64, y: &[f64; N], k: usize) -> [f64; 2] {
        let (sn, cs) = self.phase(k, t);
        self.deflection(k, y, cs, sn)
    }

    fn mesh_force(&self, t: f64, y: &[f64; N], mode: &TrainMode, k: usize) -> f64 {
        let (sn, cs) = self.phase(k, t);
        let dl = self.deflection(k, y, cs, sn);
        self.force_of(k, mode.contact[k], self.stiffness(k, cs, mode), dl)
    }

    fn contact(&self, mode: &TrainMode, k: usize) -> ContactState {
        mode.contact[k]
    }

    fn backlash_levels(&self, _k: usize) -> (f64, f64) {
        (self.op.d, self.op.d)
    }

    fn event(&self, before: &TrainMode, _after: &TrainMode, index: usize) -> (usize, EventKind) {
        let (k, local) = self.which(before, index);
        let kind = match (before.contact[k.min(MAX_MESHES - 1)], local) {
            (ContactState::Separated, 0) => EventKind::DriveEnter,
            (ContactState::Separated, _) => EventKind::BackEnter,
            (ContactState::Drive, _) => EventKind::DriveExit,
            _ => EventKind::BackExit,
        };
        (k.min(self.meshes.len() - 1), kind)
    }

    fn segment(&self, mode: &TrainMode) -> u32 {
        // (a change of any one mask changes the label: rotations are bijective)
        mode.double ^ mode.chip_full.rotate_left(8) ^ mode.chip_half.rotate_left(16)
    }
}
