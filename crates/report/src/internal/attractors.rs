//! A coexisting-attractors study of seed B over one parameter, declared by an
//! [`AttractorTable`]: a multi-initial diagram, the bifurcation-safety tree (continuation),
//! basins at the seed's points and the marker runs of the backlash sensitivity; the claims are
//! the table's own. The studies `attractors_F` and `attractors_omega` are two tables.

use super::attractor_tables::{
    backlash_sensitivity, basins_at, basins_figure, continuation_opts, marker_runs, AttractorsData,
};
use super::multi;
use crate::claims::Claim;
use crate::runner::{Ctx, Study};
use crate::shared::{continuation_figure, sweep_figure, SweepPanels};
use crate::Section;
use anyhow::Result;
use geardyn_analysis::bifurcation::{Section as Sec, TaskResult};
use geardyn_scenario::Scenario;
use std::path::Path;

/// A coexisting-attractors study declared as data.
pub(super) struct AttractorTable {
    /// Study id.
    pub(super) id: &'static str,
    /// The parameter swept.
    pub(super) param: &'static str,
    /// Fixed settings.
    pub(super) set: &'static [(&'static str, f64)],
    /// The other settings in words, as figure titles give them (`F = 0.07, xi = 0.23`).
    pub(super) at: &'static str,
    /// Values of the multi-initial sweep (sorted and deduplicated after).
    pub(super) values: fn(&Ctx) -> Vec<f64>,
    /// Values of the continuation.
    pub(super) continuation: fn(&Ctx) -> Vec<f64>,
    /// Values where basins are drawn, and whether the extra boxes of initial states are read
    /// there too.
    pub(super) basins: &'static [(f64, bool)],
    /// Values of the marker runs (the backlash sensitivity table).
    pub(super) markers: &'static [f64],
    /// Caption of the multi-initial figure.
    pub(super) multi_caption: &'static str,
    /// Section title and seed reference.
    pub(super) title: (&'static str, &'static str),
    /// Parameters and method of the section, from the data.
    pub(super) words: fn(&AttractorsData) -> (String, String),
    /// The claims checked on the data.
    pub(super) claims: fn(&AttractorsData) -> Vec<Claim>,
}

/// A coexisting-attractors study of the linear-law scenario `lin`.
pub(super) struct Attractors<'a> {
    /// The study.
    pub(super) table: &'static AttractorTable,
    /// The scenario with the linear contact law.
    pub(super) lin: &'a Scenario,
}

impl Study for Attractors<'_> {
    type Data = AttractorsData;

    fn id(&self) -> &'static str {
        self.table.id
    }

    fn compute(&self, ctx: &Ctx, dir: &Path) -> Result<AttractorsData> {
        let (tb, p) = (self.table, self.table.param);
        let b = self.lin.with_all(tb.set)?;
        let d = b.params().d_single;
        let mut values = (tb.values)(ctx);
        values.sort_by(f64::total_cmp);
        values.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
        let ics = ctx.n(6, 12);
        let sim = ctx.sim((150, 300), (30, 60));
        let multi: Vec<TaskResult> = ctx.sweep(
            dir,
            &format!("{p} multi-initial"),
            &b,
            &multi(p, values.clone(), sim, ics, d),
        )?;
        let opts = continuation_opts(p, (tb.continuation)(ctx), ctx.n(8, 24), d);
        let continuation = ctx.continuation(dir, &format!("{p} continuation"), &b, &opts)?;
        let nb = ctx.n(24, 80);
        let mut basins = Vec::new();
        for &(v, extra) in tb.basins {
            let m = b.with(p, v)?.model().clone();
            let name = format!("basins_{p}_{v}");
            basins.push(basins_at(ctx, dir, name, &m, (nb, d), extra)?);
        }
        let markers = marker_runs(ctx, dir, &b, p, tb.markers)?;
        Ok(AttractorsData {
            d,
            values,
            ics,
            nb,
            multi,
            continuation,
            basins,
            markers,
        })
    }

    fn render(&self, ctx: &Ctx, dir: &Path, data: &AttractorsData) -> Result<Section> {
        let (tb, p) = (self.table, self.table.param);
        let c = &data.continuation;
        let fig = sweep_figure(
            ctx,
            dir,
            &format!("multi_{p}"),
            p,
            &data.multi,
            &[Sec::Strobe, Sec::DsDown],
            &SweepPanels::default(),
            &format!("Multi-initial bifurcation over {p} ({})", tb.at),
            tb.multi_caption,
        )?;
        let title = format!("Bifurcation-safety tree over {p}");
        let (fig_c, table_c) = continuation_figure(ctx, dir, &format!("tree_{p}"), p, c, &title)?;
        let mut figures = vec![fig, fig_c];
        let mut tables = vec![table_c];
        for ((v, _), basins) in tb.basins.iter().zip(&data.basins) {
            let title = format!("Basins at {p} = {v} ({})", tb.at);
            let (bf, bt) = basins_figure(ctx, dir, basins, &title)?;
            figures.push(bf);
            tables.push(bt);
        }
        tables.push(backlash_sensitivity(ctx, dir, &data.markers)?);
        let (parameters, method) = (tb.words)(data);
        Ok(Section {
            id: tb.id.into(),
            title: tb.title.0.into(),
            seed_ref: tb.title.1.into(),
            parameters,
            method,
            figures,
            readings: vec![format!(
                "Continuation: {} intervals, {} events (tree_{p}_branches.csv).",
                c.intervals.len(),
                c.events.len()
            )],
            tables,
            claims: vec![],
            alternatives: vec![],
            seconds: 0.0,
        })
    }

    fn claims(&self, data: &AttractorsData) -> Vec<Claim> {
        (self.table.claims)(data)
    }
}
