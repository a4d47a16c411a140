//! Measures how long chaotic transients last: every value of a parameter is integrated for a
//! long record from one initial state, and the first excitation period after which the
//! stroboscopic points repeat (period 1..=32, to `tol (1 + max|state|)`) until the end of the
//! record is printed as the run's transient lifetime; runs that never settle get the top Lyapunov
//! exponent over the last 1000 periods. These are the measurements behind the chaos verdict's
//! decision horizon (docs/analyses.md, classification rule 2).
//!
//! Run, e.g.:
//! `cargo run --release -p geardyn-analysis --example transient_lifetimes -- breakage F 0.03:0.1:15 10000 omega=1.2`
//!
//! Arguments: preset, swept parameter, `START:STOP:COUNT`, record length in excitation periods,
//! then any `NAME=VALUE` settings and optionally `rk4` (fixed-step RK4, 512 steps per mesh cycle;
//! default the adaptive integrator at rtol 1e-9) and `x0=..`/`v0=..` for the initial state.

use geardyn_analysis::bifurcation::linspace;
use geardyn_analysis::pair_engine::tle_of;
use geardyn_analysis::simulate::{simulate, Method, SimOptions};
use geardyn_scenario::ScenarioSpec;
use rayon::prelude::*;

/// Period-test tolerance of the measurement (relative to `1 + max|state|`): ten times the
/// classification's strict one, so the adaptive integrator's noise on event-rich records does
/// not hide a period.
const TOL: f64 = 1e-5;

/// First index from which the points repeat with some period `n <= 32` to the end, and `n`;
/// `None` when the last 3 x 32 points are not periodic.
fn settle(pts: &[geardyn_analysis::simulate::Strobe<2>]) -> Option<(usize, usize)> {
    let scale = 1.0
        + pts
            .iter()
            .fold(0.0f64, |m, p| m.max(p[1].abs()).max(p[2].abs()));
    let tol = TOL * scale;
    let len = pts.len();
    let mut best: Option<(usize, usize)> = None;
    for n in 1..=32usize {
        if len < 3 * n + 96 {
            break;
        }
        // last i with |p[i] - p[i - n]| > tol
        let last_bad = (n..len).rev().find(|&i| {
            (pts[i][1] - pts[i - n][1])
                .abs()
                .max((pts[i][2] - pts[i - n][2]).abs())
                > tol
        });
        let start = match last_bad {
            None => 0,
            Some(i) => i + 1 - n,
        };
        if len - start >= 96.max(3 * n) && best.is_none_or(|(s, _)| start < s) {
            best = Some((start, n));
        }
    }
    best
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() < 4 {
        eprintln!("usage: transient_lifetimes PRESET PARAM START:STOP:COUNT PERIODS [NAME=VALUE ...] [rk4]");
        std::process::exit(2);
    }
    let mut spec = ScenarioSpec::preset(&args[0]).expect("preset");
    let param = args[1].clone();
    let r: Vec<f64> = args[2]
        .split(':')
        .map(|s| s.parse().expect("range"))
        .collect();
    let values = linspace(r[0], r[1], r[2] as usize);
    let periods: u64 = args[3].parse().expect("periods");
    let mut method = Method::default();
    let mut y0 = [0.0, 0.0];
    for a in &args[4..] {
        if a == "rk4" {
            method = Method::Rk4 {
                steps_per_cycle: 512,
            };
        } else if let Some((k, v)) = a.split_once('=') {
            let v: f64 = v.parse().expect("value");
            match k {
                "x0" => y0[0] = v,
                "v0" => y0[1] = v,
                _ => spec.set(k, v).expect("setting"),
            }
        }
    }
    let base = spec.resolve().expect("scenario");
    let rows: Vec<String> = values
        .par_iter()
        .map(|&v| {
            let sc = base.with(&param, v).expect("value");
            let m = sc.model();
            let opts = SimOptions {
                method,
                transient_periods: 0,
                record_periods: periods,
                ..Default::default()
            };
            match simulate(m, y0, &opts) {
                Err(e) => format!("{param}={v}\tfailed: {e}"),
                Ok(res) => match settle(&res.strobe) {
                    Some((s, n)) => format!("{param}={v}\tsettles at {s}\tperiod {n}"),
                    None => {
                        let (t, y) = res.final_state;
                        let opts1 = SimOptions {
                            record_periods: 1000,
                            ..opts
                        };
                        let tle = tle_of(m, &opts1, t, y, res.final_memory);
                        format!("{param}={v}\tnot settled in {periods}\ttle {tle:?}")
                    }
                },
            }
        })
        .collect();
    for r in rows {
        println!("{r}");
    }
}
