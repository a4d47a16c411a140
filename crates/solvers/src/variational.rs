//! Linearisation of a hybrid system, needed for Lyapunov exponents of non-smooth flows.
//!
//! Between events a perturbation `dy` obeys `dy' = J(t, y) dy`. At a state event with guard `g`
//! and reset `R`, it is mapped by the saltation matrix (Müller 1995; Leine & Nijmeijer 2004)
//!
//! `S = R_y + (f+ - R_y f- - R_t) g_y^T / (g_y f- + g_t)`
//!
//! where `f-` is the field before the event at `y-`, `f+` the field after it at `R(y-)`. At a time
//! breakpoint the switching time does not depend on the state (`g_y = 0`) and `S = R_y`.

use crate::hybrid::HybridSystem;

/// Capability of a [`HybridSystem`] to be linearised.
pub trait Variational<const N: usize>: HybridSystem<N> {
    /// Jacobian `J[i][j] = d f_i / d y_j` of the field of `mode`.
    fn jacobian(
        &self,
        t: f64,
        tt: &Self::TimeTerms,
        y: &[f64; N],
        mode: &Self::Mode,
        jac: &mut [[f64; N]; N],
    );

    /// Gradient `g_y` and time derivative `g_t` of guard `index` (as armed in `mode`).
    fn guard_gradient(
        &self,
        t: f64,
        y: &[f64; N],
        mode: &Self::Mode,
        index: usize,
    ) -> ([f64; N], f64);

    /// Jacobian `R_y` of the reset applied by [`HybridSystem::on_event`] for guard `index`
    /// (before the event, at `y`). Default: identity (no state jump).
    fn reset_jacobian(
        &self,
        _t: f64,
        _y: &[f64; N],
        _mode: &Self::Mode,
        _index: usize,
    ) -> [[f64; N]; N] {
        identity()
    }
}

/// The `N x N` identity.
pub fn identity<const N: usize>() -> [[f64; N]; N] {
    let mut m = [[0.0; N]; N];
    for (i, row) in m.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    m
}

/// Saltation matrix `S` from the quantities at the event (see module doc; `R_t = 0`).
///
/// ```
/// // impact oscillator x'' = a at x = 0, v+ = -r v-: the classical S = [[-r, 0], [(a+ + r a-)/v-, -r]]
/// use geardyn_solvers::variational::saltation;
/// let (r, v, a) = (0.8, -2.0, -1.0);
/// let s = saltation(&[[1.0, 0.0], [0.0, -r]], &[v, a], &[-r * v, a], &[1.0, 0.0], 0.0);
/// assert!((s[0][0] + r).abs() < 1e-15 && (s[1][0] - (a + r * a) / v).abs() < 1e-15 && (s[1][1] + r).abs() < 1e-15);
/// ```
pub fn saltation<const N: usize>(
    r_y: &[[f64; N]; N],
    f_minus: &[f64; N],
    f_plus: &[f64; N],
    g_y: &[f64; N],
    g_t: f64,
) -> [[f64; N]; N] {
    let mut denom = g_t;
    for i in 0..N {
        denom += g_y[i] * f_minus[i];
    }
    let mut s = *r_y;
    if denom == 0.0 || !denom.is_finite() {
        // tangential (grazing) crossing: the saltation matrix is unbounded; keep R_y
        return s;
    }
    for i in 0..N {
        let mut rf = 0.0;
        for j in 0..N {
            rf += r_y[i][j] * f_minus[j];
        }
        let w = (f_plus[i] - rf) / denom;
        for j in 0..N {
            s[i][j] += w * g_y[j];
        }
    }
    s
}

/// A shared reference to a linearisable system is linearisable.
impl<S: Variational<N>, const N: usize> Variational<N> for &S {
    fn jacobian(
        &self,
        t: f64,
        tt: &Self::TimeTerms,
        y: &[f64; N],
        mode: &Self::Mode,
        jac: &mut [[f64; N]; N],
    ) {
        (**self).jacobian(t, tt, y, mode, jac)
    }
    fn guard_gradient(
        &self,
        t: f64,
        y: &[f64; N],
        mode: &Self::Mode,
        index: usize,
    ) -> ([f64; N], f64) {
        (**self).guard_gradient(t, y, mode, index)
    }
    fn reset_jacobian(
        &self,
        t: f64,
        y: &[f64; N],
        mode: &Self::Mode,
        index: usize,
    ) -> [[f64; N]; N] {
        (**self).reset_jacobian(t, y, mode, index)
    }
}
