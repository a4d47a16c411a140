//! Analyses for any [`HybridSystem`], not only the gear model: stroboscopic bifurcation diagrams
//! of a one-parameter family (fixed initial state or continuation), in parallel, deterministic;
//! and for any gear system ([`Engine`]) the *decided* sweep ([`decided_sweep`]): every value's
//! motion decided as the single pair's are (period test, persistence of a positive exponent,
//! budget), with its label per mesh. The pair's own sweeps ([`crate::bifurcation`]) add impact
//! sections, the lanes and checkpoints.

use crate::classify::{simulate_decided, Decide};
use crate::driver::{run_periods, Discard, Observer};
use crate::engine::Engine;
use crate::period::minimal_period;
use crate::simulate::{SimError, SimOptions, Summary};
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

/// One value of a [`decided_sweep`].
#[derive(Clone, Debug)]
pub struct DecidedPoint<const N: usize> {
    /// Parameter value.
    pub value: f64,
    /// The decided summary (class, label per mesh, forces, P_ID, `decided_by`); `None` when the
    /// integration failed (`error`).
    pub summary: Option<Summary>,
    /// Stroboscopic states of the record the verdict reports.
    pub strobe: Vec<[f64; N]>,
    /// Final state of the run (the next value's start in a continuation).
    pub final_state: [f64; N],
    /// Integration failure, if any.
    pub error: Option<SimError>,
}

fn decided_one<F, const N: usize>(
    fam: &F,
    p: f64,
    y0: [f64; N],
    opts: &SimOptions,
    how: Decide,
) -> DecidedPoint<N>
where
    F: Family<N>,
    F::System: Engine<N>,
{
    let sys = fam.at(p);
    match simulate_decided(&sys, y0, opts, how) {
        Ok((res, s, _)) => DecidedPoint {
            value: p,
            summary: Some(s),
            strobe: res.strobe_states(),
            final_state: res.final_state.1,
            error: None,
        },
        Err(e) => DecidedPoint {
            value: p,
            summary: None,
            strobe: Vec::new(),
            final_state: y0,
            error: Some(e),
        },
    }
}

/// Decided sweep of a one-parameter family of gear systems: each value from `y0` (in parallel;
/// results in `values` order whatever the thread count) or, with `continuation`, from the final
/// state of the previous value (sequential). Each motion is decided by
/// [`simulate_decided`] with `opts` ([`Family::period`] is not used: the system states its own
/// excitation period).
///
/// ```
/// use geardyn_analysis::generic::{decided_sweep, Family};
/// use geardyn_analysis::simulate::SimOptions;
/// use geardyn_analysis::classify::Decide;
/// use geardyn_model::reference::TwoMassClearance;
/// struct Load;
/// impl Family<4> for Load {
///     type System = TwoMassClearance;
///     fn at(&self, f: f64) -> TwoMassClearance {
///         TwoMassClearance { load: [2.0 * f, f], amplitude: 0.05, ..Default::default() }
///     }
///     fn period(&self, _f: f64) -> f64 { 2.0 * std::f64::consts::PI / 0.7 }
/// }
/// let opts = SimOptions { transient_periods: 200, record_periods: 20, ..Default::default() };
/// let d = decided_sweep(&Load, &[0.5], [1.5, 0.0, 0.0, 0.0], &opts, Decide::default(), false);
/// let s = d[0].summary.as_ref().unwrap();
/// assert_eq!(s.period, 1);        // a heavy load keeps both meshes in contact
/// assert_eq!(s.meshes.len(), 2);  // one label per mesh
/// ```
pub fn decided_sweep<F, const N: usize>(
    fam: &F,
    values: &[f64],
    y0: [f64; N],
    opts: &SimOptions,
    how: Decide,
    continuation: bool,
) -> Vec<DecidedPoint<N>>
where
    F: Family<N>,
    F::System: Engine<N>,
{
    if continuation {
        let mut y = y0;
        values
            .iter()
            .map(|&p| {
                let d = decided_one(fam, p, y, opts, how);
                y = d.final_state;
                d
            })
            .collect()
    } else {
        values
            .par_iter()
            .map(|&p| decided_one(fam, p, y0, opts, how))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lyapunov::tests::Doomed;

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
