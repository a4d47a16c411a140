//! The checks of [`MeshModel::new`]: every parameter in its range (with the reason in the
//! message), the stiffness form's arrays consistent, the breakage inside the cycle, and the
//! tabulated friction factors positive.

use super::{MeshModel, MIN_BACKLASH};
use crate::error::ModelError;
use crate::impact::ImpactLaw;
use crate::params::{BackSide, Friction, ModelParams, StiffnessForm, ZonePiece};

pub(super) fn inv(field: &str, value: f64, allowed: &str) -> ModelError {
    ModelError::invalid(field, value, allowed)
}

pub(super) fn finite(field: &str, v: f64) -> Result<f64, ModelError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(inv(field, v, "a finite number"))
    }
}

/// What the scalar checks yield: `omega`, `eps`, the back-side impact law, friction on.
pub(super) type Scalars = (f64, f64, Option<ImpactLaw>, bool);

/// The scalar parameters (frequency, load, error, damping, backlash, contact ratio, contact and
/// impact laws, friction), in this order.
pub(super) fn scalars(p: &ModelParams) -> Result<Scalars, ModelError> {
    let omega = finite("omega", p.omega)?;
    // below 1e-3 one excitation period spans > 6000 natural periods: runs would take hours
    if !(1e-3..=1e3).contains(&omega) {
        return Err(inv(
            "omega",
            omega,
            "[0.001, 1000] (dimensionless mesh frequency omega_h/omega_n)",
        ));
    }
    // F and xi are in units of k b_c: beyond 1e3 the static deflection or the error
    // amplitude is a thousand backlash widths, far outside any gear pair, and a run only
    // overflows
    if !(0.0..=1e3).contains(&finite("F", p.load)?) {
        return Err(inv(
            "F",
            p.load,
            "[0, 1000] (static load in units of k b_c)",
        ));
    }
    if !(0.0..=1e3).contains(&finite("xi", p.xi)?) {
        return Err(inv(
            "xi",
            p.xi,
            "[0, 1000] (transmission error amplitude in units of b_c)",
        ));
    }
    // c = 2 zeta: beyond zeta = 10 the mesh is a rigid dashpot and the adaptive step
    // collapses; no gear pair is damped like that
    if !(0.0..=20.0).contains(&finite("c", p.c)?) {
        return Err(inv("c", p.c, "[0, 20] (c = 2 zeta)"));
    }
    // D is in units of b_c (of the order of the backlash itself): beyond 1e3 the teeth never
    // meet and the run only measures a free fall; below MIN_BACKLASH the two contact
    // boundaries +-D are closer than event location resolves them (D = 1e-13 "diverged"
    // while 1e-12 gave the bounded orbit of every larger D)
    if !(finite("D_d", p.d_double)? >= MIN_BACKLASH && p.d_double <= 1e3) {
        return Err(inv(
                "D_d",
                p.d_double,
                "[1e-9, 1000] (half backlash in units of b_c; below 1e-9 the contact boundaries +-D cannot be told apart by event location)",
            ));
    }
    if !(finite("D_s", p.d_single)? >= p.d_double && p.d_single <= 1e3) {
        return Err(inv(
            "D_s",
            p.d_single,
            &format!(
                "[D_d, 1000] with D_d = {} (the single-tooth half backlash is at least the \
                     double-tooth one; D sets both)",
                crate::error::num(p.d_double)
            ),
        ));
    }
    let eps = finite("eps", p.eps)?;
    if !(eps > 1.0 && eps < 2.0) {
        return Err(inv("eps", eps, "(1, 2)"));
    }
    p.contact.validate()?;
    let impact = match p.back_side {
        BackSide::Contact => None,
        BackSide::Impact(law) => {
            law.validate()?;
            Some(law)
        }
    };
    let fr = p.friction;
    if !(finite("friction.mu", fr.mu)? >= 0.0) {
        return Err(inv("friction.mu", fr.mu, "[0, inf)"));
    }
    if !(finite("friction.arm", fr.arm)? >= 0.0) {
        return Err(inv("friction.arm", fr.arm, "[0, inf)"));
    }
    let friction_on = fr.mu * fr.arm != 0.0;
    if friction_on && !(fr.pitch >= eps - 1.0 && fr.pitch <= 1.0) {
        return Err(inv(
            "friction.pitch",
            fr.pitch,
            "[eps-1, 1] (inside the single-tooth zone)",
        ));
    }
    Ok((omega, eps, impact, friction_on))
}

/// The stiffness form; returns the harmonic amplitude `kappa` (0 for the other forms).
pub(super) fn stiffness(p: &ModelParams) -> Result<f64, ModelError> {
    let fr = p.friction;
    let mut kappa = 0.0;
    match &p.stiffness {
        StiffnessForm::Constant { k } => {
            if !(finite("stiffness.k", *k)? > 0.0) {
                return Err(inv("stiffness.k", *k, "(0, inf)"));
            }
        }
        StiffnessForm::Harmonic { kappa: kp } => {
            if !(finite("stiffness.kappa", *kp)? >= 0.0 && *kp < 1.0) {
                return Err(inv(
                    "stiffness.kappa",
                    *kp,
                    "[0, 1) (k = 1 + kappa cos must stay positive)",
                ));
            }
            kappa = *kp;
        }
        StiffnessForm::Rectangular { k_double, k_single } => {
            if !(finite("stiffness.k_double", *k_double)? > 0.0) {
                return Err(inv("stiffness.k_double", *k_double, "(0, inf)"));
            }
            if !(finite("stiffness.k_single", *k_single)? > 0.0) {
                return Err(inv("stiffness.k_single", *k_single, "(0, inf)"));
            }
        }
        StiffnessForm::Zoned { pieces } => zoned(pieces, &fr)?,
        StiffnessForm::Table { phase, k } => table(phase, k)?,
    }
    Ok(kappa)
}

/// The zone pieces of a physical pair.
fn zoned(pieces: &[ZonePiece], fr: &Friction) -> Result<(), ModelError> {
    if fr.mu != 0.0 {
        return Err(ModelError::Inconsistent {
                field: "friction.mu".into(),
                reason: "has no effect on a physical pair, whose friction factors come from pair.mu: set pair.mu instead".into(),
            });
    }
    if pieces.is_empty() {
        return Err(ModelError::Inconsistent {
            field: "stiffness.pieces".into(),
            reason: "no zone pieces".into(),
        });
    }
    for (i, pc) in pieces.iter().enumerate() {
        let n = pc.k.len();
        if n < 2 || pc.h_drive.len() != n || pc.h_back.len() != n || !(pc.end > pc.start) {
            return Err(ModelError::Inconsistent {
                field: format!("stiffness.pieces[{i}]"),
                reason: "need end > start and k, h_drive, h_back of equal length >= 2".into(),
            });
        }
        for &v in &pc.k {
            if !(v.is_finite() && v > 0.0) {
                return Err(inv(&format!("stiffness.pieces[{i}].k"), v, "(0, inf)"));
            }
        }
    }
    Ok(())
}

/// A sampled stiffness `k(phase)` over the cycle.
fn table(phase: &[f64], k: &[f64]) -> Result<(), ModelError> {
    if phase.len() != k.len() || phase.len() < 2 {
        return Err(ModelError::Inconsistent {
            field: "stiffness.phase/stiffness.k".into(),
            reason: format!(
                "need two arrays of equal length >= 2, got {} and {}",
                phase.len(),
                k.len()
            ),
        });
    }
    for (i, w) in phase.windows(2).enumerate() {
        if !(w[1] > w[0]) {
            return Err(inv(
                &format!("stiffness.phase[{}]", i + 1),
                w[1],
                "strictly increasing",
            ));
        }
    }
    if !(phase[0] <= 0.0 && *phase.last().unwrap() >= 1.0) {
        return Err(ModelError::Inconsistent {
            field: "stiffness.phase".into(),
            reason: "must cover the whole cycle [0, 1]".into(),
        });
    }
    for (i, &v) in k.iter().enumerate() {
        if !(v.is_finite() && v > 0.0) {
            return Err(inv(&format!("stiffness.k[{i}]"), v, "(0, inf)"));
        }
    }
    Ok(())
}

/// The breakage; returns the cycles per excitation period (1 without breakage, else `z_p`).
pub(super) fn breakage(p: &ModelParams, eps: f64) -> Result<u32, ModelError> {
    let cycles = match p.breakage {
        None => 1,
        Some(b) => {
            if b.z_p < 2 {
                return Err(inv("breakage.z_p", b.z_p as f64, "an integer >= 2"));
            }
            if b.broken_cycle >= b.z_p {
                return Err(inv(
                    "breakage.broken_cycle",
                    b.broken_cycle as f64,
                    "[0, z_p - 1]",
                ));
            }
            if !(finite("breakage.eps_b", b.eps_b)? > 1.0 && b.eps_b <= eps) {
                return Err(inv("breakage.eps_b", b.eps_b, "(1, eps]"));
            }
            if !(finite("breakage.k_zone2", b.k_zone2)? > 0.0) {
                return Err(inv("breakage.k_zone2", b.k_zone2, "(0, inf)"));
            }
            b.z_p
        }
    };
    Ok(cycles)
}

/// The friction factors of the tabulated model: positive everywhere.
pub(super) fn friction_factors(m: &MeshModel) -> Result<(), ModelError> {
    if let Some(bad) = m.uniform_h_min() {
        return Err(inv(
            "friction (h from the pair's friction arms)",
            bad,
            "h > 0 everywhere: lower the friction coefficient",
        ));
    }
    for s in &m.segs {
        if !(s.h_drive > 0.0) {
            return Err(inv(
                "friction (h_drive = 1 + mu*lambda*arm)",
                s.h_drive,
                "h > 0: lower friction.mu or friction.arm",
            ));
        }
        if !(s.h_back > 0.0) {
            return Err(inv(
                "friction (h_back = 1 - mu*lambda*arm)",
                s.h_back,
                "h > 0: lower friction.mu or friction.arm",
            ));
        }
    }
    Ok(())
}
