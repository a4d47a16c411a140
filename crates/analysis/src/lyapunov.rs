//! Top Lyapunov exponent (TLE) of a non-smooth flow, per unit of the system's time (for the gear
//! model: per unit dimensionless time `tau`). docs/model.md §5.
//!
//! * [`tle_variational`]: the variational equation `dy' = J dy` integrated with the trajectory as
//!   an augmented hybrid system ([`Tangent`]), the perturbation mapped by the saltation matrix at
//!   every state event (vector-field jumps at contact changes, resets at impacts), Benettin
//!   renormalisation once per excitation period.
//! * [`tle_two_trajectory`]: a reference and a perturbed trajectory (initial distance `d0`),
//!   renormalised once per period: independent of any Jacobian, a check on the first.
//!
//! When they may disagree: the two-trajectory estimate is biased when the two trajectories sit on
//! different sides of an impact at a renormalisation instant (the distance then jumps by `O(R v)`,
//! not `O(d0)`), for grazing orbits (the saltation matrix is unbounded), and for sticking orbits
//! (the variational estimate correctly sees perturbations annihilated; the finite one only decays
//! them to round-off). Both converge like `1/sqrt(T)`; the reported spread is the standard error
//! of ten block means.

use crate::driver::{run_periods, Discard};
use geardyn_solvers::variational::{memory_saltation, saltation};
use geardyn_solvers::{
    EventAction, Guards, HybridSystem, Integrator, Scheme, SolverError, Stop, Variational,
};
use serde::Serialize;

/// A hybrid system augmented with one tangent vector: state `[y, dy, dp]` (`2N + 1`
/// components), `dp` the perturbation of the mode's memory parameter
/// ([`Variational::memory_slope`]; 0 for systems without memory).
#[derive(Clone, Debug)]
pub struct Tangent<S> {
    /// The underlying system.
    pub sys: S,
    /// Map the tangent by the saltation matrix at events (`false` only to show why it is needed).
    pub saltation: bool,
}

macro_rules! tangent_impl {
    ($n:literal, $m:literal) => {
        impl<S: Variational<$n>> HybridSystem<$m> for Tangent<S> {
            type Mode = S::Mode;
            type TimeTerms = S::TimeTerms;

            fn initial_mode(&self, t: f64, y: &mut [f64; $m]) -> S::Mode {
                let mut ys = head::<$n, $m>(y);
                let m = self.sys.initial_mode(t, &mut ys);
                y[..$n].copy_from_slice(&ys);
                m
            }
            #[inline(always)]
            fn time_terms(&self, t: f64) -> S::TimeTerms {
                self.sys.time_terms(t)
            }
            #[inline(always)]
            fn rhs(
                &self,
                t: f64,
                tt: &S::TimeTerms,
                y: &[f64; $m],
                mode: &S::Mode,
                dy: &mut [f64; $m],
            ) {
                let ys = head::<$n, $m>(y);
                let mut f = [0.0; $n];
                self.sys.rhs(t, tt, &ys, mode, &mut f);
                let mut j = [[0.0; $n]; $n];
                self.sys.jacobian(t, tt, &ys, mode, &mut j);
                let dp = y[2 * $n];
                // (a memory-free step adds nothing: its bits equal the plain tangent's)
                let fp = if dp != 0.0 {
                    self.sys.memory_slope(t, tt, &ys, mode)
                } else {
                    [0.0; $n]
                };
                for i in 0..$n {
                    dy[i] = f[i];
                    let mut s = 0.0;
                    for k in 0..$n {
                        s += j[i][k] * y[$n + k];
                    }
                    if dp != 0.0 {
                        s += fp[i] * dp;
                    }
                    dy[$n + i] = s;
                }
                dy[2 * $n] = 0.0;
            }
            #[inline(always)]
            fn guards(&self, t: f64, y: &[f64; $m], mode: &S::Mode, g: &mut Guards) {
                self.sys.guards(t, &head::<$n, $m>(y), mode, g)
            }
            fn on_event(
                &self,
                t: f64,
                y: &mut [f64; $m],
                mode: &mut S::Mode,
                index: usize,
            ) -> EventAction {
                let y_minus = head::<$n, $m>(y);
                let tt = self.sys.time_terms(t);
                let mut f_minus = [0.0; $n];
                self.sys.rhs(t, &tt, &y_minus, mode, &mut f_minus);
                let (g_y, g_t) = self.sys.guard_gradient(t, &y_minus, mode, index);
                let r_y = self.sys.reset_jacobian(t, &y_minus, mode, index);
                let before = *mode;
                let mut y_plus = y_minus;
                let action = self.sys.on_event(t, &mut y_plus, mode, index);
                let mut f_plus = [0.0; $n];
                self.sys.rhs(t, &tt, &y_plus, mode, &mut f_plus);
                let s = if self.saltation {
                    saltation(&r_y, &f_minus, &f_plus, &g_y, g_t)
                } else {
                    r_y
                };
                let (p_y, p_p) = self
                    .sys
                    .memory_reset(t, &y_minus, &before, mode, Some(index));
                let (s_y, s_p) = if self.saltation {
                    memory_saltation(&p_y, p_p, &f_minus, &g_y, g_t)
                } else {
                    (p_y, p_p)
                };
                let mut d = [0.0; $n];
                let mut dp = 0.0;
                for i in 0..$n {
                    for k in 0..$n {
                        d[i] += s[i][k] * y[$n + k];
                    }
                    dp += s_y[i] * y[$n + i];
                }
                dp += s_p * y[2 * $n];
                y[..$n].copy_from_slice(&y_plus);
                y[$n..2 * $n].copy_from_slice(&d);
                y[2 * $n] = dp;
                action
            }
            fn next_breakpoint(&self, t: f64, mode: &S::Mode) -> f64 {
                self.sys.next_breakpoint(t, mode)
            }
            fn on_breakpoint(&self, t: f64, y: &mut [f64; $m], mode: &mut S::Mode) {
                let mut ys = head::<$n, $m>(y);
                let before = *mode;
                self.sys.on_breakpoint(t, &mut ys, mode);
                // the switching time does not depend on the state: dp+ = P_y dy + P_p dp
                let (p_y, p_p) = self
                    .sys
                    .memory_reset(t, &head::<$n, $m>(y), &before, mode, None);
                let mut dp = p_p * y[2 * $n];
                for i in 0..$n {
                    dp += p_y[i] * y[$n + i];
                }
                y[..$n].copy_from_slice(&ys);
                y[2 * $n] = dp;
            }
            fn max_step(&self) -> f64 {
                self.sys.max_step()
            }
            // the guards read the trajectory part only: the bound over all components is safe
            fn guard_lipschitz(&self, mode: &S::Mode) -> Option<f64> {
                self.sys.guard_lipschitz(mode)
            }
            // an accumulation of impacts ends in the system's sticking mode; the tangent was
            // already mapped by the reset of every impact of the sequence and is kept
            fn zeno_fallback(
                &self,
                t: f64,
                y: &mut [f64; $m],
                mode: &mut S::Mode,
                index: usize,
            ) -> bool {
                let mut ys = head::<$n, $m>(y);
                let ended = self.sys.zeno_fallback(t, &mut ys, mode, index);
                y[..$n].copy_from_slice(&ys);
                ended
            }
            fn memory(&self, mode: &S::Mode) -> f64 {
                self.sys.memory(mode)
            }
            fn with_memory(&self, mode: &S::Mode, p: f64) -> S::Mode {
                self.sys.with_memory(mode, p)
            }
            fn same_regime(&self, a: &S::Mode, b: &S::Mode) -> bool {
                self.sys.same_regime(a, b)
            }
        }
    };
}

#[inline(always)]
fn head<const N: usize, const M: usize>(y: &[f64; M]) -> [f64; N] {
    let mut h = [0.0; N];
    h.copy_from_slice(&y[..N]);
    h
}

tangent_impl!(1, 3);
tangent_impl!(2, 5);
tangent_impl!(3, 7);
tangent_impl!(4, 9);
tangent_impl!(5, 11);
tangent_impl!(6, 13);
tangent_impl!(7, 15);
tangent_impl!(8, 17);
tangent_impl!(9, 19);
tangent_impl!(10, 21);
tangent_impl!(11, 23);
tangent_impl!(12, 25);
tangent_impl!(13, 27);
tangent_impl!(14, 29);
tangent_impl!(15, 31);
tangent_impl!(16, 33);
tangent_impl!(17, 35);
tangent_impl!(18, 37);
tangent_impl!(19, 39);
tangent_impl!(20, 41);
tangent_impl!(21, 43);
tangent_impl!(22, 45);
tangent_impl!(23, 47);
tangent_impl!(24, 49);

/// A system whose tangent dynamics [`Tangent`] can be integrated: any [`Variational`] system of
/// dimension 1 to 24 (the augmented state has `2N + 1` components, a size the stable compiler
/// cannot compute from a generic `N`, so each dimension is implemented once here). Analyses
/// generic over the dimension call the variational exponent through it.
#[diagnostic::on_unimplemented(
    message = "`{Self}` has no tangent space of dimension {N}: geardyn integrates the tangent dynamics of systems of 1 to 24 states",
    note = "the system must implement `Variational<{N}> + Clone`, and its state dimension must lie in 1..=24"
)]
pub trait TangentSpace<const N: usize>: Variational<N> + Clone {
    /// [`tle_variational_with`] of this system.
    fn tle_variational_with(
        &self,
        scheme: Scheme,
        t0: f64,
        y0: [f64; N],
        memory: f64,
        opts: &LyapunovOptions,
        use_saltation: bool,
    ) -> Result<LyapunovResult, SolverError>;

    /// One column of the monodromy: `periods` intervals of length `period` of the flow from
    /// `(t0, y0)` in a mode of memory `memory` ([`HybridSystem::memory`]; 0 for a fresh start)
    /// integrated with the tangent `d` ([`Tangent`] with saltation; the memory's own
    /// perturbation starts at 0). Returns the state, the tangent and the mode's memory at the
    /// end. `on_change(before, after)` sees every step after which the mode changed (a contact
    /// event, a time breakpoint), in order. The periodic orbits ([`crate::orbits`]) build the
    /// Jacobian of the stroboscopic map from `N` such runs.
    #[allow(clippy::too_many_arguments)]
    fn tangent_flow(
        &self,
        scheme: Scheme,
        t0: f64,
        y0: [f64; N],
        memory: f64,
        d: [f64; N],
        period: f64,
        periods: u64,
        on_change: &mut dyn FnMut(&Self::Mode, &Self::Mode),
    ) -> Result<TangentFlow<N>, SolverError>;
}

/// The end of a [`TangentSpace::tangent_flow`] run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TangentFlow<const N: usize> {
    /// State.
    pub y: [f64; N],
    /// Tangent.
    pub d: [f64; N],
    /// Memory parameter of the mode ([`HybridSystem::memory`]).
    pub memory: f64,
}

/// Hands every change of mode of a run to a callback.
struct ModeChanges<'f, M>(&'f mut dyn FnMut(&M, &M));

impl<S: HybridSystem<N>, const N: usize> crate::driver::Observer<S, N>
    for ModeChanges<'_, S::Mode>
{
    #[inline(always)]
    fn on_step(
        &mut self,
        _sys: &S,
        _step: &geardyn_solvers::Step<N>,
        before: &S::Mode,
        _stop: Stop,
        after: &S::Mode,
        _y_after: &[f64; N],
    ) {
        if before != after {
            (self.0)(before, after);
        }
    }
}

macro_rules! tangent_space_impl {
    ($n:literal, $m:literal) => {
        impl<S: Variational<$n> + Clone> TangentSpace<$n> for S {
            fn tle_variational_with(
                &self,
                scheme: Scheme,
                t0: f64,
                y0: [f64; $n],
                memory: f64,
                opts: &LyapunovOptions,
                use_saltation: bool,
            ) -> Result<LyapunovResult, SolverError> {
                tle_variational_with::<S, $n, $m>(
                    self.clone(),
                    scheme,
                    t0,
                    y0,
                    memory,
                    opts,
                    use_saltation,
                )
            }

            fn tangent_flow(
                &self,
                scheme: Scheme,
                t0: f64,
                y0: [f64; $n],
                memory: f64,
                d: [f64; $n],
                period: f64,
                periods: u64,
                on_change: &mut dyn FnMut(&S::Mode, &S::Mode),
            ) -> Result<TangentFlow<$n>, SolverError> {
                let mut z = [0.0; $m];
                z[..$n].copy_from_slice(&y0);
                z[$n..2 * $n].copy_from_slice(&d);
                let tan = Tangent {
                    sys: self,
                    saltation: true,
                };
                let mut it = Integrator::new(tan, scheme, t0, z)?.with_memory(memory);
                run_periods(&mut it, period, periods, &mut ModeChanges(on_change))?;
                let z = *it.y();
                let mut d = [0.0; $n];
                d.copy_from_slice(&z[$n..2 * $n]);
                Ok(TangentFlow {
                    y: head::<$n, $m>(&z),
                    d,
                    memory: self.memory(it.mode()),
                })
            }
        }
    };
}

tangent_space_impl!(1, 3);
tangent_space_impl!(2, 5);
tangent_space_impl!(3, 7);
tangent_space_impl!(4, 9);
tangent_space_impl!(5, 11);
tangent_space_impl!(6, 13);
tangent_space_impl!(7, 15);
tangent_space_impl!(8, 17);
tangent_space_impl!(9, 19);
tangent_space_impl!(10, 21);
tangent_space_impl!(11, 23);
tangent_space_impl!(12, 25);
tangent_space_impl!(13, 27);
tangent_space_impl!(14, 29);
tangent_space_impl!(15, 31);
tangent_space_impl!(16, 33);
tangent_space_impl!(17, 35);
tangent_space_impl!(18, 37);
tangent_space_impl!(19, 39);
tangent_space_impl!(20, 41);
tangent_space_impl!(21, 43);
tangent_space_impl!(22, 45);
tangent_space_impl!(23, 47);
tangent_space_impl!(24, 49);

/// Settings of a TLE computation.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct LyapunovOptions {
    /// Renormalisation interval (the excitation period for forced systems).
    pub period: f64,
    /// Intervals discarded before measuring.
    pub transient_periods: u64,
    /// Intervals measured.
    pub periods: u64,
    /// Initial distance of the two-trajectory method.
    pub d0: f64,
}

/// A TLE estimate.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LyapunovResult {
    /// Top Lyapunov exponent per unit time.
    pub tle: f64,
    /// Standard error from ten block means.
    pub spread: f64,
    /// Running estimate after each renormalisation.
    pub history: Vec<f64>,
    /// Measured time span.
    pub time: f64,
    /// Intervals in which the perturbation was annihilated (sticking to a stop: the flow
    /// contracts a direction to zero and trajectories synchronise); each counts `ln(1e-300)`.
    pub annihilated: u64,
}

/// Most entries reserved ahead for the history: the period count comes from the user (a count of
/// 10^12 must not reserve terabytes before the first step); the history grows as it is computed.
const RESERVE: u64 = 4096;

/// Number of blocks of the standard error.
const BLOCKS: u64 = 10;

/// Running TLE estimate over an announced number of intervals: the running history and the sums
/// of ten blocks of equal length (the remainder `n mod 10` in no block), without keeping the
/// per-interval logarithms.
pub(crate) struct Accumulator {
    period: f64,
    blocks: u64,
    per: u64,
    n: u64,
    sum: f64,
    block_sums: [f64; BLOCKS as usize],
    history: Vec<f64>,
}

impl Accumulator {
    pub(crate) fn new(period: f64, intervals: u64) -> Self {
        let blocks = BLOCKS.min(intervals.max(1));
        Accumulator {
            period,
            blocks,
            per: intervals / blocks,
            n: 0,
            sum: 0.0,
            block_sums: [0.0; BLOCKS as usize],
            history: Vec::with_capacity(intervals.min(RESERVE) as usize),
        }
    }

    /// The log growth of one interval.
    pub(crate) fn push(&mut self, l: f64) {
        if let Some(b) = self.n.checked_div(self.per) {
            if b < self.blocks {
                self.block_sums[b as usize] += l;
            }
        }
        self.n += 1;
        self.sum += l;
        self.history.push(self.sum / (self.n as f64 * self.period));
    }

    pub(crate) fn finish(self, annihilated: u64) -> LyapunovResult {
        let (n, period, blocks, per) = (self.n, self.period, self.blocks, self.per);
        let tle = if n > 0 {
            self.sum / (n as f64 * period)
        } else {
            f64::NAN
        };
        let spread = if per == 0 || blocks < 2 {
            f64::NAN
        } else {
            let means = &self.block_sums[..blocks as usize];
            let scale = per as f64 * period;
            let m = means.iter().map(|s| s / scale).sum::<f64>() / blocks as f64;
            let var = means
                .iter()
                .map(|s| (s / scale - m) * (s / scale - m))
                .sum::<f64>()
                / (blocks - 1) as f64;
            (var / blocks as f64).sqrt()
        };
        LyapunovResult {
            tle,
            spread,
            history: self.history,
            time: n as f64 * period,
            annihilated,
        }
    }
}

/// Smallest tangent norm treated as non-zero: below it the perturbation was annihilated (an orbit
/// sticking to a stop); it is restarted and the interval counts `ln(TINY)`.
pub(crate) const TINY: f64 = 1e-300;

/// TLE by the variational equation with saltation matrices.
///
/// ```
/// use geardyn_analysis::lyapunov::{tle_variational, LyapunovOptions};
/// use geardyn_model::reference::Duffing;
/// use geardyn_solvers::Scheme;
/// // a damped linear oscillator: TLE = -delta/2
/// let sys = Duffing { delta: 0.2, alpha: 1.0, beta: 0.0, gamma: 0.0, omega: 1.0 };
/// let opts = LyapunovOptions { period: 1.0, transient_periods: 0, periods: 400, d0: 1e-8 };
/// let r = tle_variational::<_, 2, 5>(sys, Scheme::dopri_default(), 0.0, [1.0, 0.0], &opts).unwrap();
/// assert!((r.tle + 0.1).abs() < 5e-3);
/// ```
pub fn tle_variational<S, const N: usize, const M: usize>(
    sys: S,
    scheme: Scheme,
    t0: f64,
    y0: [f64; N],
    opts: &LyapunovOptions,
) -> Result<LyapunovResult, SolverError>
where
    S: Variational<N> + Clone,
    Tangent<S>: HybridSystem<M>,
{
    tle_variational_with(sys, scheme, t0, y0, 0.0, opts, true)
}

/// As [`tle_variational`], continuing a run whose mode at `(t0, y0)` holds the memory `memory`
/// ([`HybridSystem::memory`]: the hysteresis factor of an impact in progress; 0 for a fresh
/// start), and optionally without the saltation correction (to show its effect).
pub fn tle_variational_with<S, const N: usize, const M: usize>(
    sys: S,
    scheme: Scheme,
    t0: f64,
    y0: [f64; N],
    memory: f64,
    opts: &LyapunovOptions,
    use_saltation: bool,
) -> Result<LyapunovResult, SolverError>
where
    S: Variational<N> + Clone,
    Tangent<S>: HybridSystem<M>,
{
    assert_eq!(
        M,
        2 * N + 1,
        "Tangent<S> of an N-dimensional system has dimension 2N + 1"
    );
    let mut base = Integrator::new(sys.clone(), scheme, t0, y0)?.with_memory(memory);
    run_periods(&mut base, opts.period, opts.transient_periods, &mut Discard)?;
    let memory = sys.memory(base.mode());
    let mut z = [0.0; M];
    z[..N].copy_from_slice(base.y());
    let unit = 1.0 / (N as f64).sqrt();
    for v in z[N..2 * N].iter_mut() {
        *v = unit;
    }
    let tan = Tangent {
        sys,
        saltation: use_saltation,
    };
    let t_start = base.t();
    // the tangent run continues the base run (an impact in progress keeps its hysteresis)
    let mut it = Integrator::new(tan, scheme, t_start, z)?.with_memory(memory);
    let mut acc = Accumulator::new(opts.period, opts.periods);
    let mut annihilated = 0;
    for j in 1..=opts.periods {
        let t_stop = t_start + j as f64 * opts.period;
        loop {
            match it.step(t_stop)? {
                Stop::Tstop | Stop::Terminated { .. } => break,
                _ => {}
            }
        }
        let mut z = *it.y();
        let norm = z[N..].iter().map(|v| v * v).sum::<f64>().sqrt();
        if norm > TINY && norm.is_finite() {
            acc.push(norm.ln());
            for v in z[N..].iter_mut() {
                *v /= norm;
            }
        } else {
            annihilated += 1;
            acc.push(TINY.ln());
            for v in z[N..2 * N].iter_mut() {
                *v = unit;
            }
            z[2 * N] = 0.0;
        }
        it.set_state(z);
    }
    Ok(acc.finish(annihilated))
}

/// TLE from a reference and a perturbed trajectory, renormalised to `d0` every period.
/// `d0` must be well above the integration error (`rtol*|y|`, `atol`), or the integrator's noise
/// is measured instead of the flow's growth.
pub fn tle_two_trajectory<S, const N: usize>(
    sys: S,
    scheme: Scheme,
    t0: f64,
    y0: [f64; N],
    opts: &LyapunovOptions,
) -> Result<LyapunovResult, SolverError>
where
    S: HybridSystem<N> + Clone,
{
    let mut a = Integrator::new(sys.clone(), scheme, t0, y0)?;
    run_periods(&mut a, opts.period, opts.transient_periods, &mut Discard)?;
    let t_start = a.t();
    let unit = 1.0 / (N as f64).sqrt();
    let mut yb = *a.y();
    for v in yb.iter_mut() {
        *v += opts.d0 * unit;
    }
    // the perturbed run starts inside the reference run's impact, if any, with its hysteresis
    let ma = *a.mode();
    let mut b = Integrator::new(sys, scheme, t_start, yb)?;
    let mb = *b.mode();
    if b.system().same_regime(&ma, &mb) {
        let m = b.system().with_memory(&mb, b.system().memory(&ma));
        b.set_mode(m);
    }
    let mut acc = Accumulator::new(opts.period, opts.periods);
    for j in 1..=opts.periods {
        let t_stop = t_start + j as f64 * opts.period;
        for it in [&mut a, &mut b] {
            loop {
                match it.step(t_stop)? {
                    Stop::Tstop | Stop::Terminated { .. } => break,
                    _ => {}
                }
            }
        }
        let (ya, yb) = (*a.y(), *b.y());
        // the memory of the mode belongs to the state where both runs are in the same mode
        let sys = a.system();
        let (ma, mb) = (*a.mode(), *b.mode());
        let (pa, pb) = (sys.memory(&ma), sys.memory(&mb));
        let dp = if sys.same_regime(&ma, &mb) {
            pb - pa
        } else {
            0.0
        };
        let d = (ya
            .iter()
            .zip(&yb)
            .map(|(p, q)| (p - q) * (p - q))
            .sum::<f64>()
            + dp * dp)
            .sqrt();
        let mut y_new = ya;
        let mut p_new = pa;
        if d > 0.0 && d.is_finite() {
            acc.push((d / opts.d0).ln());
            for i in 0..N {
                y_new[i] += opts.d0 * (yb[i] - ya[i]) / d;
            }
            p_new += opts.d0 * dp / d;
        } else {
            acc.push((f64::EPSILON / opts.d0).ln());
            for v in y_new.iter_mut() {
                *v += opts.d0 * unit;
            }
        }
        b.reset(a.t(), y_new)?;
        // a restart in the reference run's mode takes its memory (an impact in progress keeps
        // its hysteresis), moved by the perturbation
        let mb = *b.mode();
        if sys.same_regime(&ma, &mb) {
            b.set_mode(sys.with_memory(&mb, p_new));
        }
    }
    Ok(acc.finish(0))
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use geardyn_solvers::SolverError;

    /// Uniform motion that blows up half a time unit into the run (also for the tests of
    /// [`crate::generic`]).
    #[derive(Clone)]
    pub(crate) struct Doomed;

    geardyn_solvers::one_mode_system!(Doomed, 1, |_, t, _y, dy| {
        dy[0] = if t < 0.5 { 1.0 } else { f64::NAN };
    });

    impl Variational<1> for Doomed {
        fn jacobian(&self, _t: f64, _tt: &(), _y: &[f64; 1], _m: &(), jac: &mut [[f64; 1]; 1]) {
            jac[0][0] = 0.0;
        }
        fn guard_gradient(&self, _t: f64, _y: &[f64; 1], _m: &(), _i: usize) -> ([f64; 1], f64) {
            ([0.0], 0.0)
        }
    }

    #[test]
    fn a_huge_period_count_reserves_nothing_up_front() {
        // 10^12 periods: 8 TB of logs if reserved ahead; the run fails in the first period
        let opts = LyapunovOptions {
            period: 1.0,
            transient_periods: 0,
            periods: 1_000_000_000_000,
            d0: 1e-8,
        };
        let scheme = Scheme::Rk4 { h: 0.01 };
        let r = tle_two_trajectory(Doomed, scheme, 0.0, [0.0], &opts);
        assert!(matches!(r, Err(SolverError::NonFinite { .. })), "{r:?}");
        let r = tle_variational::<_, 1, 3>(Doomed, scheme, 0.0, [0.0], &opts);
        assert!(matches!(r, Err(SolverError::NonFinite { .. })), "{r:?}");
    }

    /// The statistics as they were computed from the stored logs.
    fn reference(logs: &[f64], period: f64) -> (f64, f64, Vec<f64>) {
        let n = logs.len();
        let mut history = vec![];
        let mut sum = 0.0;
        for (j, l) in logs.iter().enumerate() {
            sum += l;
            history.push(sum / ((j + 1) as f64 * period));
        }
        let tle = if n > 0 {
            sum / (n as f64 * period)
        } else {
            f64::NAN
        };
        let blocks = 10.min(n.max(1));
        let per = n / blocks;
        let spread = if per == 0 || blocks < 2 {
            f64::NAN
        } else {
            let means: Vec<f64> = (0..blocks)
                .map(|b| logs[b * per..(b + 1) * per].iter().sum::<f64>() / (per as f64 * period))
                .collect();
            let m = means.iter().sum::<f64>() / blocks as f64;
            let var = means.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (blocks - 1) as f64;
            (var / blocks as f64).sqrt()
        };
        (tle, spread, history)
    }

    #[test]
    fn streamed_statistics_equal_the_stored_ones() {
        for n in [0usize, 1, 5, 10, 11, 19, 20, 137, 5000] {
            let logs: Vec<f64> = (0..n)
                .map(|j| ((j as f64) * 0.7).sin() - 0.1 + 1e-3 * j as f64)
                .collect();
            let mut acc = Accumulator::new(2.5, n as u64);
            for &l in &logs {
                acc.push(l);
            }
            let r = acc.finish(3);
            let (tle, spread, history) = reference(&logs, 2.5);
            assert!(r.tle.to_bits() == tle.to_bits(), "n={n}");
            assert!(r.spread.to_bits() == spread.to_bits(), "n={n}");
            assert_eq!(r.history, history, "n={n}");
            assert_eq!((r.time, r.annihilated), (n as f64 * 2.5, 3));
        }
    }
}
