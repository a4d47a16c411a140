//! The report page as a reader would open it: every referenced figure and table exists, every
//! figure has the CSV of its data next to it, the page needs nothing from the network, the
//! folder stays within its size budget, a rerun reuses the cached studies, and the claims table
//! has its columns, its verdict vocabulary and an explanation for every `not reproduced`.

use geardyn_io::Config;
use geardyn_report::{folder_size, run, size_budget, ReportOptions};
use std::path::{Path, PathBuf};

fn refs(html: &str, attr: &str) -> Vec<String> {
    html.split(&format!("{attr}=\""))
        .skip(1)
        .filter_map(|s| s.split('"').next().map(str::to_string))
        .collect()
}

fn quick(preset: &str) -> (PathBuf, PathBuf, String) {
    let out = std::env::temp_dir().join(format!("geardyn-report-{preset}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    quick_into(preset, &out)
}

/// The quick report of `preset` into `out` (beside what is already there).
fn quick_into(preset: &str, out: &Path) -> (PathBuf, PathBuf, String) {
    let out = out.to_path_buf();
    let cfg = Config::preset(preset).unwrap();
    let opts = ReportOptions {
        preset: preset.into(),
        quick: true,
        out: out.clone(),
        decision_given: (false, false),
    };
    let index = run(&cfg, &opts).unwrap();
    assert_eq!(index, out.join(preset).join("index.html"));
    let html = std::fs::read_to_string(&index).unwrap();
    (out.clone(), out.join(preset), html)
}

/// Every file under `dir` with its bytes, sorted by path.
fn snapshot(dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else {
                out.push((p.clone(), std::fs::read(&p).unwrap()));
            }
        }
    }
    out.sort();
    out
}

fn non_empty(p: &Path) -> bool {
    p.metadata().map(|m| m.len() > 0).unwrap_or(false)
}

/// Every `<figure>` links its PNG, its SVG and at least one CSV of its data, all present.
fn check_figures(page_dir: &Path, html: &str) -> usize {
    let figures: Vec<&str> = html
        .split("<figure>")
        .skip(1)
        .map(|s| s.split("</figure>").next().unwrap_or(""))
        .collect();
    assert!(!figures.is_empty());
    for fig in &figures {
        let srcs = refs(fig, "src");
        let hrefs = refs(fig, "href");
        assert_eq!(srcs.len(), 1, "{fig}");
        assert!(srcs[0].ends_with(".png"), "{fig}");
        assert!(hrefs.iter().any(|h| h.ends_with(".svg")), "no SVG: {fig}");
        let csv: Vec<&String> = hrefs.iter().filter(|h| h.ends_with(".csv")).collect();
        assert!(!csv.is_empty(), "figure without its data: {fig}");
        for r in srcs.iter().chain(hrefs.iter()) {
            assert!(non_empty(&page_dir.join(r)), "missing {r}");
        }
        for c in csv {
            let text = std::fs::read_to_string(page_dir.join(c)).unwrap();
            assert!(text.lines().count() >= 2, "empty data file {c}");
        }
    }
    figures.len()
}

/// Parses `claims.csv` (quoted fields) into rows.
fn claims(page_dir: &Path) -> Vec<Vec<String>> {
    claims_file(&page_dir.join("claims.csv"))
}

/// Parses a claims file (quoted fields) into rows.
fn claims_file(path: &Path) -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut rows = Vec::new();
    let (mut row, mut field, mut quoted) = (Vec::new(), String::new(), false);
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                field.push('"');
                chars.next();
            }
            ('"', _) => quoted = !quoted,
            (',', false) => row.push(std::mem::take(&mut field)),
            ('\n', false) => {
                row.push(std::mem::take(&mut field));
                rows.push(std::mem::take(&mut row));
            }
            (c, _) => field.push(c),
        }
    }
    rows
}

fn check_claims(page_dir: &Path) -> Vec<Vec<String>> {
    let rows = claims(page_dir);
    assert_eq!(
        rows[0],
        [
            "claim",
            "source",
            "interpretation",
            "seed_value",
            "measured_value",
            "verdict",
            "evidence"
        ]
    );
    let vocab = [
        "reproduced",
        "partly",
        "not reproduced",
        "seed inconsistent",
    ];
    for r in &rows[1..] {
        assert_eq!(r.len(), 7, "{r:?}");
        assert!(vocab.contains(&r[5].as_str()), "verdict {r:?}");
        assert!(!r[0].is_empty() && !r[1].is_empty(), "{r:?}");
        if r[5] != "reproduced" {
            assert!(
                r[6].len() > 20,
                "a verdict other than reproduced needs evidence: {r:?}"
            );
        }
    }
    rows[1..].to_vec()
}

fn count(rows: &[Vec<String>], verdict: &str) -> usize {
    rows.iter().filter(|r| r[5] == verdict).count()
}

#[test]
fn quick_classic_report_is_complete_and_self_contained() {
    let (out, page_dir, html) = quick("classic");
    let imgs = refs(&html, "src");
    assert!(imgs.len() >= 3, "{imgs:?}");
    for r in imgs
        .iter()
        .chain(refs(&html, "href").iter().filter(|h| !h.starts_with('#')))
    {
        assert!(!r.starts_with("http"), "external reference {r}");
        assert!(non_empty(&page_dir.join(r)), "missing {r}");
    }
    assert!(!html.contains("<script"));
    check_figures(&page_dir, &html);
    let rows = check_claims(&page_dir);
    assert_eq!(count(&rows, "reproduced"), rows.len(), "{rows:?}");
    assert!(folder_size(&page_dir) <= size_budget(true));
    // no checkpoint is left once the studies are complete
    for e in std::fs::read_dir(&page_dir).unwrap().flatten() {
        if e.path().is_dir() {
            for f in std::fs::read_dir(e.path()).unwrap().flatten() {
                assert!(!f.file_name().to_string_lossy().contains("checkpoint"));
            }
        }
    }
    // a second run reuses every cached study and writes the same page body
    let cfg = Config::preset("classic").unwrap();
    let opts = ReportOptions {
        preset: "classic".into(),
        quick: true,
        out: out.clone(),
        decision_given: (false, false),
    };
    let again = std::fs::read_to_string(run(&cfg, &opts).unwrap()).unwrap();
    let strip = |s: &str| s.split("Generated by").next().unwrap_or("").to_string();
    assert_eq!(strip(&html), strip(&again));
    // a damaged file of a cached study (one digit changed) is computed again, not reused
    let csv = std::fs::read_dir(&page_dir)
        .unwrap()
        .flatten()
        .filter(|e| e.path().is_dir())
        .flat_map(|e| std::fs::read_dir(e.path()).unwrap().flatten())
        .map(|e| e.path())
        .find(|p| p.extension().is_some_and(|x| x == "csv"))
        .expect("a study CSV");
    let good = std::fs::read_to_string(&csv).unwrap();
    let i = good.find(|c: char| c.is_ascii_digit()).unwrap();
    let mut bad = good.clone();
    let d = bad.as_bytes()[i];
    bad.replace_range(i..=i, if d == b'1' { "2" } else { "1" });
    std::fs::write(&csv, &bad).unwrap();
    run(&cfg, &opts).unwrap();
    assert_eq!(
        std::fs::read_to_string(&csv).unwrap(),
        good,
        "{}",
        csv.display()
    );
    // a truncated cache (`.cache/<preset>/<id>.data.json`) of a data-cached study (its key intact, its data cut) is computed
    // again and written whole, not trusted
    let caches = page_dir
        .parent()
        .unwrap()
        .join(".cache")
        .join(page_dir.file_name().unwrap());
    let cache = std::fs::read_dir(&caches)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .find(|p| p.to_string_lossy().ends_with(".data.json"))
        .expect("a data-cached study");
    let whole = std::fs::read_to_string(&cache).unwrap();
    let (key, rest) = whole.split_once('\n').unwrap();
    let data = rest.split_once('\n').unwrap().1;
    std::fs::write(&cache, &whole[..whole.len() - data.len() / 2]).unwrap();
    run(&cfg, &opts).unwrap();
    let again = std::fs::read_to_string(&cache).unwrap();
    let (key2, rest2) = again.split_once('\n').unwrap();
    assert_eq!(
        (key2, rest2.split_once('\n').unwrap().1),
        (key, data),
        "{}",
        cache.display()
    );
    std::fs::remove_dir_all(out).ok();
}

// Thresholds for the coarse quick grids (the full reports reproduce more; the verdicts are
// strict on purpose: one attractor per seed attractor, a regime at most values). A sanity floor,
// not a target: with the decision horizon (chaos only when it persists) the quick internal report
// reproduces 16 of 66 claims (17 before: chaotic transients had counted). The two seeds are two
// tests, so that they run side by side: each report leaves a core idle in its serial stretches.

#[test]
fn quick_internal_report_has_data_budget_and_honest_claims() {
    seed_report("internal", 0.2, 0.6);
}

#[test]
fn quick_breakage_report_has_data_budget_and_honest_claims() {
    // (the high-load claims are judged over every attractor: the coexisting 1-40-40 rattle
    // makes two of them partly, 13 of 27 reproduced in a quick report)
    seed_report("breakage", 0.45, 0.55);
}

fn seed_report(preset: &str, min_reproduced: f64, min_with_partly: f64) {
    {
        // the internal page is written beside a classic one, which it must leave untouched
        // (each preset owns its folder; the top index links both)
        // (its own folder: the classic test above runs at the same time; with
        // GEARDYN_KEEP_REPORTS=DIR the three pages stay in DIR for the browser check of CI,
        // scripts/check-report.sh --dir DIR)
        let keep = std::env::var_os("GEARDYN_KEEP_REPORTS").map(PathBuf::from);
        let beside = keep.clone().unwrap_or_else(|| {
            std::env::temp_dir().join(format!("geardyn-report-beside-{}", std::process::id()))
        });
        let (out, page_dir, html) = if preset == "internal" {
            let out = beside.clone();
            // (only its own pages: the breakage test may be writing beside them)
            for p in ["classic", "internal"] {
                let _ = std::fs::remove_dir_all(out.join(p));
            }
            let (out, classic_dir, _) = quick_into("classic", &out);
            let before = snapshot(&classic_dir);
            let r = quick_into(preset, &out);
            assert_eq!(
                before,
                snapshot(&classic_dir),
                "the internal report touched classic/"
            );
            let index = std::fs::read_to_string(out.join("index.html")).unwrap();
            assert!(index.contains("classic/index.html") && index.contains("internal/index.html"));
            r
        } else if keep.is_some() {
            quick_into(preset, &beside)
        } else {
            quick(preset)
        };
        let n = check_figures(&page_dir, &html);
        assert!(n >= 10, "{preset}: {n} figures");
        let size = folder_size(&page_dir);
        assert!(
            size <= size_budget(true),
            "{preset}: {size} bytes over the budget"
        );
        let rows = check_claims(&page_dir);
        assert!(rows.len() >= 20, "{preset}: {} claims", rows.len());
        let rep = count(&rows, "reproduced");
        assert!(
            rep as f64 >= min_reproduced * rows.len() as f64,
            "{preset}: only {rep} of {} reproduced (quick)",
            rows.len()
        );
        let part = count(&rows, "partly");
        assert!(
            (rep + part) as f64 >= min_with_partly * rows.len() as f64,
            "{preset}: only {} of {} reproduced or partly (quick)",
            rep + part,
            rows.len()
        );
        // sources name the seed file
        assert!(rows.iter().all(|r| r[1].contains("seed")), "{preset}");
        // every headline claim names the reading of the text it uses; the file of every reading
        // holds the headline rows and, for the claims that depend on a reading, the others
        assert!(rows.iter().all(|r| !r[2].is_empty()), "{preset}");
        // evidence in a few sentences (details in the study CSV files)
        for r in &rows {
            assert!(
                r[6].chars().count() <= geardyn_report::EVIDENCE_MAX,
                "{preset}: long evidence {r:?}"
            );
        }
        let every = claims_file(&page_dir.join("claims_by_interpretation.csv"));
        assert_eq!(every[0], claims_file(&page_dir.join("claims.csv"))[0]);
        assert!(
            every.len() > rows.len() + 1,
            "{preset}: no claim under another reading"
        );
        let cascade: Vec<&Vec<String>> = every[1..]
            .iter()
            .filter(|r| r[0].contains("12-4-4-4-4"))
            .collect();
        if preset == "internal" {
            let readings: std::collections::BTreeSet<&str> =
                cascade.iter().map(|r| r[2].as_str()).collect();
            assert!(readings.len() >= 5, "{readings:?}");
            assert!(html.contains("claims-by-reading"));
        }
        // captions are written for the preset shown
        if preset == "internal" {
            assert!(!html.contains("broken pair") && !html.contains("chipped"));
        }
        // the coexistence of period 2 and 4 near F = 0.05 is seed A's sentence
        let p24: Vec<&Vec<String>> = rows
            .iter()
            .filter(|r| r[0].contains("period-4 and period-2"))
            .collect();
        if preset == "breakage" {
            assert_eq!(p24.len(), 1);
            assert!(p24[0][1].contains("seed A"));
        } else {
            assert!(p24.is_empty());
        }
        if keep.is_none() {
            std::fs::remove_dir_all(out).ok();
        }
    }
}

/// The plan integrates with the configuration's integrator and follow (`--set rtol=...`,
/// `follow_steps`, a config file's `[simulation]`): a setting out of range is refused before any
/// study runs, naming the field (the studies had used the default integrator whatever the
/// configuration said).
#[test]
fn the_report_takes_the_configurations_integrator() {
    let out = std::env::temp_dir().join(format!("geardyn-report-rtol-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let opts = ReportOptions {
        preset: "classic".into(),
        quick: true,
        out: out.clone(),
        decision_given: (false, false),
    };
    let mut cfg = Config::preset("classic").unwrap();
    cfg.simulation.rtol = -1.0;
    let err = run(&cfg, &opts).unwrap_err().to_string();
    assert!(err.contains("simulation.rtol"), "{err}");
    let mut cfg = Config::preset("classic").unwrap();
    cfg.simulation.follow_steps = 3;
    let err = run(&cfg, &opts).unwrap_err().to_string();
    assert!(err.contains("simulation.follow_steps"), "{err}");
    let _ = std::fs::remove_dir_all(&out);
}
