//! Case C1 (docs/model.md §6): the benchmark's bifurcation diagram, frequency response and
//! basins.
//!
//! One module per study, named after its id; each computes its data (`compute`) and renders it
//! (`render`).

mod basins;
mod bifurcation;
mod orbits;
mod response;

use crate::runner::{cached, rendered, Ctx, Plan};
use crate::Section;
use anyhow::Result;

/// The plan.
pub fn plan(ctx: &Ctx) -> Result<Vec<Section>> {
    let base = ctx.base()?;
    let base = &base;
    let n = ctx.n(60, 200);
    let sim = ctx.sim((150, 300), (40, 100));
    let nr = ctx.n(40, 150);
    let nb = ctx.n(40, 140);
    let plan: Plan<'_> = vec![
        cached(bifurcation::Bifurcation { base, n, sim }),
        cached(response::Response { base, nr, sim }),
        rendered(basins::Basins { base, nb }),
        rendered(orbits::Orbits {
            base,
            n: ctx.n(40, 60),
        }),
    ];
    let out = ctx.studies(plan)?;
    Ok(out)
}
