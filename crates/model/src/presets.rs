//! Built-in dimensionless parameter sets (docs/model.md §6).
//!
//! `classic` is case C1 exactly. `breakage` and `internal` are, for now, dimensionless stand-ins
//! for the seeds' physical pairs (rectangular stiffness, constant friction arm); the gear-physics
//! layer will later fill the same tables from geometry. Their numbers and where they come from are
//! stated below.

use crate::contact_law::ContactLaw;
use crate::error::ModelError;
use crate::impact::ImpactLaw;
use crate::params::{BackSide, Breakage, Friction, ModelParams, StiffnessForm};

/// Names of the built-in presets with a one-line description each.
pub const PRESETS: &[(&str, &str)] = &[
    ("classic", "case C1: k = 1 + 0.2 cos(omega tau), D = 1, c = 0.1, F = 0.1, xi = 0.2, linear contact on both sides"),
    ("breakage", "seed A stand-in: 40/40 external pair, one chipped pinion tooth (eps = 1.714, eps_b = 1.45), friction mu = 0.15, back-side impact R = 0.85"),
    ("internal", "seed B stand-in: 30/70 internal pair, D_s > D_d, continuous back-side contact, lubricated friction"),
];

/// Looks a preset up by name.
pub fn by_name(name: &str) -> Result<ModelParams, ModelError> {
    match name {
        "classic" => Ok(classic()),
        "breakage" => Ok(breakage()),
        "internal" => Ok(internal()),
        _ => Err(ModelError::Inconsistent {
            field: "preset".into(),
            reason: format!(
                "unknown preset '{name}': known are {}",
                PRESETS.iter().map(|p| p.0).collect::<Vec<_>>().join(", ")
            ),
        }),
    }
}

/// Case C1 (docs/model.md §6), at `omega = 0.8` (period 1).
pub fn classic() -> ModelParams {
    ModelParams {
        omega: 0.8,
        load: 0.1,
        xi: 0.2,
        c: 0.1,
        d_double: 1.0,
        d_single: 1.0,
        eps: 1.6,
        stiffness: StiffnessForm::Harmonic { kappa: 0.2 },
        contact: ContactLaw::Linear,
        back_side: BackSide::Contact,
        friction: Friction::default(),
        breakage: None,
        unilateral: false,
    }
}

/// Seed A stand-in: the 40/40, m = 3 mm, 20 deg, `ha* = 1` pair has the closed-form contact
/// ratio 1.714; the chipped tooth leaves mesh early with `eps_b = 1.45` (a moderate chip). The
/// rectangular stiffness has a double/single ratio of 1.5 and mean 1 over a healthy cycle; zone II
/// carries the healthy single-pair stiffness. `mu = 0.15`, `D = 1`, `c = 0.01`, `xi = 0.05`,
/// `R = 0.85` as in docs/model.md §6. The friction arm 0.1 is a placeholder until geometry provides it.
pub fn breakage() -> ModelParams {
    let eps: f64 = 1.714;
    let k_single = 1.0 / (1.5 * (eps - 1.0) + (2.0 - eps));
    ModelParams {
        omega: 1.0,
        load: 0.1,
        xi: 0.05,
        c: 0.01,
        d_double: 1.0,
        d_single: 1.0,
        eps,
        stiffness: StiffnessForm::Rectangular {
            k_double: 1.5 * k_single,
            k_single,
        },
        contact: ContactLaw::Linear,
        back_side: BackSide::Impact(ImpactLaw {
            restitution: 0.85,
            v_stick: 1e-6,
            k_c: 1.0,
        }),
        friction: Friction {
            mu: 0.15,
            arm: 0.1,
            pitch: (eps - 1.0 + 1.0) / 2.0,
        },
        breakage: Some(Breakage {
            z_p: 40,
            broken_cycle: 0,
            eps_b: 1.45,
            k_zone2: k_single,
        }),
        unilateral: false,
    }
}

/// Seed B: 30/70 internal pair (the physical `[pair]` of `geardyn-physics` replaces the stiffness,
/// zones, friction and backlash of this dimensionless stand-in), damping ratio 0.07 (`c = 0.14`),
/// `D_d = 0.95 < D_s = 1.05`, continuous back-side contact with seed B's Johnson-based contact
/// law (eq. 1): Lankarani–Nikravesh hysteresis with `c_e = 0.8` and the exponent of its Table 2.1
/// for a backlash of 0.2 mm ([`crate::johnson_exponent`]); `mu = 0.05`; at the multi-initial study
/// point `omega = 1.4, F = 0.07, xi = 0.23`. Seed B's impact-damping law (eq. 12) is selectable as
/// `contact.law = "impact_damping"`.
pub fn internal() -> ModelParams {
    let eps: f64 = 1.8;
    let k_single = 1.0 / (1.5 * (eps - 1.0) + (2.0 - eps));
    ModelParams {
        omega: 1.4,
        load: 0.07,
        xi: 0.23,
        c: 0.14,
        d_double: 0.95,
        d_single: 1.05,
        eps,
        stiffness: StiffnessForm::Rectangular {
            k_double: 1.5 * k_single,
            k_single,
        },
        contact: ContactLaw::LankaraniNikravesh {
            exponent: crate::contact_law::johnson_exponent(0.2).expect("0.2 mm is in the table"),
            restitution: 0.8,
        },
        back_side: BackSide::Contact,
        friction: Friction {
            mu: 0.05,
            arm: 0.1,
            pitch: 0.9,
        },
        breakage: None,
        unilateral: false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::MeshModel;

    #[test]
    fn presets_build_and_have_unit_mean_stiffness() {
        for (name, _) in PRESETS {
            let p = by_name(name).unwrap();
            let m = MeshModel::new(&p).unwrap();
            // mean of k over a healthy cycle is 1 (k normalised by k_av), by midpoint quadrature
            let n = 20_000;
            let cyc = if p.breakage.is_some() { 1.0 } else { 0.0 }; // skip the broken cycle 0
            let mean: f64 = (0..n)
                .map(|i| m.stiffness_at(cyc + (i as f64 + 0.5) / n as f64))
                .sum::<f64>()
                / n as f64;
            assert!((mean - 1.0).abs() < 1e-3, "{name}: {mean}");
        }
        assert!(by_name("nope").is_err());
    }

    #[test]
    fn breakage_contact_ratio_matches_closed_form() {
        // 40/40, m = 3, alpha = 20 deg, ha* = 1: eps = (2*sqrt(ra^2 - rb^2) - 2 r sin(alpha)) / (pi m cos(alpha))
        let (m, z, a) = (3.0f64, 40.0f64, 20f64.to_radians());
        let r = m * z / 2.0;
        let (ra, rb) = (r + m, r * a.cos());
        let eps = (2.0 * (ra * ra - rb * rb).sqrt() - 2.0 * r * a.sin())
            / (std::f64::consts::PI * m * a.cos());
        assert!((breakage().eps - eps).abs() < 1e-3, "{eps}");
    }
}
