//! The RK4 stages of the mesh lanes: the pair's [`LaneKernel`] (the field of `L` lanes from the
//! phase tables, stage by stage, driven by [`rk4_lanes`]) and the verdict on a lane's step (the
//! interior bound of its Hermite interpolant, then the scalar integrator's midpoint test).
//!
//! The kernel is compiled once per contact clamp and stiffness form (no per-lane branches). Every
//! lane evaluates the expressions of [`MeshModel`](crate::MeshModel) in the same order (no fused
//! multiply-add), so the result of a lane does not depend on the layout nor on the CPU copy of
//! the engine.

use super::{lane_contact, MeshLaneBlock, MeshLanes};
use crate::mesh_kernel as kernel;
use geardyn_solvers::dense::{hermite, nested_at};
use geardyn_solvers::ensemble::{rk4_lanes, At, LaneKernel, Soa, Stage, StepStart};
use geardyn_solvers::Direction;
use std::f64::consts::PI;

/// The coefficients every stage of one step reads, per lane: the signed half backlash, the
/// stiffness, excitation and friction factor at the middle and the end of the step (from the
/// phase tables, with the rounded-time correction of `MeshLanes::cos_k`).
pub struct StepCoef<const L: usize> {
    off: [f64; L],
    km: [f64; L],
    ke: [f64; L],
    excm: [f64; L],
    exce: [f64; L],
    hfm: [f64; L],
    hfe: [f64; L],
}

/// The pair's field over lanes for [`rk4_lanes`], specialised at compile time for the unilateral
/// clamp (`UNI`) and for a stiffness with a time correction (`HARM`; without it `k + dk * delta`
/// is `k + 0 * delta == k` exactly, as `delta` is finite).
pub struct Stages<'a, const UNI: bool, const HARM: bool>(pub &'a MeshLanes);

impl<const UNI: bool, const HARM: bool, const L: usize> LaneKernel<2, L> for Stages<'_, UNI, HARM> {
    type Lanes = MeshLaneBlock<L>;
    type Coef = StepCoef<L>;

    #[inline(always)]
    fn coef(&self, j: usize, ln: &MeshLaneBlock<L>, mid: &At<L>, end: &At<L>) -> StepCoef<L> {
        let t = self.0;
        // the row of step j, read once: middle (k2, k3) and end (k4, f1) coefficients
        let r = &t.rows[j];
        let (cm, dcm, kkm, dkm, hdm, hbm) =
            (r.cos[1], r.dcos[1], r.k[1], r.dk[1], r.hd[1], r.hb[1]);
        let (ce, dce, kke, dke, hde, hbe) =
            (r.cos[2], r.dcos[2], r.k[2], r.dk[2], r.hd[2], r.hb[2]);
        let d = r.d;
        let mut co = StepCoef {
            off: [0.0; L],
            km: [0.0; L],
            ke: [0.0; L],
            excm: [0.0; L],
            exce: [0.0; L],
            hfm: [0.0; L],
            hfe: [0.0; L],
        };
        for l in 0..L {
            let (sd, sb) = (ln.sd[l], ln.sb[l]);
            co.off[l] = (sd - sb) * d;
            // stage coefficients (as cos_k)
            let dm = t.phase_delta(ln.w[l] * mid.t[l] * (0.5 / PI), mid.grid[l]);
            let de = t.phase_delta(ln.w[l] * end.t[l] * (0.5 / PI), end.grid[l]);
            let (csm, cse) = (cm + dcm * dm, ce + dce * de);
            co.km[l] = if HARM { kkm + dkm * dm } else { kkm };
            co.ke[l] = if HARM { kke + dke * de } else { kke };
            co.excm[l] = kernel::excitation(ln.load[l], ln.xiw2[l], csm);
            co.exce[l] = kernel::excitation(ln.load[l], ln.xiw2[l], cse);
            co.hfm[l] = sd * hdm + sb * hbm;
            co.hfe[l] = sd * hde + sb * hbe;
        }
        co
    }

    #[inline(always)]
    fn field(
        &self,
        co: &StepCoef<L>,
        stage: Stage,
        ln: &MeshLaneBlock<L>,
        chunk: core::ops::Range<usize>,
        y: &Soa<2, L>,
        dy: &mut Soa<2, L>,
    ) {
        let (exc, hf, k) = if stage == Stage::Mid {
            (&co.excm, &co.hfm, &co.km)
        } else {
            (&co.exce, &co.hfe, &co.ke)
        };
        for l in chunk {
            let (x, v) = (y[0][l], y[1][l]);
            let fm = lane_contact(k[l], co.off[l], ln.c[l], ln.lo[l], ln.hi[l]).force(x, v, UNI);
            dy[0][l] = v;
            dy[1][l] = kernel::acceleration(exc[l], hf[l], fm);
        }
    }
}

/// The verdict of one lane's step from `y0` (field `f0`) to `y1` (field `f1`) of length `h`:
/// `(clear, finite)`, `clear` when the step is finite and both armed guards (`x - D` unless in
/// back contact, `x + D` unless in drive contact) keep their sign at the ends and stay farther
/// from zero than the interior bound of the Hermite interpolant lets them move (the rigorous
/// bound of the scalar integrator: `0.25 max(|r2| + |r3|)` over `x` and `x'`).
#[inline(always)]
fn verdict([y0, f0, y1, f1]: [[f64; 2]; 4], h: f64, d: f64, sd: f64, sb: f64) -> (bool, bool) {
    let [_, _, r2x, r3x] = hermite(y0[0], y1[0], f0[0], f1[0], h);
    let [_, _, r2v, r3v] = hermite(y0[1], y1[1], f0[1], f1[1], h);
    // (a NaN in the first sum gives a NaN margin, one in the second is dropped by max_fast: a
    // NaN there comes from a non-finite end, and `finite` keeps such a lane from being clear)
    let dev = max_fast(r2x.abs() + r3x.abs(), r2v.abs() + r3v.abs());
    // all three finite (tested one by one: a plain sum overflows on finite values, and
    // `v * 0` sums were slower)
    let finite = (y1[0].abs() < f64::INFINITY)
        & (y1[1].abs() < f64::INFINITY)
        & (f1[1].abs() < f64::INFINITY);
    let margin = 0.25 * dev;
    // A guard x -+ D keeps its sign at both ends and stays farther than the margin from zero
    // exactly when the smaller end value exceeds the margin or the larger one is below minus
    // it; rounding is monotone, so min(x0, x1) - D is the smaller of x0 - D and x1 - D.
    let (lo, hi) = (min_fast(y0[0], y1[0]), max_fast(y0[0], y1[0]));
    let ca = (lo - d > margin) | (hi - d < -margin);
    let cb = (lo + d > margin) | (hi + d < -margin);
    (finite & ((sb != 0.0) | ca) & ((sd != 0.0) | cb), finite)
}

/// `a.max(b)` for a non-NaN `a` (then equal to `f64::max` for any `b`, NaN included; one
/// instruction instead of three).
#[inline(always)]
pub(super) fn max_fast(a: f64, b: f64) -> f64 {
    if b > a {
        b
    } else {
        a
    }
}

/// `a.min(b)` for non-NaN operands (equal to `f64::min` there; one instruction).
#[inline(always)]
pub(super) fn min_fast(a: f64, b: f64) -> f64 {
    if a < b {
        a
    } else {
        b
    }
}

impl MeshLanes {
    /// For a lane whose step has no guard sign change at its ends but does not clear the interior
    /// bound: the scalar integrator's next test (`find_crossing`): the guards at the midpoint of
    /// the Hermite interpolant and the vertex of the parabola through the three samples. `true`
    /// when that test finds no guard near zero (the scalar step would be an ordinary one); `false`
    /// when the scalar integrator must take the step (an event at an end, or a possible graze).
    #[allow(clippy::too_many_arguments)]
    #[cold]
    #[inline(never)]
    fn no_event_by_midpoint<const L: usize>(
        &self,
        d: f64,
        sd: f64,
        sb: f64,
        h: f64,
        l: usize,
        y0: &Soa<2, L>,
        f0: &Soa<2, L>,
        y1: &Soa<2, L>,
        f1: &Soa<2, L>,
    ) -> bool {
        // Hermite interpolant of x (Step::hermite) at theta = 1/2 (Step::at_theta)
        let [r0, r1, r2, r3] = hermite(y0[0][l], y1[0][l], f0[0][l], f1[0][l], h);
        let xm = nested_at([r0, r1, r2, r3, 0.0], 0.5);
        let x1 = y1[0][l];
        // armed guards: (value at start, middle, end, direction)
        let mut guards = [(0.0, 0.0, 0.0, Direction::Rising); 2];
        let rising = |r: bool| {
            if r {
                Direction::Rising
            } else {
                Direction::Falling
            }
        };
        let mut n = 0;
        if sb == 0.0 {
            // x - D: rising when separated, falling in drive contact
            guards[n] = (r0 - d, xm - d, x1 - d, rising(sd == 0.0));
            n += 1;
        }
        if sd == 0.0 {
            // x + D: falling when separated, rising in back contact
            guards[n] = (r0 + d, xm + d, x1 + d, rising(sb != 0.0));
            n += 1;
        }
        for &(p, _, b, dir) in &guards[..n] {
            if dir.crossed(p, b) {
                return false;
            }
        }
        for &(p, a, b, dir) in &guards[..n] {
            if dir.near_crossing(p, a, b) {
                return false;
            }
        }
        true
    }

    /// The RK4 step of every lane by the stages ([`rk4_lanes`] over the [`Stages`] of the
    /// table's clamp and stiffness form: the scalar integrator's arithmetic, so its results) on
    /// any table, affine or not; returns the lanes that take it, as
    /// [`Lockstep::step`](geardyn_solvers::ensemble::Lockstep::step): those whose step is finite
    /// and clears both guards by the interior bound, and those the midpoint test lets through
    /// (`MeshLanes::settle`). `max`/`min` are plain comparisons: the `max` chain equals
    /// `f64::max`'s for any operand, the `min` only differs on a NaN state, whose lane is not
    /// finite and therefore not cleared either way. Public for callers that need the state's
    /// scalar trajectory bit for bit (the Lyapunov lanes: the decisions that continue from their
    /// end state).
    #[inline(always)]
    pub fn step_stages<const L: usize>(
        &self,
        s: &StepStart<'_, 2, L>,
        ln: &MeshLaneBlock<L>,
        y1: &mut Soa<2, L>,
        f1: &mut Soa<2, L>,
    ) -> u32 {
        // one copy of the stages per clamp and stiffness form
        match (self.unilateral, self.harmonic) {
            (false, false) => rk4_lanes(&Stages::<false, false>(self), s, ln, y1, f1),
            (false, true) => rk4_lanes(&Stages::<false, true>(self), s, ln, y1, f1),
            (true, false) => rk4_lanes(&Stages::<true, false>(self), s, ln, y1, f1),
            (true, true) => rk4_lanes(&Stages::<true, true>(self), s, ln, y1, f1),
        }
        let StepStart {
            j, t0, t1, y0, f0, ..
        } = *s;
        let d = self.rows[j].d;
        let mut bits = [0u64; L];
        for l in 0..L {
            let (ok, finite) = verdict(
                [
                    [y0[0][l], y0[1][l]],
                    [f0[0][l], f0[1][l]],
                    [y1[0][l], y1[1][l]],
                    [f1[0][l], f1[1][l]],
                ],
                t1[l] - t0[l],
                d,
                ln.sd[l],
                ln.sb[l],
            );
            bits[l] = ((ok as u64) << l) | ((finite as u64) << (32 + l));
        }
        let bits = bits.iter().fold(0, |m, b| m | b);
        self.settle(s, ln, y1, f1, bits)
    }

    /// The lanes that take a kernel's step (`bits`: clear, and finite in the upper half): the
    /// clear ones, and the finite ones near a surface without a sign change at the ends whose
    /// step the scalar integrator's midpoint test would take as an ordinary one (rare: next to
    /// events).
    #[inline(always)]
    pub(super) fn settle<const L: usize>(
        &self,
        s: &StepStart<'_, 2, L>,
        ln: &MeshLaneBlock<L>,
        y1: &Soa<2, L>,
        f1: &Soa<2, L>,
        bits: u64,
    ) -> u32 {
        let StepStart {
            j, t0, t1, y0, f0, ..
        } = *s;
        let mut mask = bits as u32;
        let mut rest = (bits >> 32) as u32 & !mask;
        if rest != 0 {
            let d = self.rows[j].d;
            while rest != 0 {
                let l = rest.trailing_zeros() as usize;
                rest &= rest - 1;
                let h = t1[l] - t0[l];
                if self.no_event_by_midpoint(d, ln.sd[l], ln.sb[l], h, l, y0, f0, y1, f1) {
                    mask |= 1 << l;
                }
            }
        }
        mask
    }
}

#[cfg(test)]
mod tests {
    use super::verdict;

    /// The verdict as the scalar integrator states it: each armed guard keeps its sign at both
    /// ends and both end values are farther from zero than the margin.
    fn direct([y0, f0, y1, f1]: [[f64; 2]; 4], h: f64, d: f64, sd: f64, sb: f64) -> bool {
        let mut dev = 0.0f64;
        for i in 0..2 {
            let r1 = y1[i] - y0[i];
            let r2 = h * f0[i] - r1;
            let r3 = r1 - h * f1[i] - r2;
            dev = dev.max(r2.abs() + r3.abs());
        }
        let m = 0.25 * dev;
        let keeps = |a: f64, b: f64| ((a > 0.0) == (b > 0.0)) && a.abs().min(b.abs()) > m;
        let finite = y1.iter().chain(f1.iter()).all(|v| v.is_finite());
        finite
            && (sb != 0.0 || keeps(y0[0] - d, y1[0] - d))
            && (sd != 0.0 || keeps(y0[0] + d, y1[0] + d))
    }

    #[test]
    fn verdict_equals_the_direct_statement() {
        // a small deterministic generator (values near the surfaces, exact zeros, signed zeros)
        let mut s = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            s
        };
        let d = 1.0;
        let picks = [
            -1.0,
            1.0,
            -0.0,
            0.0,
            1.0 + 1e-12,
            -1.0 - 1e-12,
            0.999_999,
            2.5,
            -3.0,
            // overflow of the step's sums, the smallest subnormal
            1e308,
            -1e308,
            f64::MAX,
            5e-324,
        ];
        let mut checked = 0;
        for _ in 0..200_000 {
            let mut v = [0.0; 8];
            for x in v.iter_mut() {
                let r = next();
                *x = if r % 3 == 0 {
                    picks[(r >> 8) as usize % picks.len()]
                } else {
                    ((r >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 4.0
                };
            }
            let (sd, sb) = match next() % 3 {
                0 => (1.0, 0.0),
                1 => (0.0, 1.0),
                _ => (0.0, 0.0),
            };
            let h = 1e-2 * (1 + next() % 4) as f64;
            let (y0, f0, y1, f1) = ([v[0], v[1]], [v[2], v[3]], [v[4], v[5]], [v[6], v[7]]);
            assert_eq!(
                verdict([y0, f0, y1, f1], h, d, sd, sb).0,
                direct([y0, f0, y1, f1], h, d, sd, sb),
                "{y0:?} {f0:?} {y1:?} {f1:?} {h} {sd} {sb}"
            );
            checked += 1;
        }
        assert_eq!(checked, 200_000);
        // a non-finite end is never clear
        let nan = f64::NAN;
        assert!(
            !verdict(
                [[0.0, 0.0], [0.0, 0.0], [nan, 0.0], [0.0, 0.0]],
                0.01,
                d,
                0.0,
                0.0
            )
            .0
        );
        assert!(
            !verdict(
                [[0.0, 0.0], [0.0, 0.0], [0.0, 0.0], [0.0, f64::INFINITY]],
                0.01,
                d,
                0.0,
                0.0
            )
            .1
        );
    }
}
