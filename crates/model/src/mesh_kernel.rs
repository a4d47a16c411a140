//! The mesh force `F_m` and its tangent terms, written once for the scalar model
//! ([`MeshModel`](crate::MeshModel)) and the lockstep lanes ([`MeshLanes`](crate::MeshLanes)).
//!
//! **Why one kernel.** The lanes promise to follow the scalar RK4 path to the bit where their
//! coefficients agree (docs of [`geardyn_solvers::ensemble`] and [`crate::mesh_lanes`]): the same
//! IEEE operations in the same order, no fused multiply-add. Written out in both places, that
//! promise held only as long as the copies were edited together; here both call the same
//! `#[inline(always)]` functions, so the expression is the same by construction. The functions
//! are per lane, `f64` in and out: they inline into the lanes' loops, which vectorise over the
//! lanes as before (`geardyn bench`'s ensemble figure unchanged within noise).
//!
//! **Generic over the law, not the number type.** What differs between the two callers is the
//! contact law: the scalar model takes any [`ContactLaw`] and the hysteresis factor `chi` of the
//! current impact; the lanes cover the linear law without hysteresis only, and must not pay for
//! the rest. [`Elastic`] states the law; [`Linear`] is the lanes' law, whose `g(e) = e`,
//! `g' = 1` and absent hysteresis vanish at compile time (the lanes' force is then
//! `k (x - s D) + c x'`, as before).
//!
//! **Conventions.** Dimensionless (docs/model.md §2–3): state `x` (units of `b_c`), `x'` (units of
//! `b_c omega_n`), stiffness `k` (units of the mean mesh stiffness), damping `c = 2 zeta`, forces
//! in `k_av b_c`. A flank has the sign `s`: `+1` drive side, `-1` back side. The contact spring's
//! deflection is `e = x - s D` (`D` the half backlash), positive when the drive flank is
//! compressed; the elastic force is the odd extension `g(e)` of the law (`g(-e) = -g(e)`, so the
//! back flank's `-g(-x - D)` is `g(x + D)`), and the mesh force in contact is
//! `F_m = k g(e) (1 + s chi x') + c x'`, clamped to `[lo, hi]` for a unilateral (tension-free)
//! contact: `[0, inf]` on the drive flank, `[-inf, 0]` on the back flank. The acceleration is
//! `x'' = F + xi omega^2 cos(omega tau) - h_f F_m` with the friction factor `h_f` of the flank.
//!
//! The scalar model used to write the back flank as `-k g(-x - D) (1 - chi x')` and clamp with
//! `f64::max` / `f64::min`. The odd extension gives the same values bit for bit (negation is
//! exact; test `force_equals_the_per_flank_expressions`) except for the sign of an exactly zero
//! force (`x = -D` exactly with `c x' = 0`) and a NaN force, which the clamp maps to its bound
//! instead of 0; a NaN force comes only from a non-finite state, which the integrator reports
//! either way.

use crate::contact_law::ContactLaw;

/// The elastic part `g` of a contact law as the kernel evaluates it: odd in the deflection `e`.
pub trait Elastic: Copy {
    /// Whether the law may carry a hysteresis factor `chi != 0` (the factor's terms are compiled
    /// out otherwise).
    const HYSTERESIS: bool;
    /// Elastic force per unit stiffness, `g(e)` (units of `b_c`).
    fn g(self, e: f64) -> f64;
    /// Its slope `g'(e)` (dimensionless).
    fn slope(self, e: f64) -> f64;
}

/// The linear contact law without hysteresis (`g(e) = e`): the law of the lockstep lanes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Linear;

impl Elastic for Linear {
    const HYSTERESIS: bool = false;
    #[inline(always)]
    fn g(self, e: f64) -> f64 {
        e
    }
    #[inline(always)]
    fn slope(self, _e: f64) -> f64 {
        1.0
    }
}

impl Elastic for ContactLaw {
    const HYSTERESIS: bool = true;
    #[inline(always)]
    fn g(self, e: f64) -> f64 {
        self.elastic(e)
    }
    #[inline(always)]
    fn slope(self, e: f64) -> f64 {
        self.elastic_slope(e)
    }
}

/// One flank in contact: everything its mesh force depends on besides the state `(x, x')`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact<G> {
    /// The contact law.
    pub law: G,
    /// Mesh stiffness `k` at the evaluation time.
    pub k: f64,
    /// Signed half backlash `s D`: the spring's deflection is `x - off`.
    pub off: f64,
    /// Hysteresis factor times the flank sign, `s chi` (ignored by a law without hysteresis).
    pub schi: f64,
    /// Viscous mesh damping `c`.
    pub c: f64,
    /// Lower bound of a unilateral force (`0` on the drive flank, `-inf` on the back flank).
    pub lo: f64,
    /// Upper bound of a unilateral force (`+inf` on the drive flank, `0` on the back flank).
    pub hi: f64,
}

impl<G: Elastic> Contact<G> {
    /// The mesh force `F_m = k g(x - s D) (1 + s chi x') + c x'`, clamped to `[lo, hi]` when
    /// `unilateral` (see [`clamp`]).
    #[inline(always)]
    pub fn force(&self, x: f64, v: f64, unilateral: bool) -> f64 {
        let spring = self.k * self.law.g(x - self.off);
        let spring = if G::HYSTERESIS {
            spring * (1.0 + self.schi * v)
        } else {
            spring
        };
        let f = spring + self.c * v;
        if unilateral {
            clamp(f, self.lo, self.hi)
        } else {
            f
        }
    }

    /// Coefficients `(a, b)` of the linearised acceleration `d x'' = a dx + b dx'` for the
    /// friction factor `hf`: `a = -h_f k g'(e) (1 + s chi x')`, `b = -h_f (k g(e) s chi + c)`;
    /// both zero where a unilateral force is clamped (it does not depend on the state there).
    #[inline(always)]
    pub fn tangent(&self, hf: f64, x: f64, v: f64, unilateral: bool) -> (f64, f64) {
        if unilateral && self.force(x, v, true) == 0.0 {
            return (0.0, 0.0);
        }
        let e = x - self.off;
        let a = -hf * self.k * self.law.slope(e);
        if G::HYSTERESIS {
            (
                a * (1.0 + self.schi * v),
                -hf * (self.k * self.law.g(e) * self.schi + self.c),
            )
        } else {
            (a, -hf * self.c)
        }
    }
}

/// The excitation `F + xi omega^2 cos(omega tau)` from the load, the amplitude `xi omega^2` and
/// the cosine: the acceleration of a separated tooth pair.
#[inline(always)]
pub fn excitation(load: f64, xi_w2: f64, cos_wt: f64) -> f64 {
    load + xi_w2 * cos_wt
}

/// The acceleration `x'' = exc - h_f F_m` from the excitation, the friction factor of the flank
/// in contact and the mesh force.
#[inline(always)]
pub fn acceleration(exc: f64, hf: f64, fm: f64) -> f64 {
    exc - hf * fm
}

/// `f` clamped to `[lo, hi]`: `f.max(lo).min(hi)` for a non-NaN `f` (a NaN gives `lo`, then
/// `min(lo, hi)`), as two comparisons that vectorise (no NaN handling).
#[inline(always)]
pub fn clamp(f: f64, lo: f64, hi: f64) -> f64 {
    let f = if f > lo { f } else { lo };
    if f < hi {
        f
    } else {
        hi
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The kernel's force equals the expressions the scalar model wrote before it (penetration
    /// form on each flank, `max`/`min` clamps) bit for bit on nonzero values.
    #[test]
    fn force_equals_the_per_flank_expressions() {
        let laws = [
            ContactLaw::Linear,
            ContactLaw::Power { exponent: 1.5 },
            ContactLaw::HuntCrossley {
                exponent: 1.5,
                restitution: 0.8,
            },
        ];
        let mut s = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            ((s >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 6.0
        };
        for law in laws {
            for _ in 0..20_000 {
                let (x, v, k, d, chi, c) = (
                    next(),
                    next(),
                    1.0 + 0.1 * next(),
                    0.5 + 0.1 * next(),
                    next().abs(),
                    0.05 * next().abs(),
                );
                for uni in [false, true] {
                    // drive flank, as MeshModel wrote it
                    let g = law.elastic(x - d);
                    let f = k * g * (1.0 + chi * v) + c * v;
                    let want = if uni { f.max(0.0) } else { f };
                    let dr = Contact {
                        law,
                        k,
                        off: d,
                        schi: chi,
                        c,
                        lo: 0.0,
                        hi: f64::INFINITY,
                    };
                    assert_eq!(dr.force(x, v, uni).to_bits(), want.to_bits());
                    let dg = law.elastic_slope(x - d);
                    let (a, b) = dr.tangent(2.0, x, v, uni);
                    if !(uni && want == 0.0) {
                        assert_eq!(a.to_bits(), (-2.0 * k * dg * (1.0 + chi * v)).to_bits());
                        assert_eq!(b.to_bits(), (-2.0 * (k * g * chi + c)).to_bits());
                    }
                    // back flank
                    let g = law.elastic(-x - d);
                    let f = -k * g * (1.0 - chi * v) + c * v;
                    let want = if uni { f.min(0.0) } else { f };
                    let bk = Contact {
                        off: -d,
                        schi: -chi,
                        lo: f64::NEG_INFINITY,
                        hi: 0.0,
                        ..dr
                    };
                    assert_eq!(bk.force(x, v, uni).to_bits(), want.to_bits());
                    let dg = law.elastic_slope(-x - d);
                    let (a, b) = bk.tangent(2.0, x, v, uni);
                    if !(uni && want == 0.0) {
                        assert_eq!(a.to_bits(), (-2.0 * k * dg * (1.0 - chi * v)).to_bits());
                        assert_eq!(b.to_bits(), (-2.0 * (k * g * chi + c)).to_bits());
                    }
                }
            }
        }
    }

    /// The linear law without hysteresis is the lanes' `k (x - s D) + c x'` and `(-h k, -h c)`.
    #[test]
    fn linear_law_is_the_lanes_expression() {
        let (k, d, c, x, v) = (1.3, 0.7, 0.05, 0.9, -0.4);
        for s in [1.0, -1.0, 0.0] {
            let ct = Contact {
                law: Linear,
                k,
                off: s * d,
                schi: 0.0,
                c,
                lo: f64::NEG_INFINITY,
                hi: f64::INFINITY,
            };
            let f = ct.force(x, v, false);
            assert_eq!(f.to_bits(), (k * (x - s * d) + c * v).to_bits());
            assert_eq!(ct.tangent(1.1, x, v, false), (-1.1 * k, -1.1 * c));
        }
    }
}
