//! The `geardyn` binary as a user sees it: outputs written, bad input rejected in one line.

use std::process::Command;

fn geardyn(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_geardyn"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn tmp(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("geardyn-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

#[test]
fn simulate_writes_every_output() {
    let dir = tmp("sim");
    let (code, out, err) = geardyn(&[
        "simulate",
        "--preset",
        "classic",
        "--set",
        "omega=0.95",
        "--periods",
        "20",
        "--transient",
        "200",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("period 2"), "{out}");
    for f in [
        "trajectory.csv",
        "strobe.csv",
        "events.csv",
        "sections.csv",
        "summary.json",
        "config.toml",
        "time_history.png",
        "time_history.svg",
        "phase_portrait.png",
        "mesh_force.png",
    ] {
        assert!(
            dir.join(f).metadata().map(|m| m.len() > 0).unwrap_or(false),
            "{f} missing"
        );
    }
    let strobe = std::fs::read_to_string(dir.join("strobe.csv")).unwrap();
    assert_eq!(
        strobe.lines().count(),
        21,
        "header + one row per recorded period"
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["period"], 2);
    // the echoed config reproduces the run
    let cfg = dir.join("config.toml");
    let dir2 = tmp("sim2");
    let (code, out2, _) = geardyn(&[
        "simulate",
        "--config",
        cfg.to_str().unwrap(),
        "--out",
        dir2.to_str().unwrap(),
    ]);
    assert_eq!(code, 0);
    assert_eq!(out.split(';').next(), out2.split(';').next());
    assert_eq!(
        strobe,
        std::fs::read_to_string(dir2.join("strobe.csv")).unwrap()
    );
}

#[test]
fn bad_input_gives_one_line_errors() {
    let bad_toml = tmp("bad.toml");
    std::fs::write(&bad_toml, "[model\nomega = 1").unwrap();
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["simulate", "--preset", "nope"], "unknown preset"),
        (vec!["simulate", "--set", "omgea=1"], "omgea"),
        (vec!["simulate", "--set", "D=-1"], "D_d"),
        (vec!["simulate", "--set", "omega=NaN"], "omega"),
        (
            vec!["simulate", "--set", "mu=1e6", "--preset", "breakage"],
            "h > 0",
        ),
        (
            vec!["simulate", "--config", bad_toml.to_str().unwrap()],
            "malformed",
        ),
        (vec!["show", "--config", "/nonexistent.toml"], "cannot read"),
    ];
    for (args, needle) in cases {
        let (code, _, err) = geardyn(&args);
        assert_ne!(code, 0, "{args:?}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
    }
}

#[test]
fn presets_and_show() {
    let (code, out, _) = geardyn(&["presets"]);
    assert_eq!(code, 0);
    for p in ["classic", "breakage", "internal"] {
        assert!(out.contains(p));
        let (code, toml, _) = geardyn(&["show", "--preset", p]);
        assert_eq!(code, 0);
        assert!(toml.contains("[model]") && toml.contains("omega"));
    }
}
