//! Periodic orbits as a caller asks for them ([`OrbitsRequest`]: `geardyn orbits`, Python's
//! `orbits()`): one orbit or its branches over a parameter, checked once, and the tables and
//! diagrams of the result.

use crate::simulate::{simulate, SimOptions};
use geardyn_scenario::Scenario;
use serde::Serialize;

use crate::orbit_branches::*;
use crate::orbits::*;

/// One request of `geardyn orbits` / `geardyn.orbits()`: its settings, their ranges and
/// defaults in one place ([`OrbitsRequest::check`]), run by [`run_orbits`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct OrbitsRequest {
    /// `(parameter, start, stop)` of a continuation; `None`: one orbit.
    pub range: Option<(String, f64, f64)>,
    /// Excitation periods of the orbit; `None`: the period of the motion after the transient.
    pub period: Option<u32>,
    /// Excitation periods simulated from `y0` before Newton's method starts.
    pub transient: u64,
    /// Initial state.
    pub y0: [f64; 2],
    /// Stroboscopic phase.
    pub tau0: f64,
    /// Largest arclength step.
    pub ds: f64,
    /// Most branch points.
    pub max_points: usize,
    /// Branch switching at doublings up to this period (0: none).
    pub switch_up_to: u32,
    /// Relative tolerance of the integration (absolute: 1e-2 times it).
    pub rtol: f64,
}

impl Default for OrbitsRequest {
    fn default() -> Self {
        OrbitsRequest {
            range: None,
            period: None,
            transient: 300,
            y0: [0.0, 0.0],
            tau0: 0.0,
            ds: 0.02,
            max_points: 2000,
            switch_up_to: 0,
            rtol: 1e-11,
        }
    }
}

/// Most branch points of one request.
pub const MAX_BRANCH_POINTS: usize = 1_000_000;

fn setting(field: &'static str, value: String, allowed: impl Into<String>) -> OrbitError {
    OrbitError::Setting {
        field,
        value,
        allowed: allowed.into(),
    }
}

impl OrbitsRequest {
    /// Refuses a setting outside its range (naming it and the range), and a parameter the
    /// scenario does not take at either end of the range.
    pub fn check(&self, sc: &Scenario) -> Result<(), OrbitError> {
        use geardyn_model::error::num;
        if let Some(n) = self.period {
            if n == 0 || n > MAX_ORBIT_PERIOD {
                return Err(setting(
                    "period",
                    n.to_string(),
                    format!("1 ..= {MAX_ORBIT_PERIOD}"),
                ));
            }
        }
        let max = crate::simulate::MAX_PERIODS;
        if self.transient > max {
            return Err(setting(
                "transient",
                self.transient.to_string(),
                format!("0 ..= {max}"),
            ));
        }
        if !(self.ds > 0.0 && self.ds <= 1.0) {
            return Err(setting("ds", num(self.ds), "(0, 1]"));
        }
        if !(1e-14..=1e-6).contains(&self.rtol) {
            return Err(setting("rtol", num(self.rtol), "[1e-14, 1e-6]"));
        }
        if self.max_points == 0 || self.max_points > MAX_BRANCH_POINTS {
            return Err(setting(
                "max_points",
                self.max_points.to_string(),
                format!("1 ..= {MAX_BRANCH_POINTS}"),
            ));
        }
        if self.switch_up_to > MAX_ORBIT_PERIOD {
            return Err(setting(
                "switch_up_to",
                self.switch_up_to.to_string(),
                format!("0 ..= {MAX_ORBIT_PERIOD}"),
            ));
        }
        for (field, v) in [("x0", self.y0[0]), ("v0", self.y0[1]), ("tau0", self.tau0)] {
            if !v.is_finite() {
                return Err(setting(field, num(v), "a finite number"));
            }
        }
        if let Some((p, lo, hi)) = &self.range {
            if !(lo.is_finite() && hi.is_finite()) || lo == hi {
                return Err(setting(
                    "range",
                    format!("{}:{}", num(*lo), num(*hi)),
                    "two different finite numbers START:STOP",
                ));
            }
            sc.with(p, *lo)?;
            sc.with(p, *hi)?;
        }
        Ok(())
    }
}

/// Runs an [`OrbitsRequest`] on `sc`: the initial state after the transient at the start of the
/// range, its period (unless given), then one orbit or the branches. `progress` sees every
/// branch point.
pub fn run_orbits(
    sc: &Scenario,
    req: &OrbitsRequest,
    progress: &(dyn Fn(&BranchPoint) + Sync),
) -> Result<Continuation, OrbitError> {
    req.check(sc)?;
    let start = match &req.range {
        Some((p, lo, _)) => sc.with(p, *lo)?,
        None => sc.clone(),
    };
    let solver = |e: crate::simulate::SimError| match e {
        crate::simulate::SimError::Solver(e) => OrbitError::Solver(e),
        crate::simulate::SimError::Setting {
            field,
            value,
            allowed,
        } => OrbitError::Setting {
            field,
            value,
            allowed: allowed.into(),
        },
    };
    let (near, period) = match req.period {
        Some(n) => {
            let near = if req.transient > 0 {
                let opts = SimOptions {
                    transient_periods: req.transient - 1,
                    record_periods: 1,
                    tau0: req.tau0,
                    ..Default::default()
                };
                simulate(start.model(), req.y0, &opts)
                    .map_err(solver)?
                    .final_state
                    .1
            } else {
                req.y0
            };
            (near, n)
        }
        None => {
            // the period as `geardyn simulate` decides it (transients extended where the motion
            // is still settling), and the start from the decided record's end
            let opts = SimOptions {
                transient_periods: req.transient,
                record_periods: 3 * 32,
                tau0: req.tau0,
                ..Default::default()
            };
            let (res, s, _) = crate::classify::simulate_decided(
                start.model(),
                req.y0,
                &opts,
                crate::classify::Decide::default(),
            )
            .map_err(solver)?;
            if !s.motion.is_periodic() {
                return Err(OrbitError::NotPeriodic {
                    x0: req.y0[0],
                    v0: req.y0[1],
                    transient: s.periods_integrated,
                    motion: s.label.clone(),
                });
            }
            (res.final_state.1, s.period as u32)
        }
    };
    let orbit = OrbitOptions {
        period,
        tau0: req.tau0,
        rtol: req.rtol,
        atol: req.rtol * 1e-2,
        ..Default::default()
    };
    match &req.range {
        Some((p, lo, hi)) => {
            let opts = ContinuationOptions {
                param: p.clone(),
                start: *lo,
                stop: *hi,
                ds_max: req.ds,
                max_points: req.max_points,
                switch_up_to: req.switch_up_to,
                orbit,
            };
            continue_orbits(sc, near, &opts, progress)
        }
        None => {
            let o = find_orbit(start.model(), near, &orbit)?;
            let pt = BranchPoint {
                branch: 0,
                param: f64::NAN,
                orbit: o,
            };
            progress(&pt);
            Ok(Continuation {
                points: vec![pt],
                ends: vec!["one orbit".into()],
                ..Default::default()
            })
        }
    }
}

/// The record of every branch point ([`describe_orbit`] at its parameter value; `param` the
/// continued parameter, `None` for one orbit at `sc`), in parallel: `(label, max_force, p_id)`,
/// an empty label and NaN where the record failed.
pub fn orbit_records(
    sc: &Scenario,
    param: Option<&str>,
    points: &[BranchPoint],
    tau0: f64,
) -> Vec<(String, f64, f64)> {
    use rayon::prelude::*;
    points
        .par_iter()
        .map(|p| {
            let here = match param {
                Some(name) => sc.with(name, p.param).ok(),
                None => Some(sc.clone()),
            };
            match here.and_then(|m| describe_orbit(m.model(), &p.orbit, tau0).ok()) {
                Some(s) => (s.label, s.max_force, s.p_id),
                None => (String::new(), f64::NAN, f64::NAN),
            }
        })
        .collect()
}

/// The brute-force diagram an orbit figure draws beneath the branches: strobe points
/// `(value, x)` of a plain simulation (300 + 60 periods from `y0`, DP5, no decision) at `n`
/// values of `[lo, hi]` of `param`, in parallel; a value whose run fails draws nothing.
pub fn strobe_diagram(
    sc: &Scenario,
    param: &str,
    lo: f64,
    hi: f64,
    n: usize,
    y0: [f64; 2],
    tau0: f64,
) -> Vec<(f64, f64)> {
    if n == 0 {
        return Vec::new();
    }
    let values = crate::bifurcation::linspace(lo.min(hi), lo.max(hi), n.max(2));
    use rayon::prelude::*;
    values
        .par_iter()
        .flat_map_iter(|&v| {
            let opts = SimOptions {
                transient_periods: 300,
                record_periods: 60,
                tau0,
                ..Default::default()
            };
            let pts: Vec<(f64, f64)> = sc
                .with(param, v)
                .ok()
                .and_then(|m| simulate(m.model(), y0, &opts).ok())
                .map(|r| r.strobe.iter().map(|p| (v, p.y[0])).collect())
                .unwrap_or_default();
            pts
        })
        .collect()
}
