//! Seed A (files 000, 001, 002): the external 40/40 pair with a chipped pinion tooth, friction
//! and back-side impacts with restitution. Every figure/table of seed A that the model computes,
//! at the seed's parameters (c = 0.01, mu = 0.15, 2D = 2, error coefficient 0.05, R = 0.85);
//! where the seed is silent (the mesh frequency of the load sweep, the load of the frequency
//! sweep, the chip size) the choice is stated and its sensitivity shown.
//!
//! One module per study, named after its id. This module holds the plan, the settings the
//! seed leaves open and the helpers several studies share.
//!
//! Each study is a [`crate::runner::Study`]: it computes its data (`compute`: the sweeps,
//! continuations, basins and runs through the [`Ctx`] requests, returned as a plain struct) and
//! renders it (`render`: CSV files, figures, readings and claims, the thresholds of the claims as
//! named constants beside them).

mod coexistence_load;
mod fault_signatures;
mod frequency_sweep;
mod load_sensitivity;
mod load_sweep;
mod orbits_load;
mod portraits;
mod revolution;
mod states;
mod stiffness;

pub(crate) use stiffness::stiffness_figures;

use crate::interpretations::{label_claims, Axis, Interpretation};
use crate::runner::{cached, rendered, sweep_options, Ctx, Plan};
use crate::Section;
use anyhow::{Context, Result};
use geardyn_analysis::bifurcation::{Section as Sec, SweepMode, SweepOptions};
use geardyn_analysis::simulate::SimOptions;
use geardyn_scenario::Scenario;

const A000: &str = "seed A 000 (summary)";
const A001: &str = "seed A 001 (paper)";
const A002: &str = "seed A 002 (short version)";

/// Mesh frequency of the load sweep (the seed does not state it; chosen: ω = 1.2, where seed
/// 000 places periodic motion with diminishing impacts).
const OMEGA_LOAD: f64 = 1.2;
/// Seed A's unstated readings, the headline reading of each first.
const AXES: [Axis; 2] = [
    Axis {
        name: "load-sweep frequency",
        source: "seed A 000 ¶9; 001 §3; 002 §5.2",
        text: "the bifurcation diagram and the impact-force periodogram over F are given without the mesh frequency they were computed at",
        choices: &["omega = 1.2", "omega = 1", "omega = 1.1", "omega = 1.3", "omega = 1.4"],
        why: "where seed 000 places periodic motion with diminishing impacts",
    },
    Axis {
        name: "chip size",
        source: "seed A 001 §2 (Fig. 2)",
        text: "«the tip of a pinion tooth is chipped»: the removed height is not given",
        choices: &["1 mm removed (the preset's)", "0.5 mm removed", "1.5 mm removed"],
        why: "the preset's documented default, a third of the addendum",
    },
];

/// Removed tip heights (mm) of the [`AXES`] chip readings, in their order.
const CHIP_MM: [f64; 3] = [1.0, 0.5, 1.5];

fn sweep(
    param: &str,
    values: Vec<f64>,
    mode: SweepMode,
    sim: SimOptions,
    sections: Vec<Sec>,
) -> SweepOptions {
    sweep_options(param, values, (mode, sim), sections, false)
}

/// The healthy twin integrates the same physical time (its excitation period is one mesh cycle).
fn healthy_sim(sim: SimOptions, cycles: u32) -> SimOptions {
    SimOptions {
        transient_periods: sim.transient_periods * cycles as u64,
        record_periods: sim.record_periods * cycles as u64,
        decision_periods: sim.decision_periods * cycles as u64,
        ..sim
    }
}

/// The plan.
pub fn plan(ctx: &Ctx) -> Result<Vec<Section>> {
    let pm = ctx
        .scenario
        .pair_model()
        .cloned()
        .context("the breakage plan needs the physical [pair]")?;
    let base = ctx.base()?;
    let healthy = base.healthy()?;
    let (pm, base, healthy) = (&pm, &base, &healthy);
    // the longest first (they start first), then the rest
    let plan: Plan<'_> = vec![
        cached(frequency_sweep::FrequencySweep { base }),
        cached(load_sensitivity::LoadSensitivity { base }),
        rendered(coexistence_load::CoexistenceLoad { base }),
        cached(load_sweep::LoadSweep {
            base,
            healthy,
            nf: ctx.n(20, 97),
        }),
        rendered(orbits_load::OrbitsLoad {
            base,
            omega: OMEGA_LOAD,
        }),
        rendered(revolution::Revolution { base, healthy }),
        rendered(portraits::Portraits { base }),
        rendered(fault_signatures::FaultSignatures { base }),
        rendered(stiffness::Stiffness { pm, base }),
        rendered(states::States { pm, base }),
    ];
    // in the page's order
    let order = [
        "stiffness",
        "states",
        "revolution",
        "load_sweep",
        "load_sensitivity",
        "coexistence_load",
        "orbits_load",
        "frequency_sweep",
        "portraits",
        "fault_signatures",
    ];
    let mut out = ctx.studies(plan)?;
    out.sort_by_key(|s| order.iter().position(|o| *o == s.id));
    // the load sweep and every other study run the headline reading of the text
    let headline = Interpretation::headline(&AXES).label(&AXES);
    for sec in &mut out {
        label_claims(&mut sec.claims, &headline);
    }
    Ok(out)
}

/// `base` with `mm` removed from the chipped tip (the chip-size reading).
pub(crate) fn with_chip(base: &Scenario, mm: f64) -> Result<Scenario> {
    let mut spec = base.spec().clone();
    let b = spec
        .pair
        .as_mut()
        .and_then(|p| p.breakage.as_mut())
        .context("the chip-size reading needs a pair with a broken tooth")?;
    b.removed_height_mm = Some(mm);
    b.tip_radius_mm = None;
    Ok(spec.resolve()?)
}
