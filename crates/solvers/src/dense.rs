//! One integration step and its dense output (continuous extension).

/// A step `(t0, y0) -> (t1, y1)` with its interpolant.
///
/// Both schemes share Hairer's nested form
/// `y(θ) = r1 + θ (r2 + (1-θ) (r3 + θ (r4 + (1-θ) r5)))`, `θ = (t - t0)/(t1 - t0)`:
/// Dormand–Prince fills all five rows (4th-order continuous extension), RK4 leaves `r5 = 0`, which is
/// exactly the cubic Hermite interpolant through `y0, f0, y1, f1`.
#[derive(Clone, Copy, Debug)]
pub struct Step<const N: usize> {
    /// Start time.
    pub t0: f64,
    /// End time.
    pub t1: f64,
    /// Interpolation coefficients `r1..r5` (`r1 = y0`).
    pub(crate) r: [[f64; N]; 5],
}

impl<const N: usize> Step<N> {
    pub(crate) fn empty() -> Self {
        Step {
            t0: 0.0,
            t1: 0.0,
            r: [[0.0; N]; 5],
        }
    }

    /// Sets up the cubic Hermite interpolant (`h = t1 - t0`).
    pub(crate) fn hermite(
        t0: f64,
        t1: f64,
        y0: &[f64; N],
        y1: &[f64; N],
        f0: &[f64; N],
        f1: &[f64; N],
    ) -> Self {
        let h = t1 - t0;
        let mut r = [[0.0; N]; 5];
        for i in 0..N {
            [r[0][i], r[1][i], r[2][i], r[3][i]] = hermite(y0[i], y1[i], f0[i], f1[i], h);
        }
        Step { t0, t1, r }
    }

    /// State at the start of the step.
    #[inline]
    pub fn y0(&self) -> [f64; N] {
        self.r[0]
    }

    /// State at the end of the step.
    #[inline]
    pub fn y1(&self) -> [f64; N] {
        let mut y = [0.0; N];
        for i in 0..N {
            y[i] = self.r[0][i] + self.r[1][i];
        }
        y
    }

    /// Interpolated state at time `t` (meant for `t0 <= t <= t1`).
    #[inline]
    pub fn interpolate(&self, t: f64) -> [f64; N] {
        let h = self.t1 - self.t0;
        let th = if h != 0.0 { (t - self.t0) / h } else { 1.0 };
        self.at_theta(th)
    }

    /// Interpolated state at the step fraction `theta` in `[0, 1]`.
    #[inline]
    pub fn at_theta(&self, th: f64) -> [f64; N] {
        let mut y = [0.0; N];
        for i in 0..N {
            let r = &self.r;
            y[i] = nested_at([r[0][i], r[1][i], r[2][i], r[3][i], r[4][i]], th);
        }
        y
    }
}

/// The coefficients `[r1, r2, r3, r4]` of the cubic Hermite interpolant of one component over a
/// step of length `h` from `y0` (derivative `f0`) to `y1` (derivative `f1`): `r1 = y0`,
/// `r2 = y1 - y0`, `r3 = h f0 - r2`, `r4 = r2 - h f1 - r3` (`r5 = 0`). Shared by [`Step`], the
/// lockstep lanes' samples of a step and their interior bound (`0.25 (|r3| + |r4|)`), so that all
/// of them round alike.
#[inline(always)]
pub fn hermite(y0: f64, y1: f64, f0: f64, f1: f64, h: f64) -> [f64; 4] {
    let d = y1 - y0;
    let r3 = h * f0 - d;
    [y0, d, r3, d - h * f1 - r3]
}

/// One component of Hairer's nested form at the step fraction `th` (see [`Step`]):
/// `r1 + th (r2 + (1-th) (r3 + th (r4 + (1-th) r5)))`.
#[inline(always)]
pub fn nested_at(r: [f64; 5], th: f64) -> f64 {
    let th1 = 1.0 - th;
    r[0] + th * (r[1] + th1 * (r[2] + th * (r[3] + th1 * r[4])))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hermite_reproduces_cubics_exactly() {
        // y = t^3 - 2t + 1 on [0.5, 1.7]
        let y = |t: f64| t * t * t - 2.0 * t + 1.0;
        let f = |t: f64| 3.0 * t * t - 2.0;
        let s = Step::<1>::hermite(0.5, 1.7, &[y(0.5)], &[y(1.7)], &[f(0.5)], &[f(1.7)]);
        for k in 0..=10 {
            let t = 0.5 + 1.2 * k as f64 / 10.0;
            assert!((s.interpolate(t)[0] - y(t)).abs() < 1e-13);
        }
        assert!((s.y1()[0] - y(1.7)).abs() < 1e-15);
    }
}
