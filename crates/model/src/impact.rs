//! Back-side impact law (seed A, docs/model.md §3): rigid stop at `x = -D`, restitution `x'+ = -R x'-`,
//! sticking below a velocity threshold, and the peak force of the impact.
//!
//! **Peak impact force.** Seed A quotes Hu et al. for the maximum impact force; the formula is
//! garbled in the paraphrase. geardyn uses the dissipative Hertz law of Lankarani & Nikravesh
//! (J. Mech. Des. 112 (1990) 369), `F = k_c d^(3/2) (1 + 3(1-R^2)/(4 v-) d')`, whose elastic limit is
//! the classical Hertz impact peak `F_H = k_c (5 v-^2 / (4 k_c))^(3/5)` (unit mass: the equivalent
//! mass in dimensionless units). Scaling `d` by the Hertz maximum indentation shows the peak is
//! `F = F_H * phi(R)` with `phi` a function of `R` alone, computed once per model by integrating
//! `u'' = -(5/4) u^(3/2) (1 + beta u')`, `beta = 3(1-R^2)/4`, `u(0) = 0`, `u'(0) = 1`.
//! Dimensionless: `k_c` in units of `k_av * b_c^(-1/2)`, velocities in `b_c*omega_n`.

use serde::{Deserialize, Serialize};

/// Allowed range of the dimensionless back-side contact stiffness `k_c` (the mesh stiffness is 1;
/// beyond six decades either way the peak-force formula leaves its physical meaning and, at the
/// extremes of `f64`, its range).
pub const K_C_RANGE: (f64, f64) = (1e-6, 1e6);

/// Parameters of the back-side impact law.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ImpactLaw {
    /// Restitution coefficient `R` in `[0, 1]`.
    #[serde(rename = "R")]
    pub restitution: f64,
    /// Impact speed below which the tooth sticks to the stop (if pushed into it), dimensionless.
    pub v_stick: f64,
    /// Dimensionless back-side Hertz contact stiffness `k_c` (for the peak force only).
    pub k_c: f64,
}

impl Default for ImpactLaw {
    fn default() -> Self {
        ImpactLaw {
            restitution: 0.85,
            v_stick: 1e-6,
            k_c: 1.0,
        }
    }
}

impl ImpactLaw {
    /// Elastic Hertz peak force of an impact at speed `v` (closed form, unit mass), written as
    /// `k_c^(2/5) (5/4)^(3/5) |v|^(6/5)` so no intermediate overflows; saturates at `f64::MAX`.
    pub fn hertz_peak(&self, v: f64) -> f64 {
        (self.k_c.powf(0.4) * 1.25f64.powf(0.6) * v.abs().powf(1.2)).min(f64::MAX)
    }

    /// Dissipation factor `phi(R) = F_peak / F_H` of the Lankarani–Nikravesh law (see module doc).
    pub fn peak_factor(&self) -> f64 {
        let beta = 0.75 * (1.0 - self.restitution * self.restitution);
        let f = |u: f64, w: f64| -1.25 * u.max(0.0).powf(1.5) * (1.0 + beta * w);
        let force = |u: f64, w: f64| u.max(0.0).powf(1.5) * (1.0 + beta * w);
        let (mut u, mut w) = (0.0f64, 1.0f64);
        let h = 2e-4;
        let mut peak: f64 = 0.0;
        // the compression ends before s = 2 (elastic: u_max = 1 at s ~ 1.47)
        for _ in 0..20_000 {
            (u, w) = rk4_second_order(&f, u, w, h);
            let fnow = force(u, w);
            if fnow < peak && w < 0.0 {
                break;
            }
            peak = peak.max(fnow);
        }
        peak
    }

    /// Checks the parameters; `Err((field, value, allowed))`.
    pub fn validate(&self) -> Result<(), (&'static str, f64, &'static str)> {
        if !(0.0..=1.0).contains(&self.restitution) {
            return Err(("back_side.R", self.restitution, "[0, 1]"));
        }
        if !(self.v_stick >= 0.0 && self.v_stick < 1.0) {
            return Err(("back_side.v_stick", self.v_stick, "[0, 1)"));
        }
        if !(K_C_RANGE.0..=K_C_RANGE.1).contains(&self.k_c) {
            return Err(("back_side.k_c", self.k_c, "[1e-6, 1e6]"));
        }
        Ok(())
    }
}

/// One classical RK4 step of `x' = v`, `v' = f(x, v)` of length `h` (the one-impact integrations
/// of the contact and impact laws: a peak factor, a restitution).
pub(crate) fn rk4_second_order(f: &impl Fn(f64, f64) -> f64, x: f64, v: f64, h: f64) -> (f64, f64) {
    let k1 = (v, f(x, v));
    let k2 = (
        v + 0.5 * h * k1.1,
        f(x + 0.5 * h * k1.0, v + 0.5 * h * k1.1),
    );
    let k3 = (
        v + 0.5 * h * k2.1,
        f(x + 0.5 * h * k2.0, v + 0.5 * h * k2.1),
    );
    let k4 = (v + h * k3.1, f(x + h * k3.0, v + h * k3.1));
    (
        x + h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0),
        v + h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn elastic_limit_gives_hertz_closed_form() {
        let law = ImpactLaw {
            restitution: 1.0,
            ..Default::default()
        };
        assert!((law.peak_factor() - 1.0).abs() < 1e-6);
        // Hertz closed form: F = k (5 m v^2/(4k))^(3/5); with k = 2, v = 0.3
        let law = ImpactLaw {
            restitution: 1.0,
            v_stick: 0.0,
            k_c: 2.0,
        };
        let expect = 2.0 * (5.0 * 0.09 / 8.0f64).powf(0.6);
        assert!((law.hertz_peak(0.3) - expect).abs() < 1e-15);
    }

    #[test]
    fn dissipation_lowers_peak_force_monotonically() {
        // The hysteresis term shortens the compression: the peak falls below the elastic Hertz
        // value, more so for lower R, but the force at the elastic maximum indentation bounds it
        // from below by 1 - beta.
        let mut last = 1.0 + 1e-9;
        for r in [0.95, 0.85, 0.7, 0.5] {
            let phi = ImpactLaw {
                restitution: r,
                ..Default::default()
            }
            .peak_factor();
            let beta = 0.75 * (1.0 - r * r);
            assert!(phi < last && phi > 1.0 - beta, "R={r}: {phi}");
            last = phi;
        }
    }
}
