//! The RK4 step of many lanes, written once: a system supplies its field over lanes as a
//! [`LaneKernel`] and [`rk4_lanes`] takes the RK4 stages of every lane around it.
//!
//! The stage arithmetic itself (`h/2`, `h/6`, the stage points `y + c k`, the combination
//! `y + h/6 (k1 + 2 (k2 + k3) + k4)`) is [`fractions`], [`stage_point`] and [`combine`], the same
//! functions the scalar RK4 step of [`crate::Integrator`] uses: a lane follows the scalar path
//! operation for operation (no fused multiply-add), so its result does not depend on the layout.
//!
//! Layout: the step's coefficients of every lane are computed once ([`LaneKernel::coef`]), then
//! the stages run stage by stage over chunks of [`LaneKernel::CHUNK`] lanes, so that the
//! dependent chains of the lanes' vector groups (~90 cycles per step) overlap in the instruction
//! stream instead of running one group after the other. Temporaries live on the stack; nothing
//! allocates, and everything is monomorphised per kernel.

use super::{At, Lockstep, Soa, Stage, StepStart};

/// Default lanes per chunk ([`LaneKernel::CHUNK`]). On the C1 kernel benchmark (16 lanes, one
/// thread) 16 ran at 5.2 ns per lane-step on AVX2 and 3.6 on AVX-512, against 8.1 / 6.5 for
/// chunks of 4 / 8 lanes and 7.9 for the lane-major loop.
pub const CHUNK: usize = 16;

pub use crate::rk4::{combine, fractions, stage_point};

/// A system's right-hand side over `L` lanes of dimension `N`, as the generic lane RK4 step
/// [`rk4_lanes`] drives it. A model implements it for its lockstep step
/// ([`Lockstep::step`]); its events, resets and the verdict on a step stay with its
/// [`Lockstep`] implementation.
///
/// ```
/// use geardyn_solvers::ensemble::{rk4_lanes, At, LaneKernel, Soa, Stage, StepStart};
///
/// /// `x' = -a x` in every lane, `a` per lane.
/// struct Decay;
/// impl<const L: usize> LaneKernel<1, L> for Decay {
///     type Lanes = [f64; L];
///     type Coef = ();
///     fn coef(&self, _j: usize, _lanes: &[f64; L], _mid: &At<L>, _end: &At<L>) {}
///     fn field(&self, _co: &(), _stage: Stage, a: &[f64; L], lanes: std::ops::Range<usize>,
///              y: &Soa<1, L>, dy: &mut Soa<1, L>) {
///         for l in lanes {
///             dy[0][l] = -a[l] * y[0][l];
///         }
///     }
/// }
/// let (y0, f0) = ([[1.0; 4]], [[-1.0; 4]]);
/// let (mut y1, mut f1) = ([[0.0; 4]], [[0.0; 4]]);
/// let s = StepStart { j: 0, t0: &[0.0; 4], t1: &[0.1; 4], grid: &[0.0; 4], y0: &y0, f0: &f0 };
/// rk4_lanes(&Decay, &s, &[1.0; 4], &mut y1, &mut f1);
/// assert!((y1[0][0] - (-0.1f64).exp()).abs() < 1e-7);
/// assert_eq!(f1[0][0], -y1[0][0]);
/// ```
pub trait LaneKernel<const N: usize, const L: usize> {
    /// Per-lane constants (as [`Lockstep::Lanes`]).
    type Lanes;
    /// The coefficients of one step that every stage of a lane reads (e.g. a periodic forcing
    /// at the middle and the end of the step), computed once per step.
    type Coef;
    /// Lanes advanced stage by stage together (a chunk); `L` itself when `L <= CHUNK`, else
    /// chunks of `CHUNK` when it divides `L`, else one lane at a time.
    const CHUNK: usize = CHUNK;

    /// The coefficients of step `j` of every lane, from the times and grid positions of the
    /// step's middle (`mid`) and end (`end`), as the scalar integrator rounds them.
    fn coef(&self, j: usize, lanes: &Self::Lanes, mid: &At<L>, end: &At<L>) -> Self::Coef;

    /// The field `dy = f(y)` at `stage` (middle or end of the step) of the lanes in `chunk`
    /// (the others are left alone).
    fn field(
        &self,
        co: &Self::Coef,
        stage: Stage,
        lanes: &Self::Lanes,
        chunk: core::ops::Range<usize>,
        y: &Soa<N, L>,
        dy: &mut Soa<N, L>,
    );
}

/// The RK4 step `s` of every lane (from `(s.y0, s.f0)` at `s.t0` to `s.t1`, see [`StepStart`]):
/// the end states `y1` and the end fields `f1`, with the arithmetic of the scalar RK4 step (see
/// the module doc).
#[inline(always)]
pub fn rk4_lanes<K, const N: usize, const L: usize>(
    k: &K,
    s: &StepStart<'_, N, L>,
    lanes: &K::Lanes,
    y1: &mut Soa<N, L>,
    f1: &mut Soa<N, L>,
) where
    K: LaneKernel<N, L> + ?Sized,
{
    let StepStart {
        j,
        t0,
        t1,
        grid,
        y0,
        f0,
    } = *s;
    let mut h = [0.0; L];
    let mut h2 = [0.0; L];
    let mut h6 = [0.0; L];
    let mut mid = At {
        t: [0.0; L],
        grid: [0.0; L],
    };
    let mut end = mid;
    for l in 0..L {
        h[l] = t1[l] - t0[l];
        (h2[l], h6[l]) = fractions(h[l]);
        mid.t[l] = t0[l] + h2[l];
        end.t[l] = t0[l] + h[l];
        mid.grid[l] = grid[l] + 0.5;
        end.grid[l] = grid[l] + 1.0;
    }
    let co = k.coef(j, lanes, &mid, &end);
    let width = if L <= K::CHUNK {
        L
    } else if L.is_multiple_of(K::CHUNK) {
        K::CHUNK
    } else {
        1
    };
    let mut yt = [[0.0; L]; N];
    let mut k2 = [[0.0; L]; N];
    let mut k3 = [[0.0; L]; N];
    let mut k4 = [[0.0; L]; N];
    for c0 in (0..L).step_by(width) {
        let c = c0..c0 + width;
        points(&mut yt, y0, &h2, f0, c.clone());
        k.field(&co, Stage::Mid, lanes, c.clone(), &yt, &mut k2);
        points(&mut yt, y0, &h2, &k2, c.clone());
        k.field(&co, Stage::Mid, lanes, c.clone(), &yt, &mut k3);
        points(&mut yt, y0, &h, &k3, c.clone());
        k.field(&co, Stage::End, lanes, c.clone(), &yt, &mut k4);
        for i in 0..N {
            for l in c.clone() {
                y1[i][l] = combine(y0[i][l], h6[l], f0[i][l], k2[i][l], k3[i][l], k4[i][l]);
            }
        }
        k.field(&co, Stage::End, lanes, c, y1, f1);
    }
}

/// The stage points `yt = y + c k` of the lanes in `chunk`.
#[inline(always)]
fn points<const N: usize, const L: usize>(
    yt: &mut Soa<N, L>,
    y: &Soa<N, L>,
    c: &[f64; L],
    k: &Soa<N, L>,
    chunk: core::ops::Range<usize>,
) {
    for i in 0..N {
        for l in chunk.clone() {
            yt[i][l] = stage_point(y[i][l], c[l], k[i][l]);
        }
    }
}

/// A [`Lockstep`] model's [`Lockstep::rhs`] as a one-chunk [`LaneKernel`].
struct Composed<'a, B: ?Sized>(&'a B);

impl<B: Lockstep<N, L> + ?Sized, const N: usize, const L: usize> LaneKernel<N, L>
    for Composed<'_, B>
{
    type Lanes = B::Lanes;
    type Coef = (At<L>, At<L>, usize);
    const CHUNK: usize = L;

    #[inline(always)]
    fn coef(&self, j: usize, _lanes: &B::Lanes, mid: &At<L>, end: &At<L>) -> Self::Coef {
        (*mid, *end, j)
    }

    #[inline(always)]
    fn field(
        &self,
        co: &Self::Coef,
        stage: Stage,
        lanes: &B::Lanes,
        _chunk: core::ops::Range<usize>,
        y: &Soa<N, L>,
        dy: &mut Soa<N, L>,
    ) {
        let at = if stage == Stage::Mid { &co.0 } else { &co.1 };
        self.0.rhs(co.2, stage, at, lanes, y, dy);
    }
}

/// The RK4 step of [`Lockstep::step`] composed from [`Lockstep::rhs`] and [`Lockstep::clear`]
/// exactly as the scalar RK4 step does (the trait's default, for models that take the composed
/// step in some cases and their own in others).
#[inline(always)]
pub fn compose_step<B: Lockstep<N, L> + ?Sized, const N: usize, const L: usize>(
    b: &B,
    s: &StepStart<'_, N, L>,
    lanes: &B::Lanes,
    y1: &mut Soa<N, L>,
    f1: &mut Soa<N, L>,
) -> u32 {
    rk4_lanes(&Composed(b), s, lanes, y1, f1);
    let StepStart {
        j, t0, t1, y0, f0, ..
    } = *s;
    let y = y0;
    // interior bound of the Hermite interpolant over the guard components, and finiteness
    let mut dev = [0.0f64; L];
    let mut finite = [true; L];
    for i in 0..N {
        for l in 0..L {
            let h = t1[l] - t0[l];
            let d = y1[i][l] - y[i][l];
            let r2 = h * f0[i][l] - d;
            let r3 = d - h * f1[i][l] - r2;
            if i < B::GUARD_DIMS {
                dev[l] = dev[l].max(r2.abs() + r3.abs());
            }
            finite[l] &= (y1[i][l].abs() < f64::INFINITY) & (f1[i][l].abs() < f64::INFINITY);
        }
    }
    let mut fin = 0u32;
    for l in 0..L {
        fin |= (finite[l] as u32) << l;
    }
    let clear = b.clear(j, lanes, y, y1, &dev);
    clear & fin
}
