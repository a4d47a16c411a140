//! Single-pair and mesh stiffness along the path of contact and over the excitation period, load
//! sharing and friction factors: the tables the dynamic model integrates.
//!
//! Pair stiffness: `1/k_pair(s) = 1/k_h + C_pinion(u1(s)) + C_gear(u2(s))` (series springs of the
//! Hertz contact and both teeth's bending, shear, axial and foundation compliances; docs/model.md §1).
//! Mesh stiffness: sum over the pairs in contact. Load shares: `L_i = k_i / sum k_j` (equal
//! deflection of the pairs in contact; default) or the seeds' linear formula (1/3 → 2/3 across a
//! double zone).

use crate::geometry::{PairGeometry, PairKind};
use crate::tooth::{
    hertz_compliance, hertz_compliance_nonlinear, tooth_compliance, Compliance, Material,
    ToothShape,
};
use serde::{Deserialize, Serialize};

/// Hertzian contact model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HertzModel {
    /// Yang & Lin, constant.
    Linear,
    /// Chen & Shao, `k_h ~ F^0.1` at the static load share.
    Nonlinear,
}

/// Load-sharing rule in double-tooth zones.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LoadSharing {
    /// Proportional to the pair stiffnesses (equal deflection).
    Stiffness,
    /// The seeds' linear rule: the entering pair's share rises 1/3 → 2/3 over the double zone.
    Linear,
}

/// Stiffness model of a pair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StiffnessModel {
    /// Geometry.
    pub geom: PairGeometry,
    /// Material and face width.
    pub mat: Material,
    /// Pinion bore radius (m).
    pub r_int1: f64,
    /// Gear bore radius, or ring rim outer radius (m).
    pub r_int2: f64,
    /// Hertz model.
    pub hertz: HertzModel,
    /// Static transmitted normal force (N), for the nonlinear Hertz and thermal models.
    pub static_load: f64,
    /// Thermal stiffness (seed B eq. 10-11): `(expansion coefficient 1/K, temperature rise K)`.
    pub thermal: Option<(f64, f64)>,
}

/// Compliances of one pair at a contact position (m/N).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairCompliance {
    /// Thermal compliance of both teeth (0 without a temperature rise).
    pub thermal: f64,
    /// Hertz.
    pub hertz: f64,
    /// Pinion tooth.
    pub pinion: Compliance,
    /// Gear (ring) tooth.
    pub gear: Compliance,
}

impl PairCompliance {
    /// Total compliance.
    pub fn total(&self) -> f64 {
        self.thermal + self.hertz + self.pinion.total() + self.gear.total()
    }
}

impl StiffnessModel {
    fn shapes(&self) -> (ToothShape, ToothShape) {
        let g = &self.geom;
        let p = ToothShape::External {
            half_base: g.half_base_angle1,
            rb: g.rb1,
            rf: g.rf1,
            r_int: self.r_int1,
        };
        let q = match g.kind {
            PairKind::External => ToothShape::External {
                half_base: g.half_base_angle2,
                rb: g.rb2,
                rf: g.rf2,
                r_int: self.r_int2,
            },
            PairKind::Internal => ToothShape::Ring {
                beta: g.half_base_angle2,
                rb: g.rb2,
                rf: g.rf2,
                r_rim: self.r_int2,
            },
        };
        (p, q)
    }

    /// Compliances of a pair in contact at LoA position `s`, carrying `share` of the load.
    pub fn pair_compliance(&self, s: f64, share: f64) -> PairCompliance {
        let (p, q) = self.shapes();
        let hertz = match self.hertz {
            HertzModel::Linear => hertz_compliance(&self.mat),
            HertzModel::Nonlinear => {
                hertz_compliance_nonlinear(&self.mat, self.static_load * share.max(1e-3))
            }
        };
        let thermal = match self.thermal {
            Some((a, dt)) if dt != 0.0 => {
                let fnormal = (self.static_load * share.max(1e-3)).max(1e-9);
                (self.thermal_deformation(s, a, dt, true)
                    + self.thermal_deformation(s, a, dt, false))
                    / fnormal
            }
            _ => 0.0,
        };
        PairCompliance {
            thermal,
            hertz,
            pinion: tooth_compliance(&p, &self.mat, self.geom.roll_pinion(s)),
            gear: tooth_compliance(&q, &self.mat, self.geom.roll_gear(s)),
        }
    }

    /// Thermal deformation at the contact point of one tooth (seed B eq. 11):
    /// `theta = a dT (r_k sin(alpha_k) + (s_k/2) cos(alpha_k))`, radial growth and tooth-thickness
    /// growth projected on the line of action (`r_k` contact radius, `alpha_k` its pressure angle,
    /// `s_k` the tooth's arc thickness there).
    pub fn thermal_deformation(&self, s: f64, a: f64, dt: f64, pinion: bool) -> f64 {
        let g = &self.geom;
        let (u, rb) = if pinion {
            (g.roll_pinion(s), g.rb1)
        } else {
            (g.roll_gear(s), g.rb2)
        };
        let r_k = rb * (1.0 + u * u).sqrt();
        let alpha_k = u.atan();
        let inv_k = u - alpha_k;
        let half = if pinion {
            g.half_base_angle1 - inv_k
        } else {
            match g.kind {
                PairKind::External => g.half_base_angle2 - inv_k,
                PairKind::Internal => g.half_base_angle2 + inv_k,
            }
        };
        a * dt * (r_k * alpha_k.sin() + r_k * half * alpha_k.cos())
    }

    /// Stiffness of one pair at `s` (N/m), carrying `share` of the load.
    pub fn pair_stiffness(&self, s: f64, share: f64) -> f64 {
        1.0 / self.pair_compliance(s, share).total()
    }
}

/// Load shares of the pairs `(k_1, k_2)` in contact (the second may be absent).
pub fn load_shares(
    rule: LoadSharing,
    k: [f64; 2],
    in_contact: [bool; 2],
    double_fraction: f64,
    entering: usize,
) -> [f64; 2] {
    match (in_contact[0], in_contact[1]) {
        (true, false) => [1.0, 0.0],
        (false, true) => [0.0, 1.0],
        (false, false) => [0.0, 0.0],
        (true, true) => match rule {
            LoadSharing::Stiffness => {
                let t = k[0] + k[1];
                [k[0] / t, k[1] / t]
            }
            LoadSharing::Linear => {
                let e = (1.0 + double_fraction) / 3.0;
                let mut l = [1.0 - e, 1.0 - e];
                l[entering] = e;
                l
            }
        },
    }
}
