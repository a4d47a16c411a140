//! Dimensionless parameters of the mesh model (docs/model.md §1–3), as they appear in a config file.
//!
//! All quantities are dimensionless: time `tau = omega_n*t`, displacement in units of `b_c`,
//! stiffness in units of `k_av`, forces in units of `k_av*b_c`.

use crate::contact_law::ContactLaw;
use crate::error::ModelError;
use crate::impact::ImpactLaw;
use serde::{Deserialize, Serialize};

/// Time-varying mesh stiffness `k(phi)` over one healthy mesh cycle (units of `k_av`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "form", rename_all = "snake_case", deny_unknown_fields)]
pub enum StiffnessForm {
    /// `k = k0`.
    Constant {
        /// Constant stiffness.
        k: f64,
    },
    /// `k = 1 + kappa*cos(omega*tau)` (case C1).
    Harmonic {
        /// Relative amplitude `kappa` in `[0, 1)`.
        kappa: f64,
    },
    /// Rectangular wave: `k_double` on the double-tooth zone `[0, eps-1)`, `k_single` on `[eps-1, 1)`.
    Rectangular {
        /// Stiffness in the double-tooth zone.
        k_double: f64,
        /// Stiffness in the single-tooth zone.
        k_single: f64,
    },
    /// Tables filled by the gear-physics layer: one entry per zone piece of the excitation period,
    /// each with uniform samples of `k`, `h_drive`, `h_back` from its start to its end (both
    /// included), so jumps at zone borders are exact. Not meant to be written by hand.
    Zoned {
        /// Zone pieces in order, covering `[0, cycles)` (mesh cycles).
        pieces: Vec<ZonePiece>,
    },
    /// User table over one mesh cycle: `k` at phases `phase` (strictly increasing in `[0, 1]`),
    /// interpolated linearly inside each zone; a jump at the zone border `eps-1` is kept exact by
    /// evaluating each zone from its own side.
    Table {
        /// Phases in `[0, 1]`.
        phase: Vec<f64>,
        /// Stiffness values.
        k: Vec<f64>,
    },
}

/// One zone piece of a [`StiffnessForm::Zoned`] table (positions in mesh cycles from the start
/// of the excitation period).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ZonePiece {
    /// Start (mesh cycles).
    pub start: f64,
    /// End (mesh cycles).
    pub end: f64,
    /// Single-tooth zone (half backlash `D_s`) or double (`D_d`).
    pub single: bool,
    /// Broken cycle's single-tooth zone II.
    #[serde(default)]
    pub zone_ii: bool,
    /// Dimensionless stiffness samples `k/k_av`, uniform over `[start, end]`.
    pub k: Vec<f64>,
    /// Drive-side friction factor samples.
    pub h_drive: Vec<f64>,
    /// Back-side friction factor samples.
    pub h_back: Vec<f64>,
}

/// Friction of the stand-in model: `h = 1 + mu*lambda*arm` in single-tooth zones (drive side),
/// `lambda = +1` before the pitch point and `-1` after it; in double zones the two pairs slide in
/// opposite directions with equal shares and the friction moments cancel (`h = 1`). The back side
/// uses `h = 1 - mu*lambda*arm` (the normal force reverses, the sliding direction does not).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Friction {
    /// Friction coefficient `mu >= 0`.
    pub mu: f64,
    /// Dimensionless equivalent friction arm `g` (docs/model.md §3), `>= 0`.
    pub arm: f64,
    /// Phase of the pitch point within the cycle, in `[eps-1, 1]`.
    pub pitch: f64,
}

impl Default for Friction {
    fn default() -> Self {
        Friction {
            mu: 0.0,
            arm: 0.0,
            pitch: 0.8,
        }
    }
}

/// Model of the back (non-drive) flank.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "model", rename_all = "snake_case", deny_unknown_fields)]
pub enum BackSide {
    /// Continuous back-side contact with the same stiffness and contact law as the drive side.
    Contact,
    /// Rigid stop with restitution (seed A).
    Impact(ImpactLaw),
}

/// Localized breakage of one pinion tooth (docs/model.md §2).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Breakage {
    /// Pinion tooth number `z_p`: the excitation period is `z_p` mesh cycles.
    pub z_p: u32,
    /// Index `n_b` of the broken cycle within the excitation period, `0 <= n_b < z_p`.
    pub broken_cycle: u32,
    /// Reduced contact ratio `eps_b` in `(1, eps]`.
    pub eps_b: f64,
    /// Stiffness of "single-tooth zone II" `[eps_b-1, eps-1)` of the broken cycle.
    pub k_zone2: f64,
}

/// The full dimensionless parameter set of a [`crate::MeshModel`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelParams {
    /// Dimensionless mesh frequency `omega = omega_h/omega_n`.
    pub omega: f64,
    /// Mean load `F = (T_p/R_bp)/(k_av*b_c)`.
    #[serde(rename = "F")]
    pub load: f64,
    /// Error amplitude `xi = E_a/b_c`.
    pub xi: f64,
    /// Mesh damping `c = c_m/(m_e*omega_n) = 2*zeta` (acts in contact only).
    pub c: f64,
    /// Half backlash in double-tooth zones `D_d`.
    #[serde(rename = "D_d")]
    pub d_double: f64,
    /// Half backlash in single-tooth zones `D_s >= D_d`.
    #[serde(rename = "D_s")]
    pub d_single: f64,
    /// Contact ratio `eps` in `(1, 2)`: double zone `[0, eps-1)`, single zone `[eps-1, 1)`.
    pub eps: f64,
    /// Mesh stiffness form.
    pub stiffness: StiffnessForm,
    /// Drive- and back-side contact law.
    pub contact: ContactLaw,
    /// Back flank model.
    pub back_side: BackSide,
    /// Friction.
    #[serde(default)]
    pub friction: Friction,
    /// Optional localized tooth breakage.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub breakage: Option<Breakage>,
    /// Unilateral contact: the mesh force cannot pull (`F_m >= 0` on the drive side, `<= 0` on
    /// the back side). Off by default: as in both seeds, a damped contact may carry a tensile
    /// force until `x` returns to `D` (docs/model.md §3).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub unilateral: bool,
}

/// Parameter names accepted by [`ModelParams::set`] (and by `--set`, sweeps, maps).
pub const PARAMETER_NAMES: &[&str] = &[
    "omega",
    "F",
    "xi",
    "c",
    "D",
    "D_d",
    "D_s",
    "eps",
    "kappa",
    "k",
    "k_double",
    "k_single",
    "exponent",
    "restitution",
    "R",
    "v_stick",
    "k_c",
    "mu",
    "arm",
    "pitch",
    "eps_b",
    "k_zone2",
    "z_p",
    "broken_cycle",
];

impl ModelParams {
    /// Value of a named parameter (names of [`PARAMETER_NAMES`]; `D` reads `D_s`).
    pub fn get(&self, name: &str) -> Result<f64, ModelError> {
        let name = if name == "D" { "D_s" } else { name };
        self.clone().field_mut(name).map(|f| *f)
    }

    /// Sets a named parameter. `D` is the static half backlash: it sets `D_s` and shifts `D_d` by
    /// the same amount, keeping their difference (equal to `D` when they were equal), so a
    /// backlash sweep keeps a time-varying backlash time-varying. Values are not range-checked here:
    /// [`crate::MeshModel::new`] validates the whole set.
    ///
    /// ```
    /// let mut p = geardyn_model::presets::classic();
    /// p.set("omega", 1.3).unwrap();
    /// assert_eq!(p.omega, 1.3);
    /// assert!(p.set("omgea", 1.0).is_err());
    /// ```
    pub fn set(&mut self, name: &str, value: f64) -> Result<(), ModelError> {
        if name == "D" {
            self.d_double = value - (self.d_single - self.d_double);
            self.d_single = value;
            return Ok(());
        }
        *self.field_mut(name)? = value;
        Ok(())
    }

    fn field_mut(&mut self, name: &str) -> Result<&mut f64, ModelError> {
        let unknown = |why: &str| ModelError::Inconsistent {
            field: name.to_string(),
            reason: why.to_string(),
        };
        Ok(match name {
            "omega" => &mut self.omega,
            "F" => &mut self.load,
            "xi" => &mut self.xi,
            "c" => &mut self.c,
            "D_d" => &mut self.d_double,
            "D_s" => &mut self.d_single,
            "eps" => &mut self.eps,
            "mu" => &mut self.friction.mu,
            "arm" => &mut self.friction.arm,
            "pitch" => &mut self.friction.pitch,
            "kappa" => match &mut self.stiffness {
                StiffnessForm::Harmonic { kappa } => kappa,
                _ => return Err(unknown("kappa needs stiffness.form = \"harmonic\"")),
            },
            "k" => match &mut self.stiffness {
                StiffnessForm::Constant { k } => k,
                _ => return Err(unknown("k needs stiffness.form = \"constant\"")),
            },
            "k_double" | "k_single" => match &mut self.stiffness {
                StiffnessForm::Rectangular { k_double, k_single } => {
                    if name == "k_double" {
                        k_double
                    } else {
                        k_single
                    }
                }
                _ => return Err(unknown("needs stiffness.form = \"rectangular\"")),
            },
            "exponent" | "restitution" => match (self.contact.parameters_mut(), name) {
                ((Some(exponent), _), "exponent") => exponent,
                ((_, Some(restitution)), "restitution") => restitution,
                ((None, _), _) => {
                    return Err(unknown("contact.law = \"linear\" has no such parameter"))
                }
                _ => return Err(unknown("contact.law = \"power\" has no restitution")),
            },
            "R" | "v_stick" | "k_c" => match &mut self.back_side {
                BackSide::Impact(law) => match name {
                    "R" => &mut law.restitution,
                    "v_stick" => &mut law.v_stick,
                    _ => &mut law.k_c,
                },
                BackSide::Contact => {
                    return Err(unknown("needs back_side.model = \"impact\""));
                }
            },
            "eps_b" | "k_zone2" => match &mut self.breakage {
                Some(b) => {
                    if name == "eps_b" {
                        &mut b.eps_b
                    } else {
                        &mut b.k_zone2
                    }
                }
                None => return Err(unknown("needs a [breakage] table")),
            },
            "z_p" | "broken_cycle" => {
                return Err(unknown(
                    "integer parameter: edit it in the config file, it cannot be swept",
                ))
            }
            _ => {
                return Err(ModelError::UnknownParameter {
                    name: name.to_string(),
                    known: PARAMETER_NAMES.join(", "),
                })
            }
        })
    }

    /// Mesh cycles per excitation period (`z_p` with breakage, else 1).
    pub fn cycles_per_period(&self) -> u32 {
        self.breakage.map_or(1, |b| b.z_p)
    }

    /// Excitation period `T_s = cycles * 2*pi/omega` (dimensionless time).
    pub fn excitation_period(&self) -> f64 {
        self.cycles_per_period() as f64 * 2.0 * std::f64::consts::PI / self.omega
    }
}
