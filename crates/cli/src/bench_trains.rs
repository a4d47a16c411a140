//! `geardyn bench --trains`: the cost of a gear train's excitation period beside the pair's.
//!
//! Each train runs its dynamic model (`geardyn_train::dynamics`) at the default operating point
//! from its static deflection, record only, with Dormand–Prince (default tolerances) and with
//! RK4 (512 steps per mesh cycle); the pair is case C1 at `omega = 1` on the same settings. The
//! figure of merit is the cost per mesh cycle of mesh 1 over the pair's, against the number of
//! meshes (a train's right-hand side sums its meshes: it should not cost more than that many
//! pairs). Every train runs in the state size the commands give it (8 components for up to 4
//! elastic degrees of freedom: the pair and the two-stage drive padded, `crate::train`), so the
//! figures are those of the commands.

use anyhow::Result;
use geardyn_analysis::simulate::{simulate, Method, SimOptions};
use geardyn_model::{presets, GearSystem, MeshModel};
use geardyn_train::dynamics::{TrainModel, TrainOperating};
use std::time::Instant;

/// Excitation periods of a timed run (mesh cycles for a one-cycle period).
const PERIODS: u64 = 200;

fn methods() -> [(&'static str, Method); 2] {
    [
        ("dopri", Method::default()),
        (
            "rk4",
            Method::Rk4 {
                steps_per_cycle: 512,
            },
        ),
    ]
}

/// Best wall time (s) of `repeat` runs of `sys` over `periods` periods with `method`, and the
/// steps of one.
fn time<S: GearSystem<N>, const N: usize>(
    sys: &S,
    y0: [f64; N],
    method: Method,
    periods: u64,
    repeat: u32,
) -> Result<(f64, u64)> {
    let opts = SimOptions {
        method,
        transient_periods: 0,
        record_periods: periods,
        ..Default::default()
    };
    let mut best = f64::INFINITY;
    let mut steps = 0;
    for _ in 0..repeat.max(1) {
        let t = Instant::now();
        let r = simulate(sys, y0, &opts)?;
        best = best.min(t.elapsed().as_secs_f64());
        steps = r.steps;
    }
    Ok((best, steps))
}

/// Prints the figures.
pub fn figures(repeat: u32) -> Result<()> {
    let mut p = presets::classic();
    p.omega = 1.0;
    let pair = MeshModel::new(&p)?;
    let op = TrainOperating::default();
    let planetary = TrainModel::<8>::new(
        &geardyn_train::presets::planetary(&Default::default())?,
        &op,
    )?;
    let two = TrainModel::<8>::new(
        &geardyn_train::presets::two_stage(&Default::default())?,
        &op,
    )?;
    let single = TrainModel::<8>::new(&geardyn_train::presets::single_pair()?, &op)?;
    for (name, method) in methods() {
        let (tp, sp) = time(&pair, [0.0, 0.0], method, PERIODS, repeat)?;
        let per_cycle_pair = tp / PERIODS as f64;
        println!(
            "trains {name}: pair (C1, omega 1) {PERIODS} mesh cycles: {sp} steps, {:.2} us per mesh cycle",
            1e6 * per_cycle_pair
        );
        let row = |label: &str, meshes: usize, cycles: u64, secs: f64, steps: u64| {
            let per_cycle = secs / cycles as f64;
            println!(
                "trains {name}: {label:<28} {meshes} meshes, {cycles} mesh cycles: {steps} steps, {:.2} us per mesh cycle = {:.2} x the pair (bound: {meshes} x)",
                1e6 * per_cycle,
                per_cycle / per_cycle_pair
            );
        };
        let (t, s) = time(&single, single.static_state(), method, PERIODS, repeat)?;
        row("pair as a train", 1, PERIODS, t, s);
        let (t, s) = time(
            &planetary,
            planetary.static_state(),
            method,
            PERIODS,
            repeat,
        )?;
        row("planetary (3 planets)", 6, PERIODS, t, s);
        // 25 cycles of stage 1 per excitation period
        let periods = PERIODS / 25;
        let (t, s) = time(&two, two.static_state(), method, periods, repeat)?;
        row(
            "two-stage",
            2,
            periods * u64::from(two.cycles_per_period()),
            t,
            s,
        );
    }
    Ok(())
}
