//! Analyses for any [`HybridSystem`], not only the gear model: stroboscopic bifurcation diagrams
//! of a one-parameter family (fixed initial state or continuation), in parallel, deterministic.
//! The gear-specific sweeps ([`crate::bifurcation`]) add impact sections, labels and P_ID.

use crate::driver::{run_periods, Discard, Observer};
use crate::period::minimal_period;
use geardyn_solvers::{HybridSystem, Integrator, Scheme, SolverError};
use rayon::prelude::*;

/// A one-parameter family of systems (the user's model at parameter value `p`).
pub trait Family<const N: usize>: Sync {
    /// The system type.
    type System: HybridSystem<N>;
    /// The system at parameter value `p`.
    fn at(&self, p: f64) -> Self::System;
    /// Stroboscopic period at `p` (the forcing period).
    fn period(&self, p: f64) -> f64;
}

/// Stroboscopic points of one parameter value.
#[derive(Clone, Debug, PartialEq)]
pub struct StrobeBranch<const N: usize> {
    /// Parameter value.
    pub value: f64,
    /// Recorded points.
    pub points: Vec<[f64; N]>,
    /// Minimal period (0: none found up to 32).
    pub period: usize,
    /// Integration failure, if any.
    pub error: Option<SolverError>,
}

struct Collect<const N: usize>(Vec<[f64; N]>);
impl<S: HybridSystem<N>, const N: usize> Observer<S, N> for Collect<N> {
    fn on_strobe(&mut self, _t: f64, y: &[f64; N]) {
        self.0.push(*y);
    }
}

fn one<F: Family<N>, const N: usize>(
    fam: &F,
    p: f64,
    scheme: Scheme,
    y0: [f64; N],
    transient: u64,
    record: u64,
) -> (StrobeBranch<N>, [f64; N]) {
    let period = fam.period(p);
    let run = || -> Result<([f64; N], Vec<[f64; N]>), SolverError> {
        let mut it = Integrator::new(fam.at(p), scheme, 0.0, y0)?;
        run_periods(&mut it, period, transient, &mut Discard)?;
        // (a user-given count: reserve a bounded amount, the points grow as they are computed)
        let mut c = Collect(Vec::with_capacity(record.min(4096) as usize));
        run_periods(&mut it, period, record, &mut c)?;
        Ok((*it.y(), c.0))
    };
    match run() {
        Ok((y_end, points)) => {
            let n = minimal_period(&points, 32).unwrap_or(0);
            (
                StrobeBranch {
                    value: p,
                    points,
                    period: n,
                    error: None,
                },
                y_end,
            )
        }
        Err(e) => (
            StrobeBranch {
                value: p,
                points: vec![],
                period: 0,
                error: Some(e),
            },
            y0,
        ),
    }
}

/// Stroboscopic bifurcation diagram: each value from `y0` (in parallel) or, with `continuation`,
/// each value from the final state of the previous one (sequential). Results are in `values`
/// order whatever the thread count.
///
/// ```
/// use geardyn_analysis::generic::{strobe_bifurcation, Family};
/// use geardyn_model::reference::Duffing;
/// use geardyn_solvers::Scheme;
/// struct Forcing;
/// impl Family<2> for Forcing {
///     type System = Duffing;
///     fn at(&self, g: f64) -> Duffing { Duffing { delta: 0.3, alpha: -1.0, beta: 1.0, gamma: g, omega: 1.2 } }
///     fn period(&self, _g: f64) -> f64 { 2.0 * std::f64::consts::PI / 1.2 }
/// }
/// let d = strobe_bifurcation(&Forcing, &[0.2], Scheme::dopri_default(), [1.0, 0.0], 200, 16, false);
/// assert_eq!(d[0].period, 1); // small forcing: period-1 oscillation in one well
/// ```
pub fn strobe_bifurcation<F: Family<N>, const N: usize>(
    fam: &F,
    values: &[f64],
    scheme: Scheme,
    y0: [f64; N],
    transient: u64,
    record: u64,
    continuation: bool,
) -> Vec<StrobeBranch<N>> {
    if continuation {
        let mut y = y0;
        values
            .iter()
            .map(|&p| {
                let (b, y_end) = one(fam, p, scheme, y, transient, record);
                y = y_end;
                b
            })
            .collect()
    } else {
        values
            .par_iter()
            .map(|&p| one(fam, p, scheme, y0, transient, record).0)
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geardyn_solvers::HybridSystem;

    /// Uniform motion that blows up half a time unit into the run.
    struct Doomed;
    impl HybridSystem<1> for Doomed {
        type Mode = ();
        type TimeTerms = ();
        fn initial_mode(&self, _t: f64, _y: &mut [f64; 1]) {}
        fn time_terms(&self, _t: f64) {}
        fn rhs(&self, t: f64, _tt: &(), _y: &[f64; 1], _m: &(), dy: &mut [f64; 1]) {
            dy[0] = if t < 0.5 { 1.0 } else { f64::NAN };
        }
    }
    struct Fam;
    impl Family<1> for Fam {
        type System = Doomed;
        fn at(&self, _p: f64) -> Doomed {
            Doomed
        }
        fn period(&self, _p: f64) -> f64 {
            1.0
        }
    }

    #[test]
    fn a_huge_record_count_reserves_nothing_up_front() {
        // u64::MAX points would be a capacity overflow if reserved ahead
        let d = strobe_bifurcation(
            &Fam,
            &[0.0],
            Scheme::Rk4 { h: 0.01 },
            [0.0],
            0,
            u64::MAX,
            true,
        );
        assert!(matches!(d[0].error, Some(SolverError::NonFinite { .. })));
    }
}
