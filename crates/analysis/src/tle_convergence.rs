//! A top Lyapunov exponent that stops when it has converged (docs/analyses.md).
//!
//! The finite-time estimate over `N` excitation periods carries a bias of order `1/N` (the
//! tangent vector's alignment, the oscillation of a complex Floquet pair) and, for chaos, a
//! statistical error of order `1/sqrt(N)`. Both show as the difference between the running
//! estimate at `N` and at `N/2` of the same run, so the run length doubles until that difference
//! and the block standard error are below the tolerance, or the cap is reached (then the result
//! says it has not converged).

use crate::lyapunov::{tle_variational, LyapunovOptions, LyapunovResult};
use geardyn_solvers::{Scheme, SolverError, Variational};
use serde::Serialize;

/// Convergence settings.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Convergence {
    /// First run length (excitation periods).
    pub start_periods: u64,
    /// Largest run length.
    pub max_periods: u64,
    /// Absolute tolerance (per unit dimensionless time).
    pub abs_tol: f64,
    /// Relative tolerance.
    pub rel_tol: f64,
}

impl Default for Convergence {
    fn default() -> Self {
        Convergence {
            start_periods: 200,
            max_periods: 25_600,
            abs_tol: 2.5e-4,
            rel_tol: 0.02,
        }
    }
}

/// One round of the doubling.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Round {
    /// Periods of the run.
    pub periods: u64,
    /// TLE at the end of the run.
    pub tle: f64,
    /// TLE at half the run.
    pub half: f64,
    /// Block standard error.
    pub stderr: f64,
}

/// A converged (or capped) TLE.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ConvergedTle {
    /// The last run.
    pub result: LyapunovResult,
    /// Every round.
    pub rounds: Vec<Round>,
    /// Whether the criterion was met before the cap.
    pub converged: bool,
    /// The tolerance of the last round.
    pub tol: f64,
}

/// Variational TLE (with saltation) doubling the run length until converged; every round is
/// handed to `on_round` as soon as it is done (a long run shows its progress).
pub fn tle_converged<S>(
    sys: S,
    scheme: Scheme,
    t0: f64,
    y0: [f64; 2],
    opts: &LyapunovOptions,
    conv: &Convergence,
    on_round: impl FnMut(&Round),
) -> Result<ConvergedTle, SolverError>
where
    S: Variational<2> + Clone,
    crate::lyapunov::Tangent<S>: geardyn_solvers::HybridSystem<5>,
{
    converge_by_doubling(
        conv,
        |n| {
            let o = LyapunovOptions {
                periods: n,
                ..*opts
            };
            tle_variational::<_, 2, 5>(sys.clone(), scheme, t0, y0, &o)
        },
        on_round,
    )
}

/// The doubling of any exponent computation: `run(n)` computes the exponent over `n` excitation
/// periods from one fixed start (its `history`, the running estimate, gives the value at half
/// the run); the length doubles from [`Convergence::start_periods`] until the criterion of the
/// module doc holds or [`Convergence::max_periods`] is reached. Each round goes to `on_round`.
pub fn converge_by_doubling<E>(
    conv: &Convergence,
    mut run: impl FnMut(u64) -> Result<LyapunovResult, E>,
    mut on_round: impl FnMut(&Round),
) -> Result<ConvergedTle, E> {
    // (the cap bounds the first run too: a cap below the usual start is one run of the cap)
    let mut n = conv.start_periods.max(20).min(conv.max_periods.max(20));
    let mut rounds = Vec::new();
    loop {
        let r = run(n)?;
        let half = r
            .history
            .get((r.history.len() / 2).saturating_sub(1))
            .copied()
            .unwrap_or(f64::NAN);
        let tol = conv.abs_tol.max(conv.rel_tol * r.tle.abs());
        rounds.push(Round {
            periods: n,
            tle: r.tle,
            half,
            stderr: r.spread,
        });
        on_round(rounds.last().expect("just pushed"));
        let done = (r.tle - half).abs() <= tol && r.spread <= tol;
        if done || n >= conv.max_periods || !r.tle.is_finite() {
            return Ok(ConvergedTle {
                result: r,
                rounds,
                converged: done,
                tol,
            });
        }
        n = (2 * n).min(conv.max_periods);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geardyn_model::reference::Duffing;

    #[test]
    fn a_damped_oscillator_converges_to_minus_half_the_damping() {
        // linear oscillator x'' + 0.2 x' + x = 0: both exponents are -0.1
        let sys = Duffing {
            delta: 0.2,
            alpha: 1.0,
            beta: 0.0,
            gamma: 0.0,
            omega: 1.0,
        };
        let opts = LyapunovOptions {
            period: 1.0,
            transient_periods: 0,
            periods: 0,
            d0: 1e-8,
        };
        let converged = |conv: &Convergence| {
            tle_converged(
                sys,
                Scheme::dopri_default(),
                0.0,
                [1.0, 0.0],
                &opts,
                conv,
                |_| {},
            )
            .unwrap()
        };
        let c = converged(&Convergence::default());
        assert!(c.converged);
        assert!((c.result.tle + 0.1).abs() < 5e-4, "{}", c.result.tle);
        // a cap below the first run's length is the longest run made
        let capped = Convergence {
            max_periods: 50,
            abs_tol: 0.0,
            rel_tol: 0.0,
            ..Default::default()
        };
        let c = converged(&capped);
        assert_eq!(c.rounds.iter().map(|r| r.periods).max(), Some(50));
    }
}
