//! The exponent a caller asks for ([`LyapunovRequest`]: `geardyn lyapunov`, Python's
//! `lyapunov()`): which estimates, a fixed length or converging runs, checked once; and its
//! report. The estimates themselves are [`crate::lyapunov`] and [`crate::tle_convergence`].

use crate::lyapunov::{tle_two_trajectory, tle_variational, LyapunovOptions, LyapunovResult};
use geardyn_solvers::SolverError;
use serde::Serialize;

/// Which estimates of the exponent a [`LyapunovRequest`] computes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum TleMethod {
    /// [`tle_variational`] only.
    Variational,
    /// [`tle_two_trajectory`] only.
    TwoTrajectory,
    /// Both, the second a check on the first.
    Both,
}

impl TleMethod {
    /// Every method by name, in the order of the help texts.
    pub const NAMES: [&'static str; 3] = ["variational", "two-trajectory", "both"];

    /// The method named `name` (`variational`, `two-trajectory`, `both`).
    pub fn from_name(name: &str) -> Result<Self, LyapunovRequestError> {
        match name {
            "variational" => Ok(TleMethod::Variational),
            "two-trajectory" => Ok(TleMethod::TwoTrajectory),
            "both" => Ok(TleMethod::Both),
            _ => Err(LyapunovRequestError::Method(name.to_string())),
        }
    }

    /// Its name.
    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    fn variational(self) -> bool {
        self != TleMethod::TwoTrajectory
    }

    fn two_trajectory(self) -> bool {
        self != TleMethod::Variational
    }
}

/// A top-Lyapunov-exponent computation as a caller states it (`geardyn lyapunov`,
/// `geardyn.lyapunov`): the defaults and limits in one place, and the one way it runs
/// ([`LyapunovRequest::run`]).
///
/// ```
/// use geardyn_analysis::lyapunov_request::{LyapunovRequest, TleMethod};
/// use geardyn_analysis::simulate::SimOptions;
/// let model = geardyn_model::MeshModel::new(&geardyn_model::presets::classic()).unwrap();
/// let sim = SimOptions { transient_periods: 50, ..Default::default() };
/// let req = LyapunovRequest { method: TleMethod::Variational, periods: Some(40), ..Default::default() };
/// let r = req.run(&model, &sim, [0.0, 0.0], |_| {}).unwrap();
/// assert!(r.variational.is_some() && r.two_trajectory.is_none() && r.periods == 40);
/// let bad = LyapunovRequest { d0: 0.5, ..Default::default() };
/// assert!(bad.check().unwrap_err().to_string().contains("--d0 0.5"));
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct LyapunovRequest {
    /// Estimates computed.
    pub method: TleMethod,
    /// `None`: the variational run doubles its length until converged, up to `max_periods`
    /// (the two-trajectory check then uses the converged length); `Some(n)`: runs of `n`
    /// excitation periods.
    pub periods: Option<u64>,
    /// Cap of the converging runs (excitation periods), `20 ..= MAX_PERIODS`.
    pub max_periods: u64,
    /// Initial distance of the two-trajectory method (state units), in `(0, 0.01)`.
    pub d0: f64,
}

impl Default for LyapunovRequest {
    /// The defaults of the CLI and of Python: both methods, run until converged within 25 600
    /// periods, `d0 = 1e-6`.
    fn default() -> Self {
        LyapunovRequest {
            method: TleMethod::Both,
            periods: None,
            max_periods: 25_600,
            d0: 1e-6,
        }
    }
}

/// Why a Lyapunov request was refused or failed.
#[derive(Debug, thiserror::Error)]
pub enum LyapunovRequestError {
    /// An unknown method.
    #[error("bad method '{0}': allowed variational, two-trajectory, both")]
    Method(String),
    /// `d0` out of `(0, 0.01)`.
    #[error("bad --d0 {}: allowed (0, 0.01)", geardyn_model::error::num(*.0))]
    D0(f64),
    /// `max_periods` out of range.
    #[error("bad --max-periods {0}: allowed 20 ..= {max}", max = crate::simulate::MAX_PERIODS)]
    MaxPeriods(u64),
    /// The integration failed.
    #[error(transparent)]
    Solver(#[from] SolverError),
}

/// What a [`LyapunovRequest`] computed.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LyapunovReport {
    /// Estimates computed.
    pub method: TleMethod,
    /// Measured excitation periods of the final runs.
    pub periods: u64,
    /// The converging runs (`None` with a fixed length).
    pub convergence: Option<crate::tle_convergence::ConvergedTle>,
    /// The variational estimate (the last converging run's, or the fixed-length run's).
    pub variational: Option<LyapunovResult>,
    /// The two-trajectory estimate.
    pub two_trajectory: Option<LyapunovResult>,
}

impl LyapunovReport {
    /// Whether the two estimates disagree beyond three standard errors each (plus 1e-3): the
    /// two-trajectory one then measures the integrator's noise or a discontinuity, not the flow.
    pub fn disagree(&self) -> bool {
        match (&self.variational, &self.two_trajectory) {
            // (a missing spread counts as none: f64::max drops the NaN)
            (Some(v), Some(t)) => {
                (v.tle - t.tle).abs() > 3.0 * (v.spread.max(0.0) + t.spread.max(0.0)) + 1e-3
            }
            _ => false,
        }
    }
}

impl LyapunovRequest {
    /// Checks `d0`, then (when converging) `max_periods`.
    pub fn check(&self) -> Result<(), LyapunovRequestError> {
        if !(self.d0 > 0.0 && self.d0 < 1e-2) {
            return Err(LyapunovRequestError::D0(self.d0));
        }
        if self.periods.is_none()
            && !(20..=crate::simulate::MAX_PERIODS).contains(&self.max_periods)
        {
            return Err(LyapunovRequestError::MaxPeriods(self.max_periods));
        }
        Ok(())
    }

    /// Runs the request on `model` from `y0` with the simulation settings `sim` (its method,
    /// start time and transient; its recorded periods are ignored: [`LyapunovRequest::periods`]
    /// says the length). Each converging run is handed to `on_round` when done.
    pub fn run(
        &self,
        model: &geardyn_model::MeshModel,
        sim: &crate::simulate::SimOptions,
        y0: [f64; 2],
        on_round: impl FnMut(&crate::tle_convergence::Round),
    ) -> Result<LyapunovReport, LyapunovRequestError> {
        self.check()?;
        let mut opts = LyapunovOptions {
            period: model.excitation_period(),
            transient_periods: sim.transient_periods,
            periods: self.periods.unwrap_or(sim.record_periods),
            d0: self.d0,
        };
        let scheme = sim.method.scheme(model);
        let t0 = sim.tau0;
        let mut report = LyapunovReport {
            method: self.method,
            periods: opts.periods,
            convergence: None,
            variational: None,
            two_trajectory: None,
        };
        if self.periods.is_none() {
            let conv = crate::tle_convergence::Convergence {
                max_periods: self.max_periods,
                ..Default::default()
            };
            let c = crate::tle_convergence::tle_converged(
                model.clone(),
                scheme,
                t0,
                y0,
                &opts,
                &conv,
                on_round,
            )?;
            opts.periods = c.rounds.last().map_or(opts.periods, |r| r.periods);
            if self.method.variational() {
                report.variational = Some(c.result.clone());
            }
            report.convergence = Some(c);
        } else if self.method.variational() {
            report.variational = Some(tle_variational::<_, 2, 5>(
                model.clone(),
                scheme,
                t0,
                y0,
                &opts,
            )?);
        }
        report.periods = opts.periods;
        if self.method.two_trajectory() {
            report.two_trajectory = Some(tle_two_trajectory(model.clone(), scheme, t0, y0, &opts)?);
        }
        Ok(report)
    }
}
