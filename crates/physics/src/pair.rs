//! A dimensional gear pair (`[pair]` of a config) turned into the dimensionless tables of the
//! mesh model: geometry, mesh stiffness over the excitation period, load sharing, friction
//! factors, and the normalisation `k_av`, `m_e`, `omega_n` with the operating-point mapping
//! (docs/model.md §1–3).
//!
//! Config units: mm, degrees, GPa, kg/m³, rpm, N·m, µm (stated in every field name).

mod build;
mod sampling;

use crate::error::PhysicsError;
use crate::geometry::{PairGeometry, PairKind};
use crate::lubrication::LubricationSpec;
use crate::mesh_stiffness::{HertzModel, LoadSharing};
use geardyn_model::{Breakage, ModelParams, StiffnessForm, ZonePiece};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Pitch-point crossings closer than this (in mesh cycles) to a piece border are not split off
/// (a sliver piece of a few samples would only add a breakpoint).
const PITCH_SPLIT_MIN: f64 = 1e-9;

fn one() -> f64 {
    1.0
}
fn quarter() -> f64 {
    0.25
}
fn steel_density() -> f64 {
    7850.0
}
fn samples() -> u32 {
    1024
}
fn hertz_default() -> HertzModel {
    HertzModel::Linear
}
fn sharing_default() -> LoadSharing {
    LoadSharing::Stiffness
}

/// Chipped pinion tooth.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BreakageSpec {
    /// Removed tip height, radially (mm). Give this or `tip_radius_mm`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub removed_height_mm: Option<f64>,
    /// Broken tip radius `R_ab` (mm).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tip_radius_mm: Option<f64>,
    /// Mesh cycle (within the `z1`-cycle excitation period) in which the broken tooth leaves mesh.
    #[serde(default)]
    pub broken_cycle: u32,
}

/// A physical operating point (sets the model's `omega`, `F`, `xi`, `D`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OperatingPoint {
    /// Pinion speed (rpm).
    pub speed_rpm: f64,
    /// Pinion torque (N·m).
    pub torque_nm: f64,
    /// Transmission-error amplitude `E_a` (µm).
    pub error_amplitude_um: f64,
    /// Static half backlash `b` (µm).
    pub half_backlash_um: f64,
}

/// Thermal state of the teeth (seed B): uniform temperature rise of the tooth bulk.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ThermalSpec {
    /// Temperature rise above assembly temperature (K).
    pub temperature_rise_k: f64,
    /// Linear expansion coefficient (1/K).
    #[serde(default = "steel_expansion")]
    pub expansion_per_k: f64,
}

fn steel_expansion() -> f64 {
    11.5e-6
}

/// A dimensional spur pair.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PairSpec {
    /// `external` or `internal`.
    pub kind: PairKind,
    /// Pinion teeth.
    pub z1: u32,
    /// Gear (ring) teeth.
    pub z2: u32,
    /// Module (mm).
    pub module_mm: f64,
    /// Pressure angle (deg).
    pub pressure_angle_deg: f64,
    /// Addendum coefficient `ha*`.
    #[serde(default = "one")]
    pub addendum: f64,
    /// Tip clearance coefficient `c*`.
    #[serde(default = "quarter")]
    pub clearance: f64,
    /// Pinion profile shift.
    #[serde(default)]
    pub x1: f64,
    /// Gear (ring) profile shift.
    #[serde(default)]
    pub x2: f64,
    /// Face width (mm).
    pub face_width_mm: f64,
    /// Young's modulus (GPa).
    pub youngs_modulus_gpa: f64,
    /// Poisson's ratio.
    pub poisson: f64,
    /// Density (kg/m³), for inertias when they are not given.
    #[serde(default = "steel_density")]
    pub density_kg_m3: f64,
    /// Pinion bore radius (mm); default half the pitch radius.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bore_radius_pinion_mm: Option<f64>,
    /// Gear bore radius (mm), or for a ring its rim outer radius; default half the pitch radius,
    /// or root radius + 3 modules for a ring.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bore_radius_gear_mm: Option<f64>,
    /// Pinion polar inertia (kg·m²); default from density and geometry.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inertia_pinion_kgm2: Option<f64>,
    /// Gear polar inertia (kg·m²).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inertia_gear_kgm2: Option<f64>,
    /// Hertz model: `linear` (Yang & Lin) or `nonlinear` (Chen & Shao, needs a torque).
    #[serde(default = "hertz_default")]
    pub hertz: HertzModel,
    /// Load sharing: `stiffness` or `linear`.
    #[serde(default = "sharing_default")]
    pub load_sharing: LoadSharing,
    /// Friction coefficient `mu` (constant).
    #[serde(default)]
    pub mu: f64,
    /// Chipped pinion tooth.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub breakage: Option<BreakageSpec>,
    /// Lubrication: friction from the multi-state model instead of the constant `mu`
    /// (needs `operating`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lubrication: Option<LubricationSpec>,
    /// Thermal stiffness and thermal backlash reduction (needs `operating.torque_nm`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub thermal: Option<ThermalSpec>,
    /// Table samples per mesh cycle.
    #[serde(default = "samples")]
    pub samples_per_cycle: u32,
    /// Characteristic length `b_c` (µm) of the dimensionless displacement.
    pub characteristic_length_um: f64,
    /// Prescribed mean mesh stiffness `k_av` (N/m): the computed tables are scaled to it (seed B
    /// states `k_av = 4e8 N/m` for its pair). Default: the potential-energy value.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mean_stiffness_n_per_m: Option<f64>,
    /// Damping ratio `zeta` (sets `c = 2 zeta`); default: keep `model.c`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping_ratio: Option<f64>,
    /// Operating point (sets `omega`, `F`, `xi`, `D`); default: keep the model's values.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub operating: Option<OperatingPoint>,
}

/// One row of the stiffness table (for `stiffness.csv` and plots).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct StiffnessRow {
    /// Position in the excitation period (mesh cycles).
    pub position: f64,
    /// Stiffness of the entering pair (N/m; 0 if not in contact).
    pub k_pair1: f64,
    /// Stiffness of the leaving pair (N/m; 0 if not in contact).
    pub k_pair2: f64,
    /// Mesh stiffness (N/m).
    pub k_mesh: f64,
    /// Load share of the entering pair.
    pub share1: f64,
    /// Load share of the leaving pair.
    pub share2: f64,
    /// Drive-side friction factor.
    pub h_drive: f64,
    /// Back-side friction factor.
    pub h_back: f64,
    /// Single-tooth zone.
    pub single: bool,
    /// Friction coefficient of the entering pair.
    pub mu1: f64,
    /// Friction coefficient of the leaving pair (0 if not in contact).
    pub mu2: f64,
    /// Minimum film thickness at the entering pair (m; 0 without lubrication model).
    pub film1: f64,
    /// Film parameter at the entering pair.
    pub lambda1: f64,
    /// Regime at the entering pair (0 EHL, 1 mixed, 2 boundary, -1 constant mu).
    pub regime1: i8,
}

/// Everything derived from a [`PairSpec`].
#[derive(Clone, Debug)]
pub struct PairModel {
    /// Geometry.
    pub geom: PairGeometry,
    /// Reduced contact ratio of the broken tooth (None if healthy).
    pub eps_b: Option<f64>,
    /// Mean mesh stiffness over a healthy cycle (N/m).
    pub k_av: f64,
    /// Pinion inertia (kg·m²).
    pub i_p: f64,
    /// Gear inertia (kg·m²).
    pub i_g: f64,
    /// Equivalent mass (kg).
    pub m_e: f64,
    /// Natural frequency `sqrt(k_av/m_e)` (rad/s).
    pub omega_n: f64,
    /// Characteristic length (m).
    pub b_c: f64,
    /// Mesh cycles per excitation period.
    pub cycles: u32,
    /// Table rows over the excitation period.
    pub rows: Vec<StiffnessRow>,
    /// Zone pieces for the mesh model (dimensionless).
    pub pieces: Vec<ZonePiece>,
    /// Physical half backlash `(D_d, D_s)` (dimensionless) at the operating point: static
    /// backlash + load deformation - thermal growth - oil film (see [`PairSpec::build`]).
    pub backlash: Option<(f64, f64)>,
    /// The spec it came from.
    pub spec: PairSpec,
}

fn bad(field: &str, value: f64, allowed: &str) -> PhysicsError {
    PhysicsError::Invalid {
        field: field.to_string(),
        value,
        allowed: allowed.to_string(),
    }
}

impl PairSpec {
    fn validate(&self) -> Result<(), PhysicsError> {
        let pos = |f: &str, v: f64, allowed: &str| {
            if v > 0.0 && v.is_finite() {
                Ok(())
            } else {
                Err(bad(f, v, allowed))
            }
        };
        // physical ranges, wide enough for every real gear (watch gears to mill gears, polymers
        // to carbides): outside them the pair is absurd (a face width of 1e-300 mm gave m_e = 0,
        // omega_n = inf and "inf rpm")
        let within = |f: &str, v: f64, lo: f64, hi: f64, unit: &str| {
            if v.is_finite() && (lo..=hi).contains(&v) {
                Ok(())
            } else {
                Err(bad(f, v, &format!("[{lo:e}, {hi:e}] {unit}")))
            }
        };
        within("face_width_mm", self.face_width_mm, 0.01, 1e4, "mm")?;
        within(
            "youngs_modulus_gpa",
            self.youngs_modulus_gpa,
            0.1,
            2000.0,
            "GPa",
        )?;
        within("density_kg_m3", self.density_kg_m3, 100.0, 3e4, "kg/m^3")?;
        within(
            "characteristic_length_um",
            self.characteristic_length_um,
            1e-3,
            1e5,
            "um",
        )?;
        if !(self.poisson > 0.0 && self.poisson < 0.5) {
            return Err(bad("poisson", self.poisson, "(0, 0.5)"));
        }
        if !(self.mu >= 0.0 && self.mu < 1.0) {
            return Err(bad("mu", self.mu, "[0, 1)"));
        }
        // a pair beyond 1000 teeth is a rack in all but name, and its tables (z1 mesh cycles of
        // samples with breakage) would take minutes to build
        for (f, z) in [("z1", self.z1), ("z2", self.z2)] {
            if !(3..=1000).contains(&z) {
                return Err(bad(f, z as f64, "3 ..= 1000 teeth"));
            }
        }
        if !(64..=65536).contains(&self.samples_per_cycle) {
            return Err(bad(
                "samples_per_cycle",
                self.samples_per_cycle as f64,
                "64 ..= 65536",
            ));
        }
        if let Some(l) = &self.lubrication {
            l.validate()?;
            if self.operating.is_none() {
                return Err(bad(
                    "lubrication",
                    0.0,
                    "a lubrication model needs pair.operating (speed and torque set the film)",
                ));
            }
        }
        if let Some(op) = &self.operating {
            within("operating.speed_rpm", op.speed_rpm, 1e-3, 1e6, "rpm")?;
            if !(op.torque_nm >= 0.0 && op.torque_nm.is_finite()) {
                return Err(bad("operating.torque_nm", op.torque_nm, "[0, inf) N m"));
            }
            if !(op.error_amplitude_um >= 0.0 && op.error_amplitude_um.is_finite()) {
                return Err(bad(
                    "operating.error_amplitude_um",
                    op.error_amplitude_um,
                    "[0, inf) um",
                ));
            }
            pos(
                "operating.half_backlash_um",
                op.half_backlash_um,
                "(0, inf) um (backlash must be positive)",
            )?;
        }
        if let Some(t) = &self.thermal {
            if !(t.temperature_rise_k >= 0.0 && t.temperature_rise_k < 500.0) {
                return Err(bad(
                    "thermal.temperature_rise_k",
                    t.temperature_rise_k,
                    "[0, 500) K",
                ));
            }
            if !(t.expansion_per_k > 0.0 && t.expansion_per_k < 1e-3) {
                return Err(bad(
                    "thermal.expansion_per_k",
                    t.expansion_per_k,
                    "(0, 1e-3) 1/K",
                ));
            }
            if t.temperature_rise_k > 0.0 {
                match &self.operating {
                    None => return Err(bad("thermal", t.temperature_rise_k, "a temperature rise needs pair.operating with torque_nm > 0 (thermal stiffness = load / thermal deformation)")),
                    Some(o) if o.torque_nm <= 0.0 => return Err(bad("operating.torque_nm", o.torque_nm, "(0, inf) N m while [pair.thermal] sets a temperature rise (thermal stiffness = load / thermal deformation); or set pair.thermal.temperature_rise_k = 0")),
                    _ => {}
                }
            }
        }
        if let Some(k) = self.mean_stiffness_n_per_m {
            pos("mean_stiffness_n_per_m", k, "(0, inf) N/m")?;
        }
        if let Some(z) = self.damping_ratio {
            if !(z >= 0.0 && z < 1.0) {
                return Err(bad("damping_ratio", z, "[0, 1)"));
            }
        }
        for (f, v) in [
            ("inertia_pinion_kgm2", self.inertia_pinion_kgm2),
            ("inertia_gear_kgm2", self.inertia_gear_kgm2),
        ] {
            if let Some(v) = v {
                pos(f, v, "(0, inf) kg m^2")?;
            }
        }
        Ok(())
    }
}

/// Dimensionless operating parameters.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Dimensionless {
    /// `omega = omega_h/omega_n`.
    pub omega: f64,
    /// `F = (T/R_bp)/(k_av b_c)`.
    pub load: f64,
    /// `xi = E_a/b_c`.
    pub xi: f64,
    /// `D = b/b_c`.
    pub d: f64,
}

impl PairModel {
    /// Physical operating point → dimensionless parameters.
    pub fn to_dimensionless(&self, op: &OperatingPoint) -> Dimensionless {
        let omega_h = self.geom.z1 as f64 * op.speed_rpm * 2.0 * PI / 60.0;
        Dimensionless {
            omega: omega_h / self.omega_n,
            load: op.torque_nm / self.geom.rb1 / (self.k_av * self.b_c),
            xi: op.error_amplitude_um * 1e-6 / self.b_c,
            d: op.half_backlash_um * 1e-6 / self.b_c,
        }
    }

    /// Dimensionless parameters → physical operating point (the inverse mapping).
    pub fn to_physical(&self, d: &Dimensionless) -> OperatingPoint {
        OperatingPoint {
            speed_rpm: d.omega * self.omega_n * 60.0 / (2.0 * PI * self.geom.z1 as f64),
            torque_nm: d.load * self.k_av * self.b_c * self.geom.rb1,
            error_amplitude_um: d.xi * self.b_c * 1e6,
            half_backlash_um: d.d * self.b_c * 1e6,
        }
    }

    /// Writes the pair's tables and (if given) operating point into dimensionless parameters.
    pub fn apply(&self, p: &mut ModelParams) {
        p.eps = self.geom.eps;
        p.stiffness = StiffnessForm::Zoned {
            pieces: self.pieces.clone(),
        };
        p.breakage = self.eps_b.map(|eb| Breakage {
            z_p: self.geom.z1,
            broken_cycle: self.spec.breakage.map_or(0, |b| b.broken_cycle),
            eps_b: eb,
            k_zone2: 1.0,
        });
        if let Some(op) = &self.spec.operating {
            let d = self.to_dimensionless(op);
            p.omega = d.omega;
            p.load = d.load;
            p.xi = d.xi;
            (p.d_double, p.d_single) = self.backlash.unwrap_or((d.d, d.d));
        }
        if let Some(z) = self.spec.damping_ratio {
            p.c = 2.0 * z;
        }
    }
}
