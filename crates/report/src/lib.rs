//! `geardyn report`: runs the study plan of a preset (seed A `breakage`, seed B `internal`, or
//! case C1 `classic`) and writes `DIR/<preset>/index.html` — a self-contained page (figures
//! beside it as PNG and SVG, the data of every figure as CSV next to it, no scripts, no external
//! fonts) — plus `claims.csv`, the seeds' statements checked one by one against the data.
//!
//! Every section states its parameters (the seed's own where the seed gives them; where the seed
//! is silent the choice is said on the page) and its method, and gives short readings generated
//! from the data. Verdicts use the decided classification of every run
//! ([`geardyn_analysis::classify::Motion`]) through `classes`, which tolerates an isolated
//! value at a bifurcation point.
//!
//! Every study implements [`runner::Study`]: `compute` (its sweeps, continuations and runs, from
//! its request and the context) and `render` (its files, figures, readings and claims); a plan
//! is the list of its studies. A study's data is cached in `DIR/.cache/<preset>/<study>.data.json`
//! (beside the page folders, outside their size budget),
//! keyed by its id, its request, the configuration and mode, and a digest of the library crates
//! it computes through (made by `build.rs`; not the report, not the plots), and rendered on every
//! run: a change of the report shows without recomputing, a change of an integrator or a rule of
//! the analyses recomputes. Where the libraries give no `Deserialize` for a study's results
//! (continuations, basins, recorded runs, signals) its rendered section is cached instead
//! (`section.json`, keyed by the report's source too, reused only while its files are intact);
//! sweeps inside a study are checkpointed while it runs (the checkpoint is removed when the
//! study is complete), so an interrupted report resumes.
//!
//! The report folder has a size budget ([`SIZE_BUDGET_BYTES`], [`SIZE_BUDGET_QUICK_BYTES`]):
//! scatter plots are merged per pixel, section points are capped per run, and numbers in CSV
//! files carry six significant digits.
#![warn(missing_docs)]

mod breakage;
mod claims;
mod classes;
mod classic;
mod coexisting;
mod deep_escape;
mod html;
mod internal;
mod interpretations;
mod maps;
mod orbit_figures;
mod readings;
mod runner;
mod shared;
mod sweep_figures;

pub use claims::{Claim, Verdict, EVIDENCE_MAX};

use anyhow::{Context, Result};
use geardyn_io::Config;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Largest size of one preset's full report folder (bytes): 20 MB (measured: breakage 7 MB,
/// internal 14 MB).
pub const SIZE_BUDGET_BYTES: u64 = 20_000_000;
/// Largest size of one preset's quick report folder (bytes): 8 MB (measured: about 5 MB).
pub const SIZE_BUDGET_QUICK_BYTES: u64 = 8_000_000;

/// A figure: PNG and SVG beside the page, and the CSV files of its data.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Figure {
    /// PNG path relative to the page.
    pub png: String,
    /// SVG path relative to the page.
    pub svg: String,
    /// Caption.
    pub caption: String,
    /// CSV files with the data drawn (relative to the page).
    pub data: Vec<String>,
}

/// A table shown on the page and written as CSV.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Table {
    /// Title.
    pub title: String,
    /// CSV path relative to the page.
    pub csv: String,
    /// Header.
    pub header: Vec<String>,
    /// Rows.
    pub rows: Vec<Vec<String>>,
}

/// One section of the report.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Section {
    /// Anchor id.
    pub id: String,
    /// Title.
    pub title: String,
    /// Which seed figure or table this reproduces (empty: none).
    pub seed_ref: String,
    /// Parameters, in words.
    pub parameters: String,
    /// What was computed and how.
    pub method: String,
    /// Figures.
    pub figures: Vec<Figure>,
    /// Short readings generated from the data.
    pub readings: Vec<String>,
    /// Tables.
    pub tables: Vec<Table>,
    /// Claims checked in this section, under the headline reading of the seed text.
    pub claims: Vec<Claim>,
    /// The same or related claims under the other readings the text allows
    /// (`interpretations`): `claims_by_interpretation.csv` and the matrix on the page.
    #[serde(default)]
    pub alternatives: Vec<Claim>,
    /// Wall time of the study (s).
    pub seconds: f64,
}

/// Settings of a report.
#[derive(Clone, Debug)]
pub struct ReportOptions {
    /// Preset name.
    pub preset: String,
    /// Coarse version of every figure (seconds, for CI and previews).
    pub quick: bool,
    /// Output directory.
    pub out: PathBuf,
    /// Whether the caller gave the decision horizon and the work budget (`--decision-periods`,
    /// `--decision-budget` or their `--set`): a quick report keeps them instead of its own
    /// ([`runner::decision_of`]).
    pub decision_given: (bool, bool),
}

/// The size budget of a report folder.
pub fn size_budget(quick: bool) -> u64 {
    if quick {
        SIZE_BUDGET_QUICK_BYTES
    } else {
        SIZE_BUDGET_BYTES
    }
}

/// Total size of the files under `dir` (bytes).
pub fn folder_size(dir: &Path) -> u64 {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return 0;
    };
    rd.filter_map(|e| e.ok())
        .map(|e| {
            let p = e.path();
            if p.is_dir() {
                folder_size(&p)
            } else {
                e.metadata().map_or(0, |m| m.len())
            }
        })
        .sum()
}

/// The `kind` of a report root's `run.json` (the root holds one folder per preset).
pub const REPORTS_KIND: &str = "reports";

/// Runs the study plan and writes the page into `OUT/<preset>/` (reports of different presets
/// never share files), then `OUT/index.html` linking every preset's page present; returns the
/// path of the preset's `index.html`.
pub fn run(cfg: &Config, opts: &ReportOptions) -> Result<PathBuf> {
    let root = &opts.out;
    let dir = root.join(&opts.preset);
    // the root holds the presets' folders and the index: geardyn's, or new, or empty (a root of
    // an earlier version is recognised by its index)
    let old_index = std::fs::read_to_string(root.join("index.html"))
        .is_ok_and(|t| t.contains("<title>geardyn reports</title>"));
    if old_index {
        std::fs::create_dir_all(root)?;
        geardyn_io::output::write_text(
            &root.join(geardyn_io::run_record::MARKER),
            "geardyn output folder\n",
        )?;
    }
    geardyn_io::run_record::claim_folder(root)?;
    // the root is a folder of reports: another command's folder is refused, and the root says
    // what it is, so that no other command writes into it
    let root_record = root.join("run.json");
    match std::fs::read_to_string(&root_record)
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .and_then(|v| v.get("kind").and_then(|k| k.as_str()).map(String::from))
    {
        Some(kind) if kind != REPORTS_KIND => {
            return Err(geardyn_io::run_record::FolderError::OtherCommand {
                path: root.display().to_string(),
                other: kind,
            }
            .into())
        }
        Some(_) => {}
        None => geardyn_io::output::write_json(
            &root_record,
            &serde_json::json!({
                "kind": REPORTS_KIND,
                "version": env!("CARGO_PKG_VERSION"),
                "note": "a folder of geardyn reports: one sub-folder per preset",
            }),
        )?,
    }
    let _lock = geardyn_io::run_record::prepare_folder(&dir, "report", None, false)?;
    let scenario = cfg.resolve()?;
    let t = std::time::Instant::now();
    let started = geardyn_io::run_record::now_unix_s();
    let ctx = runner::Ctx {
        cfg: cfg.clone(),
        scenario: scenario.clone(),
        quick: opts.quick,
        dir: dir.clone(),
        integration: cfg.sim_options()?,
        decision_given: opts.decision_given,
    };
    // the configuration the runs used: with the horizon and budget the plan decided at (a quick
    // report's own where none was given), so config.toml and run.json state what ran
    let mut ran = cfg.clone();
    (
        ran.simulation.decision_periods,
        ran.simulation.decision_budget,
    ) = ctx.decision();
    let cfg = &ran;
    let sections = match opts.preset.as_str() {
        "breakage" => breakage::plan(&ctx)?,
        "internal" => internal::plan(&ctx)?,
        "classic" => classic::plan(&ctx)?,
        other => {
            anyhow::bail!("no study plan for preset '{other}': allowed breakage, internal, classic")
        }
    };
    geardyn_io::output::write_text(&dir.join("config.toml"), &cfg.to_toml())?;
    let claims: Vec<&Claim> = sections.iter().flat_map(|s| s.claims.iter()).collect();
    claims::write_csv(&dir.join("claims.csv"), &claims)?;
    let mut every: Vec<&Claim> = claims.clone();
    every.extend(sections.iter().flat_map(|s| s.alternatives.iter()));
    claims::write_csv(&dir.join("claims_by_interpretation.csv"), &every)?;
    geardyn_io::run_record::write_run_record(
        &dir,
        "report",
        cfg,
        &scenario,
        started,
        geardyn_io::run_record::now_unix_s() - started,
    )?;
    // the page states the folder's size against the budget: measured before the page itself
    // is written, plus an allowance for it
    let page_of = |size: u64| {
        html::page(&html::PageInfo {
            preset: &opts.preset,
            cfg,
            scenario: &scenario,
            sections: &sections,
            quick: opts.quick,
            horizon: ctx.decision().0,
            seconds: t.elapsed().as_secs_f64(),
            size,
            budget: size_budget(opts.quick),
        })
    };
    let index = dir.join("index.html");
    let _ = std::fs::remove_file(&index);
    let before = folder_size(&dir);
    let draft = page_of(before);
    let page = page_of(before + draft.len() as u64);
    geardyn_io::output::write_text(&index, &page)?;
    write_root_index(root)?;
    Ok(index)
}

/// `OUT/index.html`: links to the page of every preset reported in `OUT`.
fn write_root_index(root: &Path) -> Result<()> {
    let mut presets: Vec<String> = std::fs::read_dir(root)
        .with_context(|| format!("cannot read {}", root.display()))?
        .filter_map(|e| e.ok())
        .filter(|e| e.path().join("index.html").is_file())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    presets.sort();
    let s = html::root_page(&presets);
    geardyn_io::output::write_text(&root.join("index.html"), &s)?;
    Ok(())
}

/// Relative path of a file in the report directory.
pub(crate) fn rel(dir: &Path, p: &Path) -> String {
    p.strip_prefix(dir)
        .unwrap_or(p)
        .to_string_lossy()
        .replace('\\', "/")
}
