//! The HTML page: one self-contained file, figures and data beside it, no scripts, no external
//! fonts. The pages are minijinja templates (`templates/`); this module gives them their values.

use crate::claims::{tally, Claim, Verdict};
use crate::readings::f;
use crate::Section;
use geardyn_io::Config;
use minijinja::{context, AutoEscape, Environment, UndefinedBehavior};
use serde::Serialize;

pub(crate) fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

const STYLE: &str = "body{font-family:sans-serif;max-width:1200px;margin:2em auto;padding:0 1em;color:#222;line-height:1.45}\
h1{font-size:1.6em}h2{border-bottom:1px solid #ccc;padding-bottom:.2em;margin-top:2em}\
figure{margin:1em 0}figure img{max-width:100%;border:1px solid #ddd}figcaption{font-size:.9em;color:#444}\
table{border-collapse:collapse;font-size:.85em;margin:.8em 0;display:block;max-width:100%;overflow-x:auto}td,th{border:1px solid #ccc;padding:.25em .5em;text-align:left;vertical-align:top}\
th{background:#f3f3f3}.meta{font-size:.9em;color:#333;background:#f8f8f8;padding:.6em .8em;border-left:3px solid #0072b2}\
.reproduced{color:#006d4f;font-weight:bold}.partly{color:#8a6d00;font-weight:bold}.not-reproduced{color:#b00;font-weight:bold}\
.seed-inconsistent{color:#6a3d9a;font-weight:bold}.small{font-size:.85em;color:#555}nav li{margin:.15em 0}";

/// Rows of a table shown on the page; longer tables are cut (the CSV has all).
const MAX_ROWS: usize = 40;

/// The templates, with their whitespace rules (a line holding only a block tag gives nothing)
/// and no automatic escaping: the templates escape text with the `esc` filter, as the page
/// always has (`&`, `<`, `>`, `"`).
fn templates() -> Environment<'static> {
    let mut env = Environment::new();
    env.set_trim_blocks(true);
    env.set_lstrip_blocks(true);
    env.set_keep_trailing_newline(true);
    env.set_auto_escape_callback(|_| AutoEscape::None);
    env.set_undefined_behavior(UndefinedBehavior::Strict);
    env.add_filter("esc", |s: &str| esc(s));
    env.add_filter("basename", |s: &str| {
        s.rsplit('/').next().unwrap_or(s).to_string()
    });
    for (name, source) in [
        ("page.html", include_str!("../templates/page.html")),
        ("root.html", include_str!("../templates/root.html")),
    ] {
        env.add_template(name, source)
            .expect("the report's templates parse");
    }
    env
}

/// Renders the template `name` (its values checked by the tests: an error is a bug).
fn render(name: &str, values: minijinja::Value) -> String {
    templates()
        .get_template(name)
        .and_then(|t| t.render(values))
        .unwrap_or_else(|e| panic!("template {name}: {e:#}"))
}

/// The class of a verdict on the page (`not-reproduced`).
fn class(v: Verdict) -> String {
    v.word().replace(' ', "-")
}

/// A claim as a row of a claims table.
#[derive(Serialize)]
struct ClaimRow<'a> {
    claim: &'a str,
    source: &'a str,
    seed: &'a str,
    measured: &'a str,
    class: String,
    word: &'static str,
    evidence: &'a str,
    interpretation: &'a str,
}

impl<'a> ClaimRow<'a> {
    fn of(c: &'a Claim) -> Self {
        ClaimRow {
            claim: &c.claim,
            source: &c.source,
            seed: &c.seed_value,
            measured: &c.measured_value,
            class: class(c.verdict),
            word: c.verdict.word(),
            evidence: &c.evidence,
            interpretation: &c.interpretation,
        }
    }
}

/// Whether a claims table has the column of the reading of the text (some claim has one).
fn readings_column<'a>(claims: impl IntoIterator<Item = &'a Claim>) -> bool {
    claims.into_iter().any(|c| !c.interpretation.is_empty())
}

/// One cell of the readings matrix: a claim's verdict and measured value under one reading.
#[derive(Serialize)]
struct Cell<'a> {
    class: String,
    word: &'static str,
    measured: &'a str,
}

/// One row of the readings matrix: a claim's text, its seed value and a cell per reading
/// (none where the claim was not judged under it).
#[derive(Serialize)]
struct MatrixRow<'a> {
    text: &'a str,
    seed: &'a str,
    cells: Vec<Option<Cell<'a>>>,
}

/// The claims that have alternatives, one column per reading of the text (the column says its
/// reading: numbers would not match the study files' numbering).
#[derive(Serialize)]
struct Matrix<'a> {
    readings: Vec<&'a str>,
    rows: Vec<MatrixRow<'a>>,
}

/// The readings matrix: the verdict and the measured value in each cell
/// (`claims_by_interpretation.csv` holds the evidence).
fn readings_matrix<'a>(headline: &[&'a Claim], alternatives: &[&'a Claim]) -> Matrix<'a> {
    let mut texts: Vec<&str> = Vec::new();
    for c in alternatives {
        if !texts.contains(&c.claim.as_str()) {
            texts.push(&c.claim);
        }
    }
    let rows: Vec<&Claim> = headline
        .iter()
        .chain(alternatives)
        .filter(|c| texts.contains(&c.claim.as_str()))
        .copied()
        .collect();
    let mut readings: Vec<&str> = Vec::new();
    for c in &rows {
        if !readings.contains(&c.interpretation.as_str()) {
            readings.push(&c.interpretation);
        }
    }
    let rows = texts
        .iter()
        .map(|t| MatrixRow {
            text: t,
            seed: rows
                .iter()
                .find(|c| c.claim == *t)
                .map_or("", |c| c.seed_value.as_str()),
            cells: readings
                .iter()
                .map(|r| {
                    rows.iter()
                        .find(|c| c.claim == *t && c.interpretation == *r)
                        .map(|c| Cell {
                            class: class(c.verdict),
                            word: c.verdict.word(),
                            measured: &c.measured_value,
                        })
                })
                .collect(),
        })
        .collect();
    Matrix { readings, rows }
}

/// A section as the page shows it.
#[derive(Serialize)]
struct SectionView<'a> {
    #[serde(flatten)]
    sec: &'a Section,
    /// Its wall time, one decimal.
    time: String,
    /// Its claims as table rows.
    claim_rows: Vec<ClaimRow<'a>>,
    readings_column: bool,
}

/// What the page shows.
pub struct PageInfo<'a> {
    /// Preset name.
    pub preset: &'a str,
    /// Its configuration.
    pub cfg: &'a Config,
    /// Its scenario.
    pub scenario: &'a geardyn_scenario::Scenario,
    /// Sections.
    pub sections: &'a [Section],
    /// Quick mode.
    pub quick: bool,
    /// The decision horizon the runs were decided at (excitation periods).
    pub horizon: u64,
    /// Wall time (s).
    pub seconds: f64,
    /// Size of the folder (bytes).
    pub size: u64,
    /// Its budget (bytes).
    pub budget: u64,
}

fn intro(preset: &str) -> &'static str {
    match preset {
        "breakage" => "Seed A: an external 40/40 spur pair, module 3 mm, with one chipped pinion tooth, friction and back-side impacts with restitution (files 000, 001, 002 of the seeds). Every figure and table of seed A that the model computes is recomputed below at the seed's parameters; where the seed does not give a parameter, the choice is stated in the section and its sensitivity is shown.",
        "internal" => "Seed B: an internal 30/70 spur pair with time-varying backlash (D_s > D_d), multi-state lubrication friction and continuous back-side contact (files 003, 004 of the seeds). The seed's bifurcation, Lyapunov, map and basin studies use the piecewise-linear mesh force k f(x, D) + c x'; they are computed here with the linear contact law, and the preset's Johnson-type (Lankarani–Nikravesh) law is shown beside them as a comparison.",
        _ => "Benchmark case C1 of docs/model.md: a single-degree-of-freedom gear model with harmonic stiffness and linear contact on both sides.",
    }
}

/// Renders the page.
pub fn page(info: &PageInfo) -> String {
    let p = info.scenario.params();
    let claims: Vec<&Claim> = info.sections.iter().flat_map(|x| x.claims.iter()).collect();
    let alternatives: Vec<&Claim> = info
        .sections
        .iter()
        .flat_map(|x| x.alternatives.iter())
        .collect();
    let tally = Verdict::ALL
        .iter()
        .zip(tally(&claims))
        .map(|(v, k)| format!("{k} {}", v.word()))
        .collect::<Vec<_>>()
        .join(", ");
    let sections: Vec<SectionView> = info
        .sections
        .iter()
        .map(|sec| SectionView {
            sec,
            time: format!("{:.1}", sec.seconds),
            claim_rows: sec.claims.iter().map(ClaimRow::of).collect(),
            readings_column: readings_column(&sec.claims),
        })
        .collect();
    let values = context! {
        preset => info.preset,
        style => STYLE,
        intro => intro(info.preset),
        quick => info.quick,
        p => context! {
            omega => f(p.omega),
            load => f(p.load),
            xi => f(p.xi),
            c => f(p.c),
            d_double => f(p.d_double),
            d_single => f(p.d_single),
        },
        pair => info.cfg.pair.is_some(),
        version => env!("CARGO_PKG_VERSION"),
        seconds => format!("{:.0}", info.seconds),
        horizon => info.horizon,
        default_horizon => geardyn_analysis::classify::DECISION_PERIODS,
        size => format!("{:.1}", info.size as f64 / 1e6),
        budget => format!("{:.0}", info.budget as f64 / 1e6),
        claims => claims.iter().map(|c| ClaimRow::of(c)).collect::<Vec<_>>(),
        claims_readings => readings_column(claims.iter().copied()),
        tally,
        matrix => (!alternatives.is_empty()).then(|| readings_matrix(&claims, &alternatives)),
        sections,
        max_rows => MAX_ROWS,
    };
    render("page.html", values)
}

/// `OUT/index.html`: links to the pages of the presets `presets`.
pub(crate) fn root_page(presets: &[String]) -> String {
    render("root.html", context! { presets })
}
