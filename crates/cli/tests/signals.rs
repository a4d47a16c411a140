//! `geardyn signals` as a user meets it: the broken pair and its healthy twin written as
//! signals.csv, spectrum.csv and indicators.csv with every indicator, the raw moments recomputed
//! from signals.csv as written, the healthy mesh force's line at the mesh order, and clear
//! refusals.

mod common;
use common::{geardyn, geardyn_ok};

/// A fresh path for this file's test `name`.
fn tmp(name: &str) -> std::path::PathBuf {
    common::tmp("sig", name)
}

use geardyn_analysis::indicators::INDICATOR_NAMES;
use geardyn_analysis::signals::SIGNAL_NAMES;
use std::collections::HashMap;
use std::path::Path;

/// Header and rows of a CSV file without quoted fields.
fn csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    (header, rows)
}

#[test]
fn broken_and_healthy_pairs_with_every_indicator_and_recomputable_moments() {
    let out = tmp("default");
    let o = out.to_str().unwrap();
    // a point where the broken cycle is in contact (the chip shows: the healthy twin stays in
    // drive contact, period one mesh cycle), kept short
    let stdout = geardyn_ok(&[
        "signals",
        "--set",
        "omega=0.3",
        "--set",
        "F=0.15",
        "--transient",
        "100",
        "--revolutions",
        "8",
        "--samples-per-cycle",
        "16",
        "--out",
        o,
    ]);
    assert!(
        stdout.contains("broken pair") && stdout.contains("healthy pair"),
        "{stdout}"
    );
    for f in [
        "signals.csv",
        "spectrum.csv",
        "indicators.csv",
        "tsa.csv",
        "lines.csv",
        "signals.json",
        "run.json",
        "config.toml",
        "spectrum.png",
        "spectrum.svg",
        "tsa.png",
        "tsa.svg",
    ] {
        assert!(out.join(f).is_file(), "missing {f}");
    }
    let (h, rows) = csv(&out.join("signals.csv"));
    assert_eq!(
        h,
        ["pair", "tau", "dte_um", "mesh_force_N", "acceleration_m_s2"]
    );
    // 8 revolutions of 40 mesh cycles of 16 samples, per pair
    let per_pair = 8 * 40 * 16;
    assert_eq!(rows.len(), 2 * per_pair);
    let (hi, irows) = csv(&out.join("indicators.csv"));
    assert_eq!(hi, ["pair", "signal", "indicator", "value"]);
    let mut ind: HashMap<(String, String, String), f64> = HashMap::new();
    for r in &irows {
        ind.insert(
            (r[0].clone(), r[1].clone(), r[2].clone()),
            r[3].parse().unwrap(),
        );
    }
    for pair in ["healthy", "broken"] {
        for (k, sig) in SIGNAL_NAMES.iter().enumerate() {
            for name in INDICATOR_NAMES {
                let v = ind[&(pair.into(), sig.to_string(), name.to_string())];
                assert!(v.is_finite(), "{pair} {sig} {name} = {v}");
            }
            // the moments of the raw signal, recomputed from the file as written
            let x: Vec<f64> = rows
                .iter()
                .filter(|r| r[0] == pair)
                .map(|r| r[2 + k].parse().unwrap())
                .collect();
            assert_eq!(x.len(), per_pair);
            let n = x.len() as f64;
            let mean = x.iter().sum::<f64>() / n;
            let m2 = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n;
            let m4 = x.iter().map(|v| (v - mean).powi(4)).sum::<f64>() / n;
            let rms = (x.iter().map(|v| v * v).sum::<f64>() / n).sqrt();
            let peak = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * b.abs().max(1e-300);
            let got = |i: &str| ind[&(pair.into(), sig.to_string(), i.to_string())];
            assert!(close(got("rms"), rms), "{pair} {sig} rms");
            assert!(
                close(got("kurtosis"), m4 / (m2 * m2)),
                "{pair} {sig} kurtosis"
            );
            assert!(close(got("crest_factor"), peak / rms), "{pair} {sig} crest");
        }
    }
    // the healthy mesh force: a line at the mesh order (z1 = 40), far above the orders around it
    // (the Hann window leaks a line into the bins 1/4 order beside it, no further), and on a
    // motion of one mesh cycle no line off the mesh harmonics
    let (hs, srows) = csv(&out.join("spectrum.csv"));
    assert_eq!(hs, ["pair", "signal", "order", "amplitude"]);
    let amp: Vec<(f64, f64)> = srows
        .iter()
        .filter(|r| r[0] == "healthy" && r[1] == "mesh_force_N")
        .map(|r| (r[2].parse().unwrap(), r[3].parse().unwrap()))
        .collect();
    let at = |o: f64| amp.iter().find(|p| p.0 == o).unwrap().1;
    let around = amp
        .iter()
        .filter(|p| (p.0 - 40.0).abs() >= 0.5 && (p.0 - 40.0).abs() <= 10.0)
        .fold(0.0f64, |m, p| m.max(p.1));
    assert!(at(40.0) > 1e3 * around, "{} vs {around}", at(40.0));
    let off_mesh = amp
        .iter()
        .filter(|p| p.0 >= 1.0 && (p.0 / 40.0 - (p.0 / 40.0).round()).abs() * 40.0 >= 0.5)
        .fold(0.0f64, |m, p| m.max(p.1));
    assert!(off_mesh < 1e-3 * at(40.0), "{off_mesh}");
    // the lines of the TSA, labelled
    let (hl, lrows) = csv(&out.join("lines.csv"));
    assert_eq!(hl, ["pair", "signal", "order", "label", "amplitude"]);
    assert!(lrows
        .iter()
        .any(|r| r[0] == "healthy" && r[1] == "mesh_force_N" && r[2] == "40" && r[3] == "mesh1"));
    // the chip shows at this point: the broken acceleration is more impulsive
    let b = ind[&(
        "broken".into(),
        "acceleration_m_s2".into(),
        "kurtosis".into(),
    )];
    let h = ind[&(
        "healthy".into(),
        "acceleration_m_s2".into(),
        "kurtosis".into(),
    )];
    assert!(b > 1.5 * h, "kurtosis {b} vs {h}");
    let b = ind[&("broken".into(), "acceleration_m_s2".into(), "na4".into())];
    let h = ind[&("healthy".into(), "acceleration_m_s2".into(), "na4".into())];
    assert!(b > 2.0 * h, "NA4 {b} vs {h}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("signals.json")).unwrap()).unwrap();
    assert_eq!(json["result"]["options"]["mesh_order"], 40);
    assert!(
        json["result"]["orders"]["difference"]
            .as_array()
            .unwrap()
            .len()
            > 3
    );
    let run: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("run.json")).unwrap()).unwrap();
    assert_eq!(run["kind"], "signals");
    std::fs::remove_dir_all(out).ok();
}

#[test]
fn refusals_name_the_setting() {
    let out = tmp("bad");
    let o = out.to_str().unwrap();
    let (code, _, stderr) = geardyn(&["signals", "--preset", "classic", "--out", o]);
    assert_eq!(code, 2);
    assert!(stderr.contains("[pair]"), "{stderr}");
    assert!(!out.exists(), "a refused run touches no folder");
    for (flag, value, field) in [
        ("--revolutions", "1", "revolutions"),
        ("--samples-per-cycle", "1", "samples_per_cycle"),
        ("--segment-revolutions", "99", "segment_revolutions"),
    ] {
        let (code, _, stderr) = geardyn(&["signals", flag, value, "--out", o]);
        assert_eq!(code, 2, "{flag}");
        assert!(
            stderr.contains(field) && stderr.contains("allowed"),
            "{stderr}"
        );
        assert!(!stderr.contains("panicked"), "{stderr}");
    }
}

#[test]
fn a_pair_without_breakage_writes_the_healthy_pair_and_says_so() {
    let out = tmp("internal");
    let o = out.to_str().unwrap();
    let stdout = geardyn_ok(&[
        "signals",
        "--preset",
        "internal",
        "--transient",
        "20",
        "--revolutions",
        "2",
        "--segment-revolutions",
        "1",
        "--samples-per-cycle",
        "8",
        "--out",
        o,
    ]);
    assert!(stdout.contains("no broken tooth"), "{stdout}");
    let (_, rows) = csv(&out.join("signals.csv"));
    assert!(rows.iter().all(|r| r[0] == "healthy"));
    let (_, irows) = csv(&out.join("indicators.csv"));
    assert_eq!(irows.len(), 3 * 13);
    std::fs::remove_dir_all(out).ok();
}
