//! A gear system other than the single pair through the same analyses: the two-mass,
//! two-clearance toy (`TwoMassClearance`: four states, two meshes with backlash) simulated,
//! decided, swept over its forcing, its top Lyapunov exponent, its basins on a plane of the state,
//! its attractors continued and a periodic orbit with its Floquet multipliers. Replace `TwoMassClearance` by a system of your own that
//! implements `HybridSystem`, `Variational` and `GearSystem` (see the doc of
//! `geardyn::model::system`), plus `impl Engine<N> for MySystem {}` and, for basins and
//! continuation, `Recordable<N>` through `describe_gear` / `decide_gear`.
//!
//! Run: `cargo run --release --example two_mass_system`

use geardyn::analysis::attractor::IdentifyOptions;
use geardyn::analysis::basins::{basins, Axis, BasinOptions, Slice};
use geardyn::analysis::continuation::{continuation_of, ContinuationOptions};
use geardyn::analysis::orbits::{find_orbit, OrbitOptions};
use geardyn::model::reference::TwoMassClearance;
use geardyn::prelude::*;

/// The toy at forcing amplitude `a`.
struct Forcing;
impl Family<4> for Forcing {
    type System = TwoMassClearance;
    fn at(&self, a: f64) -> TwoMassClearance {
        TwoMassClearance {
            amplitude: a,
            load: [0.1, 0.05],
            omega: 0.5,
            ..Default::default()
        }
    }
    fn period(&self, _a: f64) -> f64 {
        2.0 * std::f64::consts::PI / 0.5
    }
}

fn main() {
    let sys = Forcing.at(0.4);
    let opts = SimOptions::default();

    // one motion, decided: period test, persistence of a positive exponent, budget
    let (res, s, _) = simulate_decided(&sys, [0.0; 4], &opts, Decide::default()).unwrap();
    println!("motion: {} ({})", s.label, s.describe());
    for (m, r) in s.meshes.iter().zip(&res.meshes) {
        println!(
            "  {}: label {}, P_ID {:.3}, max force {:.3}, {} contact events",
            m.name,
            m.label,
            m.p_id,
            m.max_force,
            r.events.len()
        );
    }

    // its top Lyapunov exponent (variational equation with saltation at every contact change)
    let (t, y) = res.final_state;
    if let Some((tle, se)) = sys.tle(&opts, t, y, 0.0, 200) {
        println!("top Lyapunov exponent: {tle:.4} ± {se:.4}");
    }

    // a decided sweep over the forcing amplitude (in parallel; the same on any thread count)
    let values: Vec<f64> = (0..8).map(|i| 0.1 + 0.1 * i as f64).collect();
    let sweep = SimOptions {
        transient_periods: 200,
        record_periods: 32,
        ..Default::default()
    };
    for p in decided_sweep(
        &Forcing,
        &values,
        [0.0; 4],
        &sweep,
        Decide::default(),
        false,
    ) {
        match p.summary {
            Some(s) => println!(
                "A = {:.2}: {} (decided by {:?})",
                p.value, s.label, s.decided_by
            ),
            None => println!("A = {:.2}: failed ({:?})", p.value, p.error),
        }
    }

    // basins on the plane (x1, x2) of the state, velocities zero
    let identify = IdentifyOptions {
        sim: SimOptions {
            transient_periods: 150,
            record_periods: 32,
            ..Default::default()
        },
        ..Default::default()
    };
    let grid = BasinOptions {
        x: Axis {
            min: -2.0,
            max: 2.0,
            n: 12,
        },
        v: Axis {
            min: -2.0,
            max: 2.0,
            n: 12,
        },
        identify,
        slice: Slice::new((0, 2), [0.0; 4]).unwrap(),
    };
    let b = basins(&sys, &grid, &Default::default(), |_, _| {});
    for a in &b.attractors {
        println!(
            "basin of {}: {:.1} %",
            a.descriptor.label,
            100.0 * a.fraction
        );
    }

    // attractors continued over the forcing amplitude
    let cont = ContinuationOptions {
        param: "A".into(),
        values: values.clone(),
        ics: 8,
        seed: 1,
        x0_range: (-2.0, 2.0),
        v0_range: (-1.0, 1.0),
        phase: 0.0,
        identify,
    };
    let c = continuation_of(&Forcing, &cont, &Slice::default()).expect("checked options");
    for e in &c.events {
        println!("{}", e.text);
    }
    println!(
        "{} branch points, {} events",
        c.points.len(),
        c.events.len()
    );

    // the period-2 orbit at A = 0.6 by shooting, from a point of the decided motion, and its four
    // Floquet multipliers (saltation at every contact change)
    let at = Forcing.at(0.6);
    let (res, s, _) = simulate_decided(&at, [0.0; 4], &sweep, Decide::default()).unwrap();
    let start = res.strobe.last().unwrap().y;
    let o = OrbitOptions {
        period: s.period as u32,
        ..Default::default()
    };
    match find_orbit(&at, start, &o) {
        Ok(orbit) => {
            let m: Vec<String> = orbit
                .multipliers
                .iter()
                .map(|m| format!("{:.4}{:+.4}i", m.re, m.im))
                .collect();
            println!(
                "orbit of period {} at A = 0.6 ({}): multipliers {}",
                orbit.period,
                if orbit.stable { "stable" } else { "unstable" },
                m.join(", ")
            );
        }
        Err(e) => println!("no orbit: {e}"),
    }
}
