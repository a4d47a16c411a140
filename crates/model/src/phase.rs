//! Mesh phase and a fast, accurate cosine of a phase given in cycles.
//!
//! The excitation `cos(omega*tau)` is evaluated twice per RK4 step in the hot loop; `libm` cos pays
//! for a general argument reduction we do not need because the phase in cycles is already known.
//! [`cos_cycles`] reduces exactly to an octant and uses Taylor polynomials of degree 14/15 on
//! `|x| <= pi/4` (truncation below 1.1e-15; tested against `f64::cos`).

use std::f64::consts::PI;

/// `cos(2*pi*s)` for any finite `s` (a phase in cycles). Absolute error below 2e-15 plus the
/// rounding of `s` itself.
///
/// ```
/// let s = 0.123;
/// assert!((geardyn_model::phase::cos_cycles(s) - (2.0 * std::f64::consts::PI * s).cos()).abs() < 1e-15);
/// ```
#[inline]
pub fn cos_cycles(s: f64) -> f64 {
    let r = s - round_fast(s); // [-0.5, 0.5]
    let q = round_fast(4.0 * r); // octant centre: -2..=2
    let x = 2.0 * PI * (r - 0.25 * q); // |x| <= pi/4
    let x2 = x * x;
    // cos(x + q*pi/2): only the polynomial the octant needs (the branch is predictable: the
    // phase advances slowly between calls)
    let qi = q as i64;
    if qi & 1 == 0 {
        // cos x, Taylor to x^14 (Horner)
        let c = 1.0
            + x2 * (-1.0 / 2.0
                + x2 * (1.0 / 24.0
                    + x2 * (-1.0 / 720.0
                        + x2 * (1.0 / 40320.0
                            + x2 * (-1.0 / 3628800.0
                                + x2 * (1.0 / 479001600.0 + x2 * (-1.0 / 87178291200.0)))))));
        if qi == 0 {
            c
        } else {
            -c
        }
    } else {
        // sin x, Taylor to x^15
        let sn = x
            * (1.0
                + x2 * (-1.0 / 6.0
                    + x2 * (1.0 / 120.0
                        + x2 * (-1.0 / 5040.0
                            + x2 * (1.0 / 362880.0
                                + x2 * (-1.0 / 39916800.0
                                    + x2 * (1.0 / 6227020800.0
                                        + x2 * (-1.0 / 1307674368000.0))))))));
        if qi == 1 {
            -sn
        } else {
            sn
        }
    }
}

/// Round to nearest (ties to even) by the 1.5*2^52 trick: `f64::round` is a libm call on the
/// baseline x86-64 target and showed up at 8% of the integrator's time. Exact for `|s| < 2^51`;
/// larger arguments (no fractional part anyway) are returned as they are.
#[inline(always)]
fn round_fast(s: f64) -> f64 {
    const MAGIC: f64 = 6_755_399_441_055_744.0; // 1.5 * 2^52
    if s.abs() < 2_251_799_813_685_248.0 {
        (s + MAGIC) - MAGIC
    } else {
        s
    }
}

/// Mesh phase `phi = frac(omega*tau/(2*pi))` in `[0, 1)` (docs/model.md §2).
#[inline]
pub fn mesh_phase(omega: f64, tau: f64) -> f64 {
    let s = omega * tau / (2.0 * PI);
    s - s.floor()
}

/// Mesh cycle index `n = floor(omega*tau/(2*pi))` (docs/model.md §2).
#[inline]
pub fn mesh_cycle(omega: f64, tau: f64) -> i64 {
    (omega * tau / (2.0 * PI)).floor() as i64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cos_cycles_matches_libm_everywhere() {
        for k in 0..200_001 {
            let s = -50.0 + 100.0 * k as f64 / 200_000.0 + 1e-7 * (k % 7) as f64;
            let e = (cos_cycles(s) - (2.0 * PI * s).cos()).abs();
            // libm's argument 2*pi*s carries a rounding error ~|2*pi*s|*eps; ours reduces exactly
            let allowed = 2e-15 + 2.0 * PI * s.abs() * f64::EPSILON;
            assert!(e < allowed, "s = {s}: error {e}");
        }
        for k in 0..10_000 {
            let s = k as f64 / 10_000.0;
            assert!((cos_cycles(s) - (2.0 * PI * s).cos()).abs() < 2e-15);
        }
        assert_eq!(cos_cycles(0.0), 1.0);
        assert!((cos_cycles(0.5) + 1.0).abs() < 1e-16);
    }

    #[test]
    fn phase_and_cycle() {
        let omega = 1.3;
        let tau = 2.0 * PI / omega * 7.25;
        assert_eq!(mesh_cycle(omega, tau), 7);
        assert!((mesh_phase(omega, tau) - 0.25).abs() < 1e-12);
    }
}
