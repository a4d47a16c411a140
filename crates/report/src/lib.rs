//! `geardyn report`: runs the study plan of a preset (seed A `breakage`, seed B `internal`, or
//! case C1 `classic`) and writes `DIR/index.html` — a self-contained page (figures beside it as
//! PNG and SVG, no scripts, no external fonts) — plus every table as CSV.
//!
//! Every section states its parameters and method and gives readings generated from the data.
//! The seeds' qualitative claims are checked against the measurements in a claims table.
//! Studies are cached in `DIR/<study>/section.json` (keyed by the full settings) and sweeps
//! inside them are checkpointed, so an interrupted report resumes.
#![warn(missing_docs)]

mod html;
mod readings;
mod studies;

use anyhow::{Context, Result};
use geardyn_io::Config;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// A figure: PNG and SVG beside the page.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Figure {
    /// PNG path relative to the page.
    pub png: String,
    /// SVG path relative to the page.
    pub svg: String,
    /// Caption.
    pub caption: String,
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

/// A claim of the seeds checked against the data.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Claim {
    /// The claim.
    pub claim: String,
    /// Where it comes from.
    pub source: String,
    /// What was measured.
    pub evidence: String,
    /// `reproduced`, `not reproduced` or `inconclusive`.
    pub verdict: String,
}

/// One section of the report.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Section {
    /// Anchor id.
    pub id: String,
    /// Title.
    pub title: String,
    /// Parameters, in words.
    pub parameters: String,
    /// What was computed and how.
    pub method: String,
    /// Figures.
    pub figures: Vec<Figure>,
    /// Readings generated from the data.
    pub readings: Vec<String>,
    /// Tables.
    pub tables: Vec<Table>,
    /// Claims checked in this section.
    pub claims: Vec<Claim>,
    /// Wall time of the study (s).
    pub seconds: f64,
}

/// Settings of a report.
#[derive(Clone, Debug)]
pub struct ReportOptions {
    /// Preset name.
    pub preset: String,
    /// Coarse version of every figure (under two minutes).
    pub quick: bool,
    /// Output directory.
    pub out: PathBuf,
}

/// Runs the study plan and writes the page into `OUT/<preset>/` (reports of different presets
/// never share files), then `OUT/index.html` linking every preset's page present; returns the
/// path of the preset's `index.html`.
pub fn run(cfg: &Config, opts: &ReportOptions) -> Result<PathBuf> {
    let root = &opts.out;
    let dir = root.join(&opts.preset);
    std::fs::create_dir_all(&dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let scenario = cfg.resolve()?;
    let t = std::time::Instant::now();
    let started = geardyn_io::run_record::now_unix_s();
    let ctx = studies::Ctx {
        cfg: cfg.clone(),
        scenario: scenario.clone(),
        quick: opts.quick,
        dir: dir.clone(),
    };
    let sections = match opts.preset.as_str() {
        "breakage" => studies::breakage_plan(&ctx)?,
        "internal" => studies::internal_plan(&ctx)?,
        "classic" => studies::classic_plan(&ctx)?,
        other => {
            anyhow::bail!("no study plan for preset '{other}': allowed breakage, internal, classic")
        }
    };
    let opts = &ReportOptions {
        out: dir.clone(),
        ..opts.clone()
    };
    geardyn_io::output::write_text(&opts.out.join("config.toml"), &cfg.to_toml())?;
    let page = html::page(
        &opts.preset,
        cfg,
        &scenario,
        &sections,
        opts.quick,
        t.elapsed().as_secs_f64(),
    );
    let index = opts.out.join("index.html");
    geardyn_io::output::write_text(&index, &page)?;
    // every claim in one CSV as well
    let claims: Vec<&Claim> = sections.iter().flat_map(|s| s.claims.iter()).collect();
    geardyn_io::output::write_csv(
        &opts.out.join("claims.csv"),
        &["claim", "source", "evidence", "verdict"],
        claims.iter().map(|c| {
            vec![
                c.claim.clone(),
                c.source.clone(),
                c.evidence.clone(),
                c.verdict.clone(),
            ]
        }),
    )?;
    geardyn_io::run_record::write_run_record(
        &opts.out,
        "report",
        cfg,
        &scenario,
        started,
        geardyn_io::run_record::now_unix_s() - started,
    )?;
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
    let mut s = String::from(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>geardyn reports</title></head><body>\n<h1>geardyn reports</h1>\n<ul>\n",
    );
    for p in &presets {
        let p = html::esc(p);
        s.push_str(&format!(
            "<li><a href=\"{p}/index.html\">preset <code>{p}</code></a></li>\n"
        ));
    }
    s.push_str("</ul>\n</body></html>\n");
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
