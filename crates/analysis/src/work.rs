//! One estimate of the work a command asks for, in right-hand-side evaluations of the equation
//! of motion (4 per RK4 step, 6 per Dormand–Prince step), and the cap above which a command is
//! refused before it starts (every knob has its own range, but not their product: 10^6 steps per
//! cycle times 10^6 periods would run for days).

use crate::simulate::{Method, SimOptions};
use geardyn_model::MeshModel;

/// Default cap on a command's estimated work (right-hand-side evaluations): 10^12, a few hours
/// of both cores (one evaluation takes 5–60 ns).
pub const DEFAULT_MAX_WORK: f64 = 1e12;
/// Dormand–Prince steps per unit of dimensionless time assumed by the estimate (measured 13–15
/// on every preset at the default tolerances; the natural period is 2 pi).
const DOPRI_STEPS_PER_TIME: f64 = 20.0;

/// Right-hand-side evaluations of one excitation period of `model` with `method`.
pub fn per_period(model: &MeshModel, method: &Method) -> f64 {
    let cycles = f64::from(model.cycles_per_period().max(1));
    match method {
        Method::Rk4 { steps_per_cycle } => 4.0 * f64::from(*steps_per_cycle) * cycles,
        Method::Dopri { .. } => {
            6.0 * (DOPRI_STEPS_PER_TIME * model.excitation_period()).max(20.0 * cycles)
        }
    }
}

/// Right-hand-side evaluations of one excitation period of any gear system (a train): as
/// [`per_period`], Dormand–Prince's steps scaled to the system's shortest natural period (a
/// stiff shaft makes every period dear).
pub fn per_period_system<S: geardyn_model::GearSystem<N>, const N: usize>(
    sys: &S,
    method: &Method,
) -> f64 {
    let cycles = f64::from(sys.cycles_per_period().max(1));
    match method {
        Method::Rk4 { steps_per_cycle } => 4.0 * f64::from(*steps_per_cycle) * cycles,
        Method::Dopri { .. } => {
            let scale = (std::f64::consts::TAU / sys.natural_period()).max(1.0);
            6.0 * (DOPRI_STEPS_PER_TIME * scale * sys.excitation_period()).max(20.0 * cycles)
        }
    }
}

/// Estimated work of one decided run of any gear system with `opts` (see [`per_run`]).
pub fn per_run_system<S: geardyn_model::GearSystem<N>, const N: usize>(
    sys: &S,
    opts: &SimOptions,
) -> f64 {
    let p = per_period_system(sys, &opts.method);
    (opts.transient_periods + opts.record_periods) as f64 * p
        + (opts.decision_periods as f64 * p).min(opts.decision_budget as f64)
}

/// Estimated work of one run with `opts`: its transient and record and, when the run is
/// decided (`decided`), the decision's worst case (followed to the horizon
/// `decision_periods`, at most `decision_budget`).
pub fn per_run(model: &MeshModel, opts: &SimOptions, decided: bool) -> f64 {
    let p = per_period(model, &opts.method);
    let requested = (opts.transient_periods + opts.record_periods) as f64 * p;
    let decision = if decided {
        (opts.decision_periods as f64 * p).min(opts.decision_budget as f64)
    } else {
        0.0
    };
    requested + decision
}

/// Refuses `runs` runs of `per_run` evaluations each above `cap`, with a message that names the
/// estimate, the cap and the flag that lifts it.
pub fn check(runs: usize, per_run: f64, cap: f64) -> Result<f64, String> {
    let total = runs as f64 * per_run;
    if total.is_finite() && total <= cap {
        return Ok(total);
    }
    // 20 ns per evaluation on one core: the order of the hours, not a promise
    let hours = total * 20e-9 / 3600.0;
    Err(format!(
        "the requested work is about {total:.1e} right-hand-side evaluations ({runs} run(s) of {per_run:.1e}, about {hours:.0} core-hours), above the cap of {cap:.0e}: ask for fewer periods, steps or runs, or raise the cap with --max-work (config: simulation.max_work; Python: max_work=N)"
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_product_of_legal_knobs_is_capped_and_the_message_names_the_flag() {
        let model = geardyn_model::MeshModel::new(&geardyn_model::presets::classic()).unwrap();
        let opts = SimOptions::rk4(1_000_000, 0, 1_000_000);
        // 4 evaluations x 1e6 steps x 1e6 periods
        let w = per_run(&model, &opts, false);
        assert_eq!(w, 4e12);
        let e = check(1, w, DEFAULT_MAX_WORK).unwrap_err();
        assert!(e.contains("--max-work") && e.contains("4.0e12"), "{e}");
        assert!(check(1, w, 5e12).is_ok());
        // the decision's worst case counts, bounded by its budget
        let d = SimOptions {
            decision_budget: 1_000,
            ..opts
        };
        assert_eq!(per_run(&model, &d, true), 4e12 + 1_000.0);
        assert!(check(usize::MAX, f64::INFINITY, DEFAULT_MAX_WORK).is_err());
    }
}
