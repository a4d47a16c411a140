//! A dimensional gear pair (`[pair]` of a config) turned into the dimensionless tables of the
//! mesh model: geometry, mesh stiffness over the excitation period, load sharing, friction
//! factors, and the normalisation `k_av`, `m_e`, `omega_n` with the operating-point mapping
//! (docs/model.md §1–3).
//!
//! Config units: mm, degrees, GPa, kg/m³, rpm, N·m, µm (stated in every field name).

use crate::breakage::{broken_contact, Chip};
use crate::error::PhysicsError;
use crate::geometry::{PairGeometry, PairGeometryInput, PairKind};
use crate::lubrication::{friction, ContactConditions, LubricationSpec, Regime};
use crate::mesh_stiffness::{load_shares, HertzModel, LoadSharing, StiffnessModel};
use crate::tooth::Material;
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

    /// Builds geometry, stiffness tables and normalisation.
    pub fn build(&self) -> Result<PairModel, PhysicsError> {
        self.validate()?;
        let geom = PairGeometry::new(&PairGeometryInput {
            kind: self.kind,
            z1: self.z1,
            z2: self.z2,
            module: self.module_mm * 1e-3,
            pressure_angle: self.pressure_angle_deg.to_radians(),
            addendum: self.addendum,
            clearance: self.clearance,
            x1: self.x1,
            x2: self.x2,
        })?;
        geom.check_two_zone()?;
        let m = geom.module;
        let b = self.face_width_mm * 1e-3;
        let mat = Material {
            e: self.youngs_modulus_gpa * 1e9,
            nu: self.poisson,
            b,
        };
        let r_int1 = self
            .bore_radius_pinion_mm
            .map_or(0.5 * geom.r1, |r| r * 1e-3);
        let r_int2 = self.bore_radius_gear_mm.map_or(
            match self.kind {
                PairKind::External => 0.5 * geom.r2,
                PairKind::Internal => geom.rf2 + 3.0 * m,
            },
            |r| r * 1e-3,
        );
        if !(r_int1 > 0.0 && r_int1 < geom.rf1) {
            return Err(bad(
                "bore_radius_pinion_mm",
                r_int1 * 1e3,
                &format!("(0, {:.3}) mm (inside the root circle)", geom.rf1 * 1e3),
            ));
        }
        match self.kind {
            PairKind::External if !(r_int2 > 0.0 && r_int2 < geom.rf2) => {
                return Err(bad(
                    "bore_radius_gear_mm",
                    r_int2 * 1e3,
                    &format!("(0, {:.3}) mm (inside the root circle)", geom.rf2 * 1e3),
                ));
            }
            PairKind::Internal if r_int2 <= geom.rf2 => {
                return Err(bad(
                    "bore_radius_gear_mm",
                    r_int2 * 1e3,
                    &format!(
                        "({:.3}, inf) mm (ring rim outside its root circle)",
                        geom.rf2 * 1e3
                    ),
                ));
            }
            _ => {}
        }
        let rho = self.density_kg_m3;
        let disk = |ro: f64, ri: f64| rho * b * PI * (ro.powi(4) - ri.powi(4)) / 2.0;
        let i_p = self
            .inertia_pinion_kgm2
            .unwrap_or_else(|| disk(geom.r1, r_int1));
        let i_g = self.inertia_gear_kgm2.unwrap_or_else(|| match self.kind {
            PairKind::External => disk(geom.r2, r_int2),
            PairKind::Internal => disk(r_int2, geom.r2),
        });
        let m_e = i_p * i_g / (geom.rb1 * geom.rb1 * i_g + geom.rb2 * geom.rb2 * i_p);
        let static_load = match (self.hertz, &self.operating) {
            (HertzModel::Linear, Some(op)) => op.torque_nm / geom.rb1,
            (HertzModel::Linear, None) => 0.0,
            (HertzModel::Nonlinear, Some(op)) if op.torque_nm > 0.0 => op.torque_nm / geom.rb1,
            (HertzModel::Nonlinear, _) => {
                return Err(bad("hertz", 0.0, "\"linear\", or \"nonlinear\" together with pair.operating.torque_nm > 0 (the Hertz stiffness depends on the load)"));
            }
        };
        let sm = StiffnessModel {
            geom,
            mat,
            r_int1,
            r_int2,
            hertz: self.hertz,
            static_load,
            thermal: self
                .thermal
                .map(|t| (t.expansion_per_k, t.temperature_rise_k)),
        };
        let e_red = mat.e / (1.0 - mat.nu * mat.nu);
        let omega1 = self
            .operating
            .map_or(0.0, |o| o.speed_rpm * 2.0 * PI / 60.0);
        let omega2 = omega1 * self.z1 as f64 / self.z2 as f64;
        let lub_at = |s: f64, share: f64| -> Option<crate::lubrication::FrictionState> {
            let lub = self.lubrication.as_ref()?;
            let (r1, r2) = geom.friction_arms(s);
            let r = match geom.kind {
                PairKind::External => r1 * r2 / (r1 + r2),
                PairKind::Internal => r1 * r2 / (r2 - r1),
            };
            let c = ContactConditions {
                u1: omega1 * r1,
                u2: omega2 * r2,
                r,
                w: static_load * share.max(1e-3) / b,
                e_red,
            };
            Some(friction(&c, lub))
        };
        let (eps_b, s_d1, broken_cycle) = match &self.breakage {
            None => (None, geom.s_d, None),
            Some(bs) => {
                let chip = match (bs.removed_height_mm, bs.tip_radius_mm) {
                    (Some(h), None) => Chip::RemovedHeight(h * 1e-3),
                    (None, Some(r)) => Chip::TipRadius(r * 1e-3),
                    _ => {
                        return Err(bad(
                            "breakage",
                            0.0,
                            "exactly one of removed_height_mm or tip_radius_mm",
                        ));
                    }
                };
                if bs.broken_cycle >= self.z1 {
                    return Err(bad(
                        "breakage.broken_cycle",
                        bs.broken_cycle as f64,
                        &format!("[0, {}] (z1 - 1)", self.z1 - 1),
                    ));
                }
                let (eb, sd1) = broken_contact(&geom, chip)?;
                (Some(eb), sd1, Some(bs.broken_cycle))
            }
        };
        let cycles = if eps_b.is_some() { self.z1 } else { 1 };
        let n = self.samples_per_cycle as usize;
        let mu = self.mu;
        let arms = |s: f64| {
            let (sp, sg) = geom.friction_arms(s);
            m_e * (geom.rb1 * sp / i_p + geom.rb2 * sg / i_g)
        };
        // one healthy cycle and, if broken, the broken cycle: samples of each zone piece
        let eps = geom.eps;
        let sample_cycle = |broken: bool| -> Vec<(f64, f64, bool, bool, Vec<StiffnessRow>)> {
            let e_dbl = if broken {
                eps_b.unwrap_or(eps) - 1.0
            } else {
                eps - 1.0
            };
            let mut out = Vec::new();
            let mut pieces = vec![(0.0, e_dbl, false, false)];
            if broken && e_dbl < eps - 1.0 {
                pieces.push((e_dbl, eps - 1.0, true, true));
            }
            pieces.push((eps - 1.0, 1.0, true, false));
            // The sliding direction of a pair flips where it passes the pitch point: the friction
            // factor jumps there, so that instant is a piece border (a time breakpoint the
            // integrator steps onto), not a jump smeared across one table interval.
            // (the crossings of the pair entering at the cycle's start and of the one ahead of
            // it, in ascending order; none without friction)
            let pitch = (geom.s_p - geom.s_a) / geom.pb;
            let flips: &[f64] = if mu > 0.0 || self.lubrication.is_some() {
                &[pitch - 1.0, pitch]
            } else {
                &[]
            };
            let pieces: Vec<_> = pieces
                .into_iter()
                .flat_map(|(a, bnd, single, zone_ii)| {
                    let mut ends = vec![a];
                    ends.extend(
                        flips
                            .iter()
                            .filter(|&&f| f > a + PITCH_SPLIT_MIN && f < bnd - PITCH_SPLIT_MIN),
                    );
                    ends.push(bnd);
                    ends.windows(2)
                        .map(|w| (w[0], w[1], single, zone_ii))
                        .collect::<Vec<_>>()
                })
                .collect();
            for (a, bnd, single, zone_ii) in pieces {
                // a sample on the pitch point takes the direction of the piece it belongs to
                // (that of the pair's position at the piece's middle)
                let mid = geom.s_a + 0.5 * (a + bnd) * geom.pb;
                let direction = |s: f64, s_mid: f64| {
                    if (s - geom.s_p).abs() <= PITCH_SPLIT_MIN * geom.pb {
                        geom.sliding_direction(s_mid)
                    } else {
                        geom.sliding_direction(s)
                    }
                };
                let cnt = (((bnd - a) * n as f64).ceil() as usize).max(2);
                let mut rows = Vec::with_capacity(cnt + 1);
                for j in 0..=cnt {
                    let phi = a + (bnd - a) * j as f64 / cnt as f64;
                    let s0 = geom.s_a + phi * geom.pb;
                    let s1 = s0 + geom.pb;
                    let end1 = if broken { s_d1 } else { geom.s_d };
                    let in1 = !single && s1 <= end1 + 1e-12;
                    let contact = [true, in1];
                    let frac = if e_dbl > 0.0 {
                        (phi / e_dbl).clamp(0.0, 1.0)
                    } else {
                        0.0
                    };
                    let mut k = [
                        sm.pair_stiffness(s0, if in1 { 0.5 } else { 1.0 }),
                        if in1 { sm.pair_stiffness(s1, 0.5) } else { 0.0 },
                    ];
                    let mut l = load_shares(self.load_sharing, k, contact, frac, 0);
                    if self.hertz == HertzModel::Nonlinear || sm.thermal.is_some_and(|t| t.1 != 0.0)
                    {
                        // one fixed-point pass: Hertz stiffness at the pair's own load share
                        k = [
                            sm.pair_stiffness(s0, l[0]),
                            if in1 {
                                sm.pair_stiffness(s1, l[1])
                            } else {
                                0.0
                            },
                        ];
                        l = load_shares(self.load_sharing, k, contact, frac, 0);
                    }
                    let st0 = lub_at(s0, l[0]);
                    let st1 = if in1 { lub_at(s1, l[1]) } else { None };
                    let mu0 = st0.map_or(mu, |st| st.mu);
                    let mu1 = if in1 { st1.map_or(mu, |st| st.mu) } else { 0.0 };
                    let mut fr = mu0 * direction(s0, mid) * arms(s0) * l[0];
                    if in1 {
                        fr += mu1 * direction(s1, mid + geom.pb) * arms(s1) * l[1];
                    }
                    rows.push(StiffnessRow {
                        position: phi,
                        k_pair1: k[0],
                        k_pair2: k[1],
                        k_mesh: k[0] + k[1],
                        share1: l[0],
                        share2: l[1],
                        h_drive: 1.0 + fr,
                        h_back: 1.0 - fr,
                        single,
                        mu1: mu0,
                        mu2: mu1,
                        film1: st0.map_or(0.0, |st| st.film),
                        lambda1: st0.map_or(0.0, |st| st.lambda),
                        regime1: st0.map_or(-1, |st| match st.regime {
                            Regime::Ehl => 0,
                            Regime::Mixed => 1,
                            Regime::Boundary => 2,
                        }),
                    });
                }
                out.push((a, bnd, single, zone_ii, rows));
            }
            out
        };
        let healthy = sample_cycle(false);
        // k_av: trapezoidal mean over the healthy cycle
        let mut k_int = 0.0;
        for (a, bnd, _, _, rows) in &healthy {
            let w = (bnd - a) / (rows.len() - 1) as f64;
            for (j, r) in rows.iter().enumerate() {
                let f = if j == 0 || j + 1 == rows.len() {
                    0.5
                } else {
                    1.0
                };
                k_int += f * w * r.k_mesh;
            }
        }
        // optional prescribed mean: scale every stiffness (shares and friction are unchanged)
        let scale = match self.mean_stiffness_n_per_m {
            Some(k) => k / k_int,
            None => 1.0,
        };
        let k_av = k_int * scale;
        let broken = if eps_b.is_some() {
            Some(sample_cycle(true))
        } else {
            None
        };
        let mut rows_all = Vec::new();
        let mut pieces = Vec::new();
        for c in 0..cycles {
            let src = match (&broken, broken_cycle) {
                (Some(bc), Some(nb)) if nb == c => bc,
                _ => &healthy,
            };
            for (a, bnd, single, zone_ii, rows) in src {
                pieces.push(ZonePiece {
                    start: c as f64 + a,
                    end: c as f64 + bnd,
                    single: *single,
                    zone_ii: *zone_ii,
                    k: rows.iter().map(|r| r.k_mesh * scale / k_av).collect(),
                    h_drive: rows.iter().map(|r| r.h_drive).collect(),
                    h_back: rows.iter().map(|r| r.h_back).collect(),
                });
                rows_all.extend(rows.iter().map(|r| StiffnessRow {
                    position: c as f64 + r.position,
                    k_pair1: r.k_pair1 * scale,
                    k_pair2: r.k_pair2 * scale,
                    k_mesh: r.k_mesh * scale,
                    ..*r
                }));
            }
        }
        let b_c = self.characteristic_length_um * 1e-6;
        // physical half backlash per zone at the operating point (needs a torque):
        // static half backlash + half the difference of the zone's static deflection from the
        // mean one (a softer zone deflects the loaded flanks further and opens the back side) -
        // half the thermal growth of both teeth along the LoA - the oil film on the back flank
        let backlash = match &self.operating {
            Some(op) if op.torque_nm > 0.0 => {
                let w = op.torque_nm / geom.rb1;
                let zone_mean = |single: bool, what: &dyn Fn(&StiffnessRow) -> f64| {
                    let v: Vec<f64> = healthy
                        .iter()
                        .filter(|z| z.2 == single)
                        .flat_map(|z| z.4.iter().map(what))
                        .collect();
                    v.iter().sum::<f64>() / v.len().max(1) as f64
                };
                let thermal = self.thermal.map_or(0.0, |t| {
                    t.expansion_per_k * t.temperature_rise_k * PI * m * geom.alpha_w.cos() / 2.0
                });
                let mut d = [0.0; 2];
                for (i, single) in [false, true].into_iter().enumerate() {
                    let k_zone = zone_mean(single, &|r| r.k_mesh) * scale;
                    let film = zone_mean(single, &|r| r.film1);
                    d[i] = op.half_backlash_um * 1e-6 + 0.5 * w * (1.0 / k_zone - 1.0 / k_av)
                        - thermal
                        - film;
                    if d[i] <= 0.0 {
                        return Err(PhysicsError::Geometry(format!(
                            "the backlash closes in the {} zone at this operating point (static {} um, thermal growth {} um, film {} um)",
                            if single { "single-tooth" } else { "double-tooth" },
                            geardyn_model::error::num(op.half_backlash_um),
                            geardyn_model::error::num((thermal * 1e6 * 1e3).round() / 1e3),
                            geardyn_model::error::num((film * 1e6 * 1e3).round() / 1e3)
                        )));
                    }
                }
                Some((d[0] / b_c, d[1] / b_c))
            }
            _ => None,
        };
        Ok(PairModel {
            geom,
            eps_b,
            k_av,
            i_p,
            i_g,
            m_e,
            omega_n: (k_av / m_e).sqrt(),
            b_c,
            cycles,
            rows: rows_all,
            pieces,
            backlash,
            spec: self.clone(),
        })
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
