//! Linearisation of a hybrid system, needed for Lyapunov exponents of non-smooth flows.
//!
//! Between events a perturbation `dy` obeys `dy' = J(t, y) dy`. At a state event with guard `g`
//! and reset `R`, it is mapped by the saltation matrix (Müller 1995; Leine & Nijmeijer 2004)
//!
//! `S = R_y + (f+ - R_y f- - R_t) g_y^T / (g_y f- + g_t)`
//!
//! where `f-` is the field before the event at `y-`, `f+` the field after it at `R(y-)`. At a time
//! breakpoint the switching time does not depend on the state (`g_y = 0`) and `S = R_y`.
//!
//! # Memory of the mode
//!
//! A mode may hold a parameter `p` that the field depends on, constant between events and set at
//! events from the state (a dissipative contact law's hysteresis factor, set from the entry speed
//! of each impact). A perturbation of the state at the event perturbs `p`, and `p` then acts on
//! the state until the next event that sets it: the tangent carries `dp` beside `dy`
//! (`dy' = J dy + f_p dp`, `dp' = 0`), and at an event with `p+ = P(y-, p-)`
//!
//! `dp+ = P_y dy- - (P_y f-) (g_y dy-) / (g_y f- + g_t) + P_p dp-`
//!
//! (the saltation matrix of the system augmented with `p' = 0`: the entry speed of the perturbed
//! trajectory is read at its own, shifted, event time). Systems without memory keep the defaults.

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

    /// Sensitivity `f_p = d f / d p` of the field to the mode's memory parameter (module doc).
    /// Default: no memory.
    fn memory_slope(
        &self,
        _t: f64,
        _tt: &Self::TimeTerms,
        _y: &[f64; N],
        _mode: &Self::Mode,
    ) -> [f64; N] {
        [0.0; N]
    }

    /// How the memory parameter after an event or breakpoint depends on the state and the memory
    /// before it: `(P_y, P_p)` of `p+ = P(y-, p-)`, with `y` the state before it, `before` and
    /// `after` the modes around it, `index` the guard (`None` at a time breakpoint). Default:
    /// the memory is kept, `([0; N], 1)`.
    fn memory_reset(
        &self,
        _t: f64,
        _y: &[f64; N],
        _before: &Self::Mode,
        _after: &Self::Mode,
        _index: Option<usize>,
    ) -> ([f64; N], f64) {
        ([0.0; N], 1.0)
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

/// Row of the augmented saltation matrix for the memory parameter (module doc): the coefficients
/// `(s_y, s_p)` of `dp+ = s_y . dy- + s_p dp-`, from `(P_y, P_p)` of the reset, the field `f-`
/// before the event and the guard's gradient `g_y` and time derivative `g_t`. At a time
/// breakpoint (`g_y = 0`) or a grazing crossing it is `(P_y, P_p)`.
///
/// ```
/// // p+ = phi(v-) set at the crossing of x = 0 by x' = v, v' = a: the perturbed crossing comes
/// // dt = -dx/v later, at the speed v + a dt, so dp+ = phi'(v) (dv - a dx / v)
/// use geardyn_solvers::variational::memory_saltation;
/// let (v, a, slope) = (2.0, -3.0, 0.5);
/// let (s_y, s_p) = memory_saltation(&[0.0, slope], 0.0, &[v, a], &[1.0, 0.0], 0.0);
/// assert!((s_y[0] + slope * a / v).abs() < 1e-15 && s_y[1] == slope && s_p == 0.0);
/// ```
pub fn memory_saltation<const N: usize>(
    p_y: &[f64; N],
    p_p: f64,
    f_minus: &[f64; N],
    g_y: &[f64; N],
    g_t: f64,
) -> ([f64; N], f64) {
    let mut denom = g_t;
    let mut pf = 0.0;
    for i in 0..N {
        denom += g_y[i] * f_minus[i];
        pf += p_y[i] * f_minus[i];
    }
    let mut s = *p_y;
    if denom == 0.0 || !denom.is_finite() || pf == 0.0 {
        return (s, p_p);
    }
    let w = pf / denom;
    for i in 0..N {
        s[i] -= w * g_y[i];
    }
    (s, p_p)
}

/// A shared reference to a linearisable system is linearisable.
impl<S: Variational<N>, const N: usize> Variational<N> for &S {
    crate::forward_methods! { to referent;
        fn jacobian(&self, t: f64, tt: &S::TimeTerms, y: &[f64; N], mode: &S::Mode, jac: &mut [[f64; N]; N]);
        fn guard_gradient(&self, t: f64, y: &[f64; N], mode: &S::Mode, index: usize) -> ([f64; N], f64);
        fn reset_jacobian(&self, t: f64, y: &[f64; N], mode: &S::Mode, index: usize) -> [[f64; N]; N];
        fn memory_slope(&self, t: f64, tt: &S::TimeTerms, y: &[f64; N], mode: &S::Mode) -> [f64; N];
        fn memory_reset(
            &self, t: f64, y: &[f64; N], before: &S::Mode, after: &S::Mode, index: Option<usize>,
        ) -> ([f64; N], f64);
    }
}
