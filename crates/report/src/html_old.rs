#![allow(dead_code, missing_docs)]
//! (temporary) The HTML page: one self-contained file, figures and data beside it, no scripts, no external
//! fonts.

use crate::claims::{tally, Claim, Verdict};
use crate::readings::f;

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

fn claims_table(claims: &[&Claim]) -> String {
    // the reading of the seed text each claim uses, when the plan has readings
    let readings = claims.iter().any(|c| !c.interpretation.is_empty());
    let mut s = String::from(
        "<table id=\"claims-table\"><tr><th>claim</th><th>source</th><th>seed</th><th>measured</th><th>verdict</th><th>evidence</th>",
    );
    if readings {
        s.push_str("<th>reading of the text</th>");
    }
    s.push_str("</tr>\n");
    for c in claims {
        s.push_str(&format!(
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td class=\"{}\">{}</td><td>{}</td>",
            esc(&c.claim),
            esc(&c.source),
            esc(&c.seed_value),
            esc(&c.measured_value),
            c.verdict.word().replace(' ', "-"),
            esc(c.verdict.word()),
            esc(&c.evidence)
        ));
        if readings {
            s.push_str(&format!(
                "<td class=\"small\">{}</td>",
                esc(&c.interpretation)
            ));
        }
        s.push_str("</tr>\n");
    }
    s.push_str("</table>\n");
    s
}

/// The claims that have alternatives, one column per reading of the text: the verdict and the
/// measured value in each cell (`claims_by_interpretation.csv` holds the evidence).
fn readings_matrix(headline: &[&Claim], alternatives: &[&Claim]) -> String {
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
    let mut s = String::from(
        "<h2 id=\"claims-by-reading\">The same claims under every reading of the text</h2>\n<p class=\"small\">Where the seed text leaves a reading open (section on readings), the claims that depend on it are judged under each reading. The headline table above uses the reading the text states most directly; the columns here are all readings run, listed below (every row is in <a href=\"claims_by_interpretation.csv\">claims_by_interpretation.csv</a> with its evidence).</p>\n<ol class=\"small\">\n",
    );
    for r in &readings {
        s.push_str(&format!("<li>{}</li>\n", esc(r)));
    }
    s.push_str("</ol>\n<table><tr><th>claim</th><th>seed</th>");
    // the column says its reading (numbers would not match the study files' numbering)
    for r in &readings {
        s.push_str(&format!("<th class=\"small\">{}</th>", esc(r)));
    }
    s.push_str("</tr>\n");
    for t in &texts {
        let first = rows.iter().find(|c| c.claim == *t);
        s.push_str(&format!(
            "<tr><td>{}</td><td>{}</td>",
            esc(t),
            esc(first.map_or("", |c| c.seed_value.as_str()))
        ));
        for r in &readings {
            match rows
                .iter()
                .find(|c| c.claim == *t && c.interpretation == *r)
            {
                Some(c) => s.push_str(&format!(
                    "<td><span class=\"{}\">{}</span><br><span class=\"small\">{}</span></td>",
                    c.verdict.word().replace(' ', "-"),
                    esc(c.verdict.word()),
                    esc(&c.measured_value)
                )),
                None => s.push_str("<td>–</td>"),
            }
        }
        s.push_str("</tr>\n");
    }
    s.push_str("</table>\n");
    s
}

use crate::html::PageInfo;

fn intro(preset: &str) -> &'static str {
    match preset {
        "breakage" => "Seed A: an external 40/40 spur pair, module 3 mm, with one chipped pinion tooth, friction and back-side impacts with restitution (files 000, 001, 002 of the seeds). Every figure and table of seed A that the model computes is recomputed below at the seed's parameters; where the seed does not give a parameter, the choice is stated in the section and its sensitivity is shown.",
        "internal" => "Seed B: an internal 30/70 spur pair with time-varying backlash (D_s > D_d), multi-state lubrication friction and continuous back-side contact (files 003, 004 of the seeds). The seed's bifurcation, Lyapunov, map and basin studies use the piecewise-linear mesh force k f(x, D) + c x'; they are computed here with the linear contact law, and the preset's Johnson-type (Lankarani–Nikravesh) law is shown beside them as a comparison.",
        _ => "Benchmark case C1 of docs/model.md: a single-degree-of-freedom gear model with harmonic stiffness and linear contact on both sides.",
    }
}

/// Renders the page.
pub fn page(info: &PageInfo) -> String {
    let mut s = String::new();
    s.push_str("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n");
    s.push_str(&format!(
        "<title>geardyn report: {}</title>\n<style>{STYLE}</style></head><body>\n",
        esc(info.preset)
    ));
    s.push_str(&format!(
        "<h1>geardyn report — preset <code>{}</code>{}</h1>\n<p>{}</p>\n",
        esc(info.preset),
        if info.quick { " (quick)" } else { "" },
        esc(intro(info.preset))
    ));
    let p = info.scenario.params();
    s.push_str(&format!(
        "<p class=\"meta\">Preset operating point (dimensionless, docs/model.md): omega = {}, F = {}, xi = {}, c = {}, D_d = {}, D_s = {}; {}. \
         Studies set their own parameters from this scenario and say so. Generated by geardyn {} in {:.0} s{}. \
         The resolved configuration is <a href=\"config.toml\">config.toml</a>; every claim is in <a href=\"claims.csv\">claims.csv</a>; \
         the data of every figure are in the CSV files linked under it. This folder: {:.1} MB (budget {:.0} MB).</p>\n",
        f(p.omega),
        f(p.load),
        f(p.xi),
        f(p.c),
        f(p.d_double),
        f(p.d_single),
        if info.cfg.pair.is_some() { "stiffness, zones, backlash and friction from the physical [pair]" } else { "dimensionless stiffness form" },
        env!("CARGO_PKG_VERSION"),
        info.seconds,
        {
            let horizon = info.horizon;
            let default = geardyn_analysis::classify::DECISION_PERIODS;
            if info.quick {
                format!(
                    " with coarse grids (--quick: chaos is decided at a horizon of {horizon} excitation periods instead of {default}, so the verdicts are indicative only)"
                )
            } else if horizon != default {
                format!(
                    " (chaos decided at a horizon of {horizon} excitation periods instead of the default {default})"
                )
            } else {
                String::new()
            }
        },
        info.size as f64 / 1e6,
        info.budget as f64 / 1e6,
    ));
    s.push_str("<nav><h2>Contents</h2><ol>\n<li><a href=\"#claims\">Claims of the seeds, checked by the data</a></li>\n");
    if info.sections.iter().any(|x| !x.alternatives.is_empty()) {
        s.push_str("<li><a href=\"#claims-by-reading\">The same claims under every reading of the text</a></li>\n");
    }
    for sec in info.sections {
        s.push_str(&format!(
            "<li><a href=\"#{}\">{}</a></li>\n",
            sec.id,
            esc(&sec.title)
        ));
    }
    s.push_str("</ol></nav>\n");
    let claims: Vec<&Claim> = info.sections.iter().flat_map(|x| x.claims.iter()).collect();
    s.push_str("<h2 id=\"claims\">Claims of the seeds, checked by the data</h2>\n");
    if claims.is_empty() {
        s.push_str("<p>No claim is checked in this plan.</p>\n");
    } else {
        let n = tally(&claims);
        s.push_str(&format!(
            "<p><b>{} claims:</b> {}.</p>\n<p class=\"small\">One row per statement; where the seeds state a thing twice differently, each statement has its own row. \
             <i>partly</i>: the main part holds, a detail differs; <i>seed inconsistent</i>: the statement contradicts another statement of the seeds and the data side with the other. \
             Every verdict uses the decided classification of each run (periodic by the period test, chaotic only with a significantly positive TLE); shares and counts take every value as decided; ranges and label sequences pass over a single value between two equal neighbours (a bifurcation point), and say so.</p>\n",
            claims.len(),
            Verdict::ALL
                .iter()
                .zip(n)
                .map(|(v, k)| format!("{k} {}", v.word()))
                .collect::<Vec<_>>()
                .join(", ")
        ));
        s.push_str(&claims_table(&claims));
    }
    let alternatives: Vec<&Claim> = info
        .sections
        .iter()
        .flat_map(|x| x.alternatives.iter())
        .collect();
    if !alternatives.is_empty() {
        s.push_str(&readings_matrix(&claims, &alternatives));
    }
    for sec in info.sections {
        s.push_str(&format!("<h2 id=\"{}\">{}</h2>\n", sec.id, esc(&sec.title)));
        s.push_str(&format!(
            "<p class=\"meta\">{}<b>Parameters.</b> {}<br><b>Method.</b> {} <i>({:.1} s)</i></p>\n",
            if sec.seed_ref.is_empty() {
                String::new()
            } else {
                format!("<b>Seed.</b> {}<br>", esc(&sec.seed_ref))
            },
            esc(&sec.parameters),
            esc(&sec.method),
            sec.seconds
        ));
        if !sec.readings.is_empty() {
            s.push_str("<ul>\n");
            for r in &sec.readings {
                s.push_str(&format!("<li>{}</li>\n", esc(r)));
            }
            s.push_str("</ul>\n");
        }
        for fig in &sec.figures {
            let data = fig
                .data
                .iter()
                .map(|d| {
                    format!(
                        "<a href=\"{}\">{}</a>",
                        esc(d),
                        esc(d.rsplit('/').next().unwrap_or(d))
                    )
                })
                .collect::<Vec<_>>()
                .join(", ");
            s.push_str(&format!(
                "<figure><img src=\"{}\" alt=\"{}\" loading=\"lazy\"><figcaption>{} (<a href=\"{}\">SVG</a>; data: {})</figcaption></figure>\n",
                esc(&fig.png),
                esc(&fig.caption),
                esc(&fig.caption),
                esc(&fig.svg),
                data
            ));
        }
        for t in &sec.tables {
            s.push_str(&format!(
                "<p><b>{}</b> (<a href=\"{}\">CSV</a>)</p><table><tr>",
                esc(&t.title),
                esc(&t.csv)
            ));
            for h in &t.header {
                s.push_str(&format!("<th>{}</th>", esc(h)));
            }
            s.push_str("</tr>\n");
            for row in t.rows.iter().take(MAX_ROWS) {
                s.push_str("<tr>");
                for c in row {
                    s.push_str(&format!("<td>{}</td>", esc(c)));
                }
                s.push_str("</tr>\n");
            }
            s.push_str("</table>\n");
            if t.rows.len() > MAX_ROWS {
                s.push_str(&format!(
                    "<p class=\"small\">First {MAX_ROWS} of {} rows; all in the CSV.</p>\n",
                    t.rows.len()
                ));
            }
        }
        if !sec.claims.is_empty() {
            s.push_str("<p><b>Claims checked here:</b></p>\n");
            let cl: Vec<&Claim> = sec.claims.iter().collect();
            s.push_str(&claims_table(&cl));
        }
    }
    s.push_str("</body></html>\n");
    s
}

#[test]
fn templates_give_the_same_page() {
    use crate::{Figure, Section, Table};
    let claim = |t: &str, i: &str, v: Verdict| Claim {
        claim: format!("{t} <a> & \"q\" 'x'"),
        source: "003 §4 / 5".into(),
        interpretation: i.into(),
        seed_value: "58 %".into(),
        measured_value: "1 > 0".into(),
        verdict: v,
        evidence: "why\nnot".into(),
    };
    let sec = |id: &str, seed: &str, rows: usize, alt: bool, readings: bool| Section {
        id: id.into(),
        title: format!("Title {id} <x>"),
        seed_ref: seed.into(),
        parameters: "F = 0.1 & xi".into(),
        method: "m".into(),
        figures: vec![
            Figure {
                png: "a/b.png".into(),
                svg: "a/b.svg".into(),
                caption: "cap \"1\"".into(),
                data: vec!["a/x.csv".into(), "y.csv".into()],
            },
            Figure {
                png: "c.png".into(),
                svg: "c.svg".into(),
                caption: "c".into(),
                data: vec![],
            },
        ],
        readings: if readings {
            vec!["r1 <".into(), "r2".into()]
        } else {
            vec![]
        },
        tables: vec![Table {
            title: "T&".into(),
            csv: "t.csv".into(),
            header: vec!["a".into(), "b".into()],
            rows: (0..rows)
                .map(|i| vec![format!("{i}"), "<".into()])
                .collect(),
        }],
        claims: vec![
            claim(
                "c1",
                if alt { "reading one" } else { "" },
                Verdict::NotReproduced,
            ),
            claim("c2", "", Verdict::Reproduced),
        ],
        alternatives: if alt {
            vec![
                claim("c1", "reading two", Verdict::Partly),
                claim("c3", "reading three", Verdict::SeedInconsistent),
            ]
        } else {
            vec![]
        },
        seconds: 12.349,
    };
    for (preset, quick, secs) in [
        ("classic", false, vec![]),
        (
            "internal",
            true,
            vec![
                sec("s1", "", 3, false, true),
                sec("s2", "004 Fig. 5", 45, true, false),
            ],
        ),
        (
            "breakage",
            false,
            vec![
                sec("s1", "x", 40, false, false),
                sec("s3", "", 41, false, true),
            ],
        ),
    ] {
        let cfg = geardyn_io::Config::preset(preset).unwrap();
        let scenario = cfg.resolve().unwrap();
        for horizon in [geardyn_analysis::classify::DECISION_PERIODS, 77] {
            let info = PageInfo {
                preset,
                cfg: &cfg,
                scenario: &scenario,
                sections: &secs,
                quick,
                horizon,
                seconds: 3.5,
                size: 1_234_567,
                budget: 8_000_000,
            };
            assert_eq!(page(&info), crate::html::page(&info), "{preset} {horizon}");
        }
    }
    let presets = vec!["a&b".to_string(), "classic".into()];
    let mut s = String::from("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>geardyn reports</title></head><body>\n<h1>geardyn reports</h1>\n<ul>\n");
    for p in &presets {
        let p = esc(p);
        s.push_str(&format!(
            "<li><a href=\"{p}/index.html\">preset <code>{p}</code></a></li>\n"
        ));
    }
    s.push_str("</ul>\n</body></html>\n");
    assert_eq!(s, crate::html::root_page(&presets));
}
