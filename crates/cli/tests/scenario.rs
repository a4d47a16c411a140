//! "What I set is what ran": every command resolves its model through the one builder, records
//! the integrated parameters in `run.json`, and output folders never mix.

mod common;
use common::{geardyn, geardyn_ok, strs};

/// A fresh path for this file's test `name`.
fn tmp(name: &str) -> std::path::PathBuf {
    common::tmp("scn", name)
}

use std::path::Path;

fn resolved(dir: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(dir.join("run.json")).expect("run.json written");
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["resolved"].clone()
}

const PRESETS: [&str; 3] = ["classic", "breakage", "internal"];

/// The commands that integrate the model and write a folder ([`command_args`] gives their short
/// arguments).
const RUNS: [&str; 6] = [
    "simulate",
    "bifurcation",
    "response",
    "basins",
    "continuation",
    "map2d",
];

/// Short, cheap arguments of every command that writes a folder.
fn command_args(cmd: &str) -> Vec<&'static str> {
    // a short decision horizon: these tests check what is integrated, not the verdict
    let short = [
        "--periods",
        "2",
        "--transient",
        "2",
        "--decision-periods",
        "200",
    ];
    let mut a: Vec<&'static str> = match cmd {
        "simulate" => vec![],
        "bifurcation" => vec!["--range", "0.9:1.1:2"],
        "response" => vec!["--range", "0.9:1.1:2"],
        "basins" => vec!["--grid", "x:-1:1:3", "--grid", "v:-1:1:3"],
        "continuation" => vec!["--range", "0.9:1.1:2", "--ics", "2"],
        "map2d" => vec!["--x", "xi:0.1:0.2:2", "--y", "F:0.05:0.1:2"],
        "stiffness" => return vec![],
        _ => unreachable!(),
    };
    a.extend(short);
    a
}

#[test]
fn every_command_integrates_the_operating_point_that_was_set() {
    for preset in PRESETS {
        for cmd in RUNS.into_iter().chain(["stiffness"]) {
            let dir = tmp(&format!("{cmd}-{preset}"));
            let mut args = strs(&[cmd, "--preset", preset]);
            for s in ["omega=1.23", "F=0.0456", "xi=0.0789", "c=0.0321", "D=1.11"] {
                args.extend(strs(&["--set", s]));
            }
            args.extend(strs(&command_args(cmd)));
            args.extend(strs(&["--out", dir.to_str().unwrap()]));
            let (code, _, err) = geardyn(&args);
            assert_eq!(code, 0, "{cmd} {preset}: {err}");
            let r = resolved(&dir);
            // a swept parameter's base value is the one set; the sweep itself varies it
            if !["bifurcation", "response", "continuation"].contains(&cmd) {
                assert_eq!(r["omega"], 1.23, "{cmd} {preset}: {r}");
            }
            if cmd != "map2d" {
                assert_eq!(r["F"], 0.0456, "{cmd} {preset}: {r}");
                assert_eq!(r["xi"], 0.0789, "{cmd} {preset}: {r}");
            }
            assert_eq!(r["c"], 0.0321, "{cmd} {preset}: {r}");
            assert_eq!(r["D_s"], 1.11, "{cmd} {preset}: {r}");
            // and the record names what the sweep varied, with its values
            let text = std::fs::read_to_string(dir.join("run.json")).unwrap();
            let v: serde_json::Value = serde_json::from_str(&text).unwrap();
            let swept: Vec<(String, f64, f64)> = v["swept"]
                .as_array()
                .map(|a| {
                    a.iter()
                        .map(|s| {
                            (
                                s["param"].as_str().unwrap().to_string(),
                                s["from"].as_f64().unwrap(),
                                s["to"].as_f64().unwrap(),
                            )
                        })
                        .collect()
                })
                .unwrap_or_default();
            let expected: Vec<(String, f64, f64)> = match cmd {
                "bifurcation" | "response" | "continuation" => vec![("omega".into(), 0.9, 1.1)],
                "map2d" => vec![("xi".into(), 0.1, 0.2), ("F".into(), 0.05, 0.1)],
                _ => vec![],
            };
            assert_eq!(swept, expected, "{cmd} {preset}");
            let _ = std::fs::remove_dir_all(&dir);
        }
    }
}

#[test]
fn every_command_runs_the_contact_law_that_was_given() {
    for cmd in RUNS {
        let dir = tmp(&format!("contact-{cmd}"));
        let mut args = strs(&[cmd, "--preset", "internal", "--contact", "power:1.5"]);
        args.extend(strs(&command_args(cmd)));
        args.extend(strs(&["--out", dir.to_str().unwrap()]));
        let (code, _, err) = geardyn(&args);
        assert_eq!(code, 0, "{cmd}: {err}");
        let text = std::fs::read_to_string(dir.join("run.json")).unwrap();
        let v: serde_json::Value = serde_json::from_str(&text).unwrap();
        let law = &v["config"]["model"]["contact"];
        assert_eq!(law["law"], "power", "{cmd}: {law}");
        assert_eq!(law["exponent"], 1.5, "{cmd}: {law}");
        let _ = std::fs::remove_dir_all(&dir);
    }
    // a field the law does not have is refused, naming the option
    let (code, _, err) = geardyn(&strs(&["simulate", "--contact", "linear:2"]));
    assert_ne!(code, 0);
    assert!(
        err.contains("--contact") && err.contains("linear has no exponent"),
        "{err}"
    );
}

#[test]
fn a_set_operating_point_changes_the_result_on_every_preset() {
    for preset in PRESETS {
        let mut summaries = Vec::new();
        for omega in ["0.7", "2"] {
            let dir = tmp(&format!("omega-{preset}-{omega}"));
            geardyn_ok(&strs(&[
                "simulate",
                "--preset",
                preset,
                "--set",
                &format!("omega={omega}"),
                "--periods",
                "3",
                "--transient",
                "5",
                "--out",
                dir.to_str().unwrap(),
            ]));
            summaries.push(std::fs::read_to_string(dir.join("strobe.csv")).unwrap());
            let _ = std::fs::remove_dir_all(&dir);
        }
        assert_ne!(summaries[0], summaries[1], "{preset}: omega had no effect");
        // lyapunov prints what it integrated
        let out = geardyn_ok(&strs(&[
            "lyapunov",
            "--preset",
            preset,
            "--set",
            "omega=1.7",
            "--periods",
            "2",
            "--transient",
            "2",
            "--method",
            "variational",
        ]));
        assert!(out.contains("omega = 1.7"), "{preset}: {out}");
    }
}

fn csv_rows(path: &Path) -> Vec<Vec<String>> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(String::from).collect())
        .collect()
}

#[test]
fn a_one_value_bifurcation_equals_simulate_on_every_preset() {
    for preset in PRESETS {
        for (param, value) in [("omega", "1.2"), ("F", "0.08")] {
            let s = tmp(&format!("eq-sim-{preset}-{param}"));
            let b = tmp(&format!("eq-bif-{preset}-{param}"));
            let common = [
                "--periods",
                "4",
                "--transient",
                "20",
                "--decision-periods",
                "200",
            ];
            let mut sa = strs(&["simulate", "--preset", preset, "--set"]);
            sa.push(format!("{param}={value}"));
            sa.extend(strs(&common));
            sa.extend(strs(&["--out", s.to_str().unwrap()]));
            let mut ba = strs(&["bifurcation", "--preset", preset, "--param", param]);
            ba.extend(strs(&["--range", &format!("{value}:{value}:1")]));
            ba.extend(strs(&common));
            ba.extend(strs(&["--out", b.to_str().unwrap()]));
            assert_eq!(geardyn(&sa).0, 0);
            assert_eq!(geardyn(&ba).0, 0);
            let strobe = csv_rows(&s.join("strobe.csv"));
            let points = csv_rows(&b.join("bifurcation.csv"));
            assert_eq!(strobe.len(), points.len(), "{preset} {param}");
            for (a, p) in strobe.iter().zip(&points) {
                for (i, j) in [(1, 4), (2, 5)] {
                    let (x, y): (f64, f64) = (a[i].parse().unwrap(), p[j].parse().unwrap());
                    assert!((x - y).abs() <= 1e-9, "{preset} {param}: {x} vs {y}");
                }
            }
            let _ = std::fs::remove_dir_all(&s);
            let _ = std::fs::remove_dir_all(&b);
        }
    }
}

/// The README's main job through the binary: `report` writes the page, its top index links it, and
/// a rerun resumes from the cached studies (that two presets' pages never touch each other's files
/// is checked on the library side, crates/report/tests/page.rs, beside the internal page it runs).
#[test]
fn report_through_the_binary_writes_the_page_and_resumes() {
    let out = tmp("reports");
    let o = out.to_str().unwrap();
    let run = || {
        let (code, _, err) = geardyn(&strs(&[
            "report", "--preset", "classic", "--quick", "--out", o,
        ]));
        assert_eq!(code, 0, "{err}");
        err
    };
    let first = run();
    assert!(!first.contains(": cached"), "{first}");
    let index = std::fs::read_to_string(out.join("index.html")).unwrap();
    assert!(index.contains("classic/index.html"));
    assert!(out.join("classic").join("claims.csv").is_file());
    let again = run();
    assert!(again.contains(": cached"), "{again}");
    assert!(!again.contains("computing it again"), "{again}");
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn folders_of_other_commands_or_settings_are_refused() {
    let d = tmp("refuse");
    let o = d.to_str().unwrap();
    let bif = |omega_range: &str, force: bool| {
        let mut a = strs(&[
            "bifurcation",
            "--range",
            omega_range,
            "--periods",
            "2",
            "--transient",
            "2",
            "--out",
            o,
        ]);
        if force {
            a.push("--force".into());
        }
        geardyn(&a)
    };
    assert_eq!(bif("0.8:0.9:2", false).0, 0);
    let (code, _, err) = bif("0.8:1.0:2", false);
    assert_ne!(code, 0);
    assert!(
        err.contains("--force") && err.trim().lines().count() == 1,
        "{err}"
    );
    assert_eq!(bif("0.8:1.0:2", true).0, 0);
    let before = std::fs::read(d.join("config.toml")).unwrap();
    let (code, _, err) = geardyn(&strs(&["simulate", "--periods", "2", "--out", o]));
    assert_ne!(code, 0);
    assert!(err.contains("geardyn bifurcation"), "{err}");
    assert_eq!(before, std::fs::read(d.join("config.toml")).unwrap());
    let _ = std::fs::remove_dir_all(&d);
}
