//! The dimensionless operating point of a train's dynamic model (the pair model's parameters,
//! per mesh): what `--set omega=, F=, xi=, c=, D=, kappa=, ratio=` and a description's
//! `[operating]` table state, checked.

use crate::TrainError;
use serde::{Deserialize, Serialize};

/// Relative stiffness of each mesh over its mesh cycle (mean 1).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "form", rename_all = "snake_case")]
pub enum MeshStiffness {
    /// `1 + kappa cos(theta_k)`.
    Harmonic {
        /// Relative amplitude in `[0, 1)`.
        kappa: f64,
    },
    /// Rectangular wave of the mesh's contact ratio, `ratio = k_double / k_single >= 1`.
    Rectangular {
        /// Double- to single-tooth stiffness.
        ratio: f64,
    },
}

/// The dimensionless operating point of a train (the pair model's parameters, per mesh).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrainOperating {
    /// Mesh frequency of mesh 0 over `omega_ref` (`omega`).
    pub omega: f64,
    /// Static force of mesh 0 (`F`, units `k_ref b_c`).
    pub load: f64,
    /// Static transmission error amplitude of every mesh (`xi`, units `b_c`).
    pub xi: f64,
    /// Mesh damping (`c = 2 zeta` for mesh 0).
    pub c: f64,
    /// Half backlash of every mesh (`D`, units `b_c`).
    pub d: f64,
    /// Stiffness variation of every mesh.
    pub stiffness: MeshStiffness,
}

impl Default for TrainOperating {
    /// `omega = 1`, `F = 0.1`, `xi = 0`, `c = 0.1`, `D = 1`, rectangular stiffness of ratio 1.5
    /// (the seeds' pair values; no transmission error, the meshes excite each other through
    /// their stiffness).
    fn default() -> Self {
        TrainOperating {
            omega: 1.0,
            load: 0.1,
            xi: 0.0,
            c: 0.1,
            d: 1.0,
            stiffness: MeshStiffness::Rectangular { ratio: 1.5 },
        }
    }
}

impl TrainOperating {
    /// The fields `set` knows.
    pub const FIELDS: [&'static str; 7] = ["omega", "F", "xi", "c", "D", "kappa", "ratio"];

    /// Set a field by its name (`kappa`: harmonic stiffness of that amplitude; `ratio`:
    /// rectangular stiffness of that double- to single-tooth ratio), checked.
    pub fn set(&mut self, field: &str, v: f64) -> Result<(), TrainError> {
        match field {
            "omega" => self.omega = v,
            "F" => self.load = v,
            "xi" => self.xi = v,
            "c" => self.c = v,
            "D" => self.d = v,
            "kappa" => self.stiffness = MeshStiffness::Harmonic { kappa: v },
            "ratio" => self.stiffness = MeshStiffness::Rectangular { ratio: v },
            _ => {
                return Err(TrainError::Unknown {
                    field: field.to_string(),
                    allowed:
                        "one of omega, F, xi, c, D, kappa (harmonic stiffness), ratio (rectangular)"
                            .into(),
                })
            }
        }
        self.validate()
    }

    /// Ranges: `omega` in (0, 100], `F` in [0, 100], `xi` in [0, 100], `c` in [0, 10], `D` in
    /// [0, 1e3], `kappa` in [0, 1), `ratio` in [1, 10].
    pub fn validate(&self) -> Result<(), TrainError> {
        let check = |f: &str, v: f64, ok: bool, allowed: &str| {
            if v.is_finite() && ok {
                Ok(())
            } else {
                Err(crate::error::invalid(f, v, allowed))
            }
        };
        check(
            "omega",
            self.omega,
            self.omega > 0.0 && self.omega <= 100.0,
            "(0, 100]",
        )?;
        check(
            "F",
            self.load,
            (0.0..=100.0).contains(&self.load),
            "[0, 100]",
        )?;
        check("xi", self.xi, (0.0..=100.0).contains(&self.xi), "[0, 100]")?;
        check("c", self.c, (0.0..=10.0).contains(&self.c), "[0, 10]")?;
        check("D", self.d, (0.0..=1e3).contains(&self.d), "[0, 1000]")?;
        match self.stiffness {
            MeshStiffness::Harmonic { kappa } => {
                check("kappa", kappa, (0.0..1.0).contains(&kappa), "[0, 1)")
            }
            MeshStiffness::Rectangular { ratio } => {
                check("ratio", ratio, (1.0..=10.0).contains(&ratio), "[1, 10]")
            }
        }
    }
}
