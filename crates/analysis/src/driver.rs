//! Generic driving loop: integrates any [`HybridSystem`] over whole excitation periods and feeds
//! every step, event and stroboscopic instant to an [`Observer`].

use geardyn_solvers::{HybridSystem, Integrator, SolverError, Step, Stop};

/// Receives what happens during integration. All methods default to doing nothing.
pub trait Observer<S: HybridSystem<N>, const N: usize> {
    /// A step `[step.t0, step.t1]` taken entirely in mode `before`. `stop` says how it ended; for
    /// an event, `after`/`y_after` are the mode and (reset) state after it.
    fn on_step(
        &mut self,
        _sys: &S,
        _step: &Step<N>,
        _before: &S::Mode,
        _stop: Stop,
        _after: &S::Mode,
        _y_after: &[f64; N],
    ) {
    }
    /// The stroboscopic instant `t` (an integer number of excitation periods after the start).
    fn on_strobe(&mut self, _t: f64, _y: &[f64; N]) {}
}

/// An observer that records nothing (for transients).
pub struct Discard;
impl<S: HybridSystem<N>, const N: usize> Observer<S, N> for Discard {}

/// Integrates `periods` excitation periods of length `period` from the integrator's current time,
/// calling `obs.on_strobe` at the end of each. Stroboscopic times are computed as
/// `t_start + j*period` (no accumulated round-off).
pub fn run_periods<S, O, const N: usize>(
    integ: &mut Integrator<S, N>,
    period: f64,
    periods: u64,
    obs: &mut O,
) -> Result<(), SolverError>
where
    S: HybridSystem<N>,
    O: Observer<S, N>,
{
    let t_start = integ.t();
    for j in 1..=periods {
        let t_stop = t_start + j as f64 * period;
        loop {
            let before = *integ.mode();
            let stop = integ.step(t_stop)?;
            obs.on_step(
                integ.system(),
                integ.last_step(),
                &before,
                stop,
                integ.mode(),
                integ.y(),
            );
            match stop {
                Stop::Tstop => break,
                Stop::Terminated { .. } => return Ok(()),
                _ => {}
            }
        }
        obs.on_strobe(integ.t(), integ.y());
    }
    Ok(())
}
