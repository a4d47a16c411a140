//! Case C1 (docs/model.md §6): the benchmark's bifurcation diagram, frequency response and
//! basins.
//!
//! One module per study, named after its id; each computes its data (`compute`) and renders it
//! (`render`).

mod basins;
mod bifurcation;
mod orbits;
mod response;

use crate::runner::{Ctx, Study};
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
    let jobs: Vec<Study<'_>> = vec![
        Box::new(move || {
            ctx.study("bifurcation", &(n,), |dir| {
                bifurcation::study(ctx, base, n, sim, dir)
            })
        }),
        Box::new(move || {
            ctx.study("response", &(nr,), |dir| {
                response::study(ctx, base, nr, sim, dir)
            })
        }),
        Box::new(move || ctx.study("basins", &(nb,), |dir| basins::study(ctx, base, nb, dir))),
        Box::new(move || {
            ctx.study("orbits", &(ctx.n(40, 60),), |dir| {
                orbits::study(ctx, base, dir)
            })
        }),
    ];
    let out = ctx.studies(jobs)?;
    Ok(out)
}
