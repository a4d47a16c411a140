//! Bracketed scalar root finding (Illinois variant of regula falsi).
//!
//! Hand-written rather than taken from a crate because it runs inside the integrator's event
//! location on a step interpolant: it must not allocate and must keep the *bracket*, so that the
//! caller can pick the end on the far side of the switching surface.

/// Result of [`illinois`]: a bracket `[a, b]` with `f(a)` on the old side and `f(b)` on the new side.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bracket {
    /// End on the old side of the root.
    pub a: f64,
    /// Function value at `a`.
    pub fa: f64,
    /// End on the new side of the root.
    pub b: f64,
    /// Function value at `b`.
    pub fb: f64,
}

/// Shrinks a sign-change bracket of `f` until it is narrower than `xtol`.
///
/// `new_side(f)` says whether a value lies on the new side of the root; `f(a)` must not and `f(b)`
/// must. Works for `a > b` too. At most 200 evaluations.
///
/// ```
/// use geardyn_solvers::root::illinois;
/// let br = illinois(|x: f64| x * x - 2.0, 0.0, -2.0, 2.0, 2.0, 1e-14, |f| f > 0.0);
/// assert!((br.b - 2f64.sqrt()).abs() < 1e-13);
/// ```
pub fn illinois<F, S>(
    mut f: F,
    mut a: f64,
    mut fa: f64,
    mut b: f64,
    mut fb: f64,
    xtol: f64,
    new_side: S,
) -> Bracket
where
    F: FnMut(f64) -> f64,
    S: Fn(f64) -> bool,
{
    // side: which end was retained last (for the Illinois halving)
    let mut side = 0i8;
    for _ in 0..200 {
        if (b - a).abs() <= xtol {
            break;
        }
        let denom = fb - fa;
        let mut x = if denom != 0.0 && denom.is_finite() {
            b - fb * (b - a) / denom
        } else {
            0.5 * (a + b)
        };
        // keep strictly inside; fall back to bisection when regula falsi stalls at an end
        let lo = a.min(b);
        let hi = a.max(b);
        if !(x > lo && x < hi) {
            x = 0.5 * (a + b);
        }
        let fx = f(x);
        if new_side(fx) {
            b = x;
            fb = fx;
            if side == 1 {
                fa *= 0.5;
            }
            side = 1;
        } else {
            a = x;
            fa = fx;
            if side == -1 {
                fb *= 0.5;
            }
            side = -1;
        }
    }
    Bracket { a, fa, b, fb }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_cubic_root_from_either_orientation() {
        let f = |x: f64| (x - 0.3) * (x * x + 1.0);
        let br = illinois(f, 0.0, f(0.0), 1.0, f(1.0), 1e-15, |v| v > 0.0);
        assert!((br.b - 0.3).abs() < 1e-14);
        assert!(br.fb > 0.0 && br.fa <= 0.0);
        // reversed orientation: old side at the right end
        let g = |x: f64| -(x - 0.3);
        let br = illinois(g, 1.0, g(1.0), 0.0, g(0.0), 1e-15, |v| v > 0.0);
        assert!((br.b - 0.3).abs() < 1e-14 && br.b <= 0.3);
    }

    #[test]
    fn steep_root_converges() {
        let f = |x: f64| (x - 0.7).powi(7) + 1e-3 * (x - 0.7);
        let br = illinois(f, 0.0, f(0.0), 1.0, f(1.0), 1e-14, |v| v > 0.0);
        assert!((br.b - 0.7).abs() < 1e-10, "{}", br.b);
    }
}
