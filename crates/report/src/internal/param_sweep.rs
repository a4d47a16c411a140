//! A bifurcation study of seed B over one parameter, declared by a [`SweepTable`]: the main sweep
//! from (0, 0) with the five sections and the TLE, a multi-initial sweep, the preset's contact
//! law beside the linear one, and a sensitivity table of other settings; the claims are the
//! table's own. The backlash sweep (`backlash_sweep`) and the xi sweep (`xi_sweep`) are two
//! tables.

use super::{chaos_ranges, fixed, interval_table, multi, ranges_text, FIVE};
use crate::claims::Claim;
use crate::classes::{self, tolerant, Pt};
use crate::readings::sequence;
use crate::runner::{hdr, Ctx, Study};
use crate::shared::{sweep_figure, SweepPanels};
use crate::Section;
use anyhow::Result;
use geardyn_analysis::bifurcation::{linspace, Section as Sec, TaskResult};
use geardyn_analysis::simulate::SimOptions;
use geardyn_scenario::Scenario;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// One setting of the sensitivity table: its first cells and the scenario it sweeps.
pub(super) struct Case {
    /// Name of its sweep (progress bar and checkpoint).
    pub(super) name: String,
    /// The table's first cells of its row.
    pub(super) cells: Vec<String>,
    /// The scenario swept.
    pub(super) scenario: Scenario,
}

/// What a parameter sweep shows: its figures' and tables' texts.
pub(super) struct Texts {
    /// Title and caption of the main figure.
    pub(super) main: (&'static str, &'static str),
    /// Title of the interval table.
    pub(super) intervals: &'static str,
    /// Title and caption of the multi-initial figure.
    pub(super) multi: (&'static str, &'static str),
    /// Title and caption of the figure with the preset's law.
    pub(super) law: (&'static str, &'static str),
    /// Title and header of the sensitivity table (the sequence and, where asked, the chaotic
    /// range follow the case's cells).
    pub(super) sensitivity: (&'static str, &'static [&'static str]),
    /// Section title and seed reference.
    pub(super) title: (&'static str, &'static str),
}

/// A parameter sweep declared as data.
pub(super) struct SweepTable {
    /// Study id.
    pub(super) id: &'static str,
    /// The parameter swept.
    pub(super) param: &'static str,
    /// Fixed settings of the main, multi-initial and law sweeps.
    pub(super) set: &'static [(&'static str, f64)],
    /// Range of the main and law sweeps.
    pub(super) range: (f64, f64),
    /// Values of the main sweep (quick, full).
    pub(super) n: (usize, usize),
    /// Values of the law sweep (quick, full).
    pub(super) n_law: (usize, usize),
    /// Range, values (quick, full) and initial states (quick, full) of the multi-initial sweep.
    pub(super) multi: ((f64, f64), (usize, usize), (usize, usize)),
    /// Half backlash of the multi-initial sweep's box of initial states (None: the scenario's
    /// `D_s`).
    pub(super) multi_d: Option<f64>,
    /// Values of each sensitivity sweep (quick, full).
    pub(super) n_sensitivity: (usize, usize),
    /// The sensitivity cases, from the linear-law scenario.
    pub(super) cases: fn(&Scenario) -> Result<Vec<Case>>,
    /// Whether the sensitivity table gives the chaotic range of each case.
    pub(super) chaotic_column: bool,
    /// Texts of the figures and tables.
    pub(super) texts: Texts,
    /// Parameters and method of the section, from the data.
    pub(super) words: fn(&SweepData) -> (String, String),
    /// The claims checked on the data.
    pub(super) claims: fn(&Runs) -> Vec<Claim>,
}

/// One sweep of the sensitivity table.
#[derive(Serialize, Deserialize)]
pub(super) struct SensitivityRun {
    /// The first cells of its row.
    cells: Vec<String>,
    /// The runs from (0, 0).
    runs: Vec<TaskResult>,
}

/// What a parameter sweep computed.
#[derive(Serialize, Deserialize)]
pub(super) struct SweepData {
    /// Values of the main sweep.
    pub(super) n: usize,
    /// Its integration settings.
    pub(super) sim: SimOptions,
    /// Its backlash levels (D_d, D_s).
    pub(super) levels: (f64, f64),
    /// The main sweep from (0, 0) (linear law, five sections, TLE).
    main: Vec<TaskResult>,
    /// The multi-initial sweep.
    multi: Vec<TaskResult>,
    /// The sweep with the preset's contact law.
    law: Vec<TaskResult>,
    /// The sweeps of the sensitivity table.
    sensitivity: Vec<SensitivityRun>,
}

/// The runs the claims read.
pub(super) struct Runs<'a> {
    /// The main sweep.
    pub(super) main: &'a [TaskResult],
    /// Its points.
    pub(super) pts: Vec<Pt>,
    /// The points of the multi-initial sweep.
    pub(super) multi: Vec<Pt>,
}

/// A parameter sweep of the linear-law scenario `lin`, the preset's law `preset_law` beside.
pub(super) struct ParamSweep<'a> {
    /// The sweep.
    pub(super) table: &'static SweepTable,
    /// The scenario with the linear contact law.
    pub(super) lin: &'a Scenario,
    /// The scenario with the preset's contact law.
    pub(super) preset_law: &'a Scenario,
    /// The request besides the context (the cache key).
    pub(super) request: serde_json::Value,
}

impl Study for ParamSweep<'_> {
    type Data = SweepData;

    fn id(&self) -> &'static str {
        self.table.id
    }

    fn request(&self) -> serde_json::Value {
        self.request.clone()
    }

    fn compute(&self, ctx: &Ctx, dir: &Path) -> Result<SweepData> {
        let (tb, p) = (self.table, self.table.param);
        let n = ctx.n(tb.n.0, tb.n.1);
        let sim = ctx.sim((150, 300), (40, 100));
        let values = |k: (usize, usize)| linspace(tb.range.0, tb.range.1, ctx.n(k.0, k.1));
        let b = self.lin.with_all(tb.set)?;
        let main = ctx.sweep(
            dir,
            &format!("{p} sweep (linear law)"),
            &b,
            &fixed(p, values(tb.n), sim, FIVE.to_vec(), true),
        )?;
        let ((lo, hi), nm, ics) = tb.multi;
        let multi = ctx.sweep(
            dir,
            &format!("{p} multi-initial"),
            &b,
            &multi(
                p,
                linspace(lo, hi, ctx.n(nm.0, nm.1)),
                ctx.sim((150, 300), (30, 60)),
                ctx.n(ics.0, ics.1),
                tb.multi_d.unwrap_or(b.params().d_single),
            ),
        )?;
        let strobe = |k| fixed(p, values(k), sim, vec![Sec::Strobe], false);
        let law = ctx.sweep(
            dir,
            &format!("{p} sweep (LN law)"),
            &self.preset_law.with_all(tb.set)?,
            &strobe(tb.n_law),
        )?;
        let mut sensitivity = Vec::new();
        for case in (tb.cases)(self.lin)? {
            let runs = ctx.sweep(dir, &case.name, &case.scenario, &strobe(tb.n_sensitivity))?;
            sensitivity.push(SensitivityRun {
                cells: case.cells,
                runs,
            });
        }
        Ok(SweepData {
            n,
            sim,
            levels: (b.params().d_double, b.params().d_single),
            main,
            multi,
            law,
            sensitivity,
        })
    }

    fn render(&self, ctx: &Ctx, dir: &Path, data: &SweepData) -> Result<Section> {
        let (tb, p, tx) = (self.table, self.table.param, &self.table.texts);
        let figure = |stem: &str, runs: &[TaskResult], secs: &[Sec], texts: (&str, &str)| {
            let panels = SweepPanels {
                tle: secs.len() > 1,
                p_id: secs.len() > 1,
                ..Default::default()
            };
            sweep_figure(ctx, dir, stem, p, runs, secs, &panels, texts.0, texts.1)
        };
        let fig = figure(&format!("bif_{p}"), &data.main, &FIVE, tx.main)?;
        let pts = classes::fixed_points(&data.main);
        let file = format!("intervals_{p}.csv");
        let table = interval_table(ctx, dir, &file, tx.intervals, p, &pts)?;
        let fig_m = figure(&format!("multi_{p}"), &data.multi, &[Sec::Strobe], tx.multi)?;
        let sens_rows: Vec<Vec<String>> = data
            .sensitivity
            .iter()
            .map(|run| {
                let ps = classes::fixed_points(&run.runs);
                let mut row = run.cells.clone();
                row.push(sequence(&classes::intervals(&tolerant(&ps)), 2));
                if tb.chaotic_column {
                    row.push(ranges_text(&chaos_ranges(&ps)));
                }
                row
            })
            .collect();
        let sens = ctx.table(
            &dir.join("sensitivity.csv"),
            tx.sensitivity.0,
            &hdr(tx.sensitivity.1),
            sens_rows,
        )?;
        let stem = format!("bif_{p}_johnson");
        let fig_l = figure(&stem, &data.law, &[Sec::Strobe], tx.law)?;
        let pl = classes::fixed_points(&data.law);
        let seq = sequence(&classes::intervals(&tolerant(&pts)), 2);
        let table_cmp = ctx.table(
            &dir.join("law_comparison.csv"),
            &format!("Linear law (seed) and Johnson-type law (preset) over {p}"),
            &hdr(&["contact law", "sequence", &format!("chaotic {p}")]),
            vec![
                vec![
                    "linear".into(),
                    seq.clone(),
                    ranges_text(&chaos_ranges(&pts)),
                ],
                vec![
                    "Johnson-type (Lankarani–Nikravesh)".into(),
                    sequence(&classes::intervals(&tolerant(&pl)), 2),
                    ranges_text(&chaos_ranges(&pl)),
                ],
            ],
        )?;
        let (parameters, method) = (tb.words)(data);
        Ok(Section {
            id: tb.id.into(),
            title: tx.title.0.into(),
            seed_ref: tx.title.1.into(),
            parameters,
            method,
            figures: vec![fig, fig_m, fig_l],
            readings: vec![format!("Sequence (runs of ≥ 2 values): {seq}.")],
            tables: vec![table, sens, table_cmp],
            claims: vec![],
            alternatives: vec![],
            seconds: 0.0,
        })
    }

    fn claims(&self, data: &SweepData) -> Vec<Claim> {
        let runs = Runs {
            main: &data.main,
            pts: classes::fixed_points(&data.main),
            multi: classes::points(&data.multi, 0),
        };
        let mut claims = (self.table.claims)(&runs);
        crate::readings::note_transients(&mut claims, &runs.pts, self.table.param, "periods");
        claims
    }
}
