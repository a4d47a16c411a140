//! The `geardyn` binary as a user sees it: outputs written, bad input rejected in one line.

mod common;
use common::{geardyn, geardyn_ok, strs};

/// A fresh path for this file's test `name`.
fn tmp(name: &str) -> std::path::PathBuf {
    common::tmp("cli", name)
}

#[test]
fn simulate_writes_every_output() {
    let dir = tmp("sim");
    let out = geardyn_ok(&[
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
            vec!["simulate", "--set", "arm=0.1", "--set", "mu=20"],
            "h > 0",
        ),
        (
            vec!["simulate", "--set", "mu=0.3", "--preset", "breakage"],
            "pair.mu",
        ),
        (
            vec!["simulate", "--config", bad_toml.to_str().unwrap()],
            "malformed",
        ),
        (vec!["show", "--config", "/nonexistent.toml"], "cannot read"),
        (vec!["continuation", "--phase", "1"], "bad phase 1"),
        (
            vec!["map2d", "--x", "xi:0:0.3:3", "--y", "xi:0:0.2:3"],
            "two different",
        ),
        (
            vec!["map2d", "--x", "xi:0:0.3:100000", "--y", "F:0:0.2:100000"],
            "cells",
        ),
        // bench: every length and count it takes is bounded (0 periods printed "inf ns/step",
        // 1e8 steps per cycle ran for hours)
        (vec!["bench", "--periods", "0"], "--periods 0"),
        (vec!["bench", "--repeat", "0"], "--repeat 0"),
        (
            vec!["bench", "--steps-per-cycle", "100000000"],
            "[8, 1000000]",
        ),
        (vec!["bench", "--basin-steps", "4"], "--basin-steps 4"),
        (vec!["bench", "--grazing", "9"], "--grazing 9"),
        // issue 28, item 11: a field given twice is refused (it was silently overridden); a huge
        // number is printed as one (it was 301 digits); a wide range keeps its start (0.5 was
        // snapped to 0 as "a rounding of zero")
        (
            vec!["simulate", "--periods", "5", "--set", "record_periods=7"],
            "given twice",
        ),
        (
            vec![
                "bifurcation",
                "--transient",
                "5",
                "--set",
                "transient_periods=7",
            ],
            "given twice",
        ),
        (vec!["continuation", "--phase", "1e300"], "bad phase 1e300:"),
        // a pair field: the kind of value needed (it said "expected u32"), and a table the pair
        // does not have (it said "missing field `torque_nm`")
        (
            vec!["simulate", "--preset", "breakage", "--set", "pair.z1=-1"],
            "pair.z1: -1: a whole number >= 0 is needed",
        ),
        (
            vec![
                "simulate",
                "--preset",
                "breakage",
                "--set",
                "pair.operating.speed_rpm=1000",
            ],
            "this pair has no such table",
        ),
        (
            vec!["map2d", "--x", "omega:0.5:2:1e9"],
            "bad --x '0.5:2:1e9'",
        ),
        (
            vec!["bifurcation", "--range", "0.5:1e300:3"],
            "omega = 1e300: invalid omega = 1e300",
        ),
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
        assert!(toml.contains("[model"), "{toml}");
        assert!(
            toml.contains("# integrated (dimensionless): omega ="),
            "{toml}"
        );
    }
}

fn geardyn_env(args: &[&str], threads: &str) -> (i32, String, String) {
    let out = common::bin()
        .args(args)
        .env("RAYON_NUM_THREADS", threads)
        .output();
    common::outcome(out.unwrap())
}

#[test]
fn bifurcation_is_resumable_and_thread_count_independent() {
    let a = tmp("bif1");
    let b = tmp("bif2");
    let args = |d: &std::path::Path| -> Vec<String> {
        strs(&[
            "bifurcation",
            "--range",
            "0.8:1.4:9",
            "--mode",
            "multi",
            "--ics",
            "3",
            "--periods",
            "20",
            "--transient",
            "100",
            "--sections",
            "strobe,ds_up,ds_down",
            "--lyapunov",
            "--out",
            d.to_str().unwrap(),
        ])
    };
    let aa = args(&a);
    let ba = args(&b);
    let aa: Vec<&str> = aa.iter().map(|s| s.as_str()).collect();
    let ba: Vec<&str> = ba.iter().map(|s| s.as_str()).collect();
    let (c1, _, e1) = geardyn_env(&aa, "1");
    let (c2, _, e2) = geardyn_env(&ba, "2");
    assert_eq!((c1, c2), (0, 0), "{e1}{e2}");
    for f in ["bifurcation.csv", "runs.csv"] {
        let x = std::fs::read(a.join(f)).unwrap();
        assert_eq!(
            x,
            std::fs::read(b.join(f)).unwrap(),
            "{f} differs between 1 and 2 threads"
        );
    }
    assert!(a.join("bifurcation.png").exists() && a.join("bifurcation.svg").exists());
    // a rerun resumes from the checkpoint and reproduces the same bytes
    let before = std::fs::read(a.join("bifurcation.csv")).unwrap();
    let (c3, _, e3) = geardyn_env(&aa, "2");
    assert_eq!(c3, 0);
    assert!(e3.contains("resuming: 9 items"), "{e3}");
    assert_eq!(before, std::fs::read(a.join("bifurcation.csv")).unwrap());
    // an interrupted run (checkpoint truncated to a few tasks, last line torn) completes the rest
    let cp = a.join("checkpoint.jsonl");
    let text = std::fs::read_to_string(&cp).unwrap();
    let keep: Vec<&str> = text.lines().take(4).collect();
    std::fs::write(&cp, format!("{}\n{{\"task\":", keep.join("\n"))).unwrap();
    let (c4, _, e4) = geardyn_env(&aa, "2");
    assert_eq!(c4, 0, "{e4}");
    assert!(e4.contains("resuming: 3 items"), "{e4}");
    assert_eq!(before, std::fs::read(a.join("bifurcation.csv")).unwrap());
}

#[test]
fn lyapunov_and_response_commands() {
    let out = geardyn_ok(&[
        "lyapunov",
        "--set",
        "omega=1.3",
        "--periods",
        "200",
        "--transient",
        "100",
    ]);
    assert!(
        out.contains("variational") && out.contains("two-trajectory"),
        "{out}"
    );
    let d = tmp("resp");
    let out = geardyn_ok(&[
        "response",
        "--range",
        "0.7:1.2:11",
        "--periods",
        "20",
        "--out",
        d.to_str().unwrap(),
    ]);
    assert!(out.contains("both sweeps"));
    let csv = std::fs::read_to_string(d.join("response.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 22);
    // every runs table states the verdict's evidence and length (the response's too), and the
    // folder has the runs table of every sweep
    let head = csv.lines().next().unwrap();
    assert!(
        head.ends_with(",class,decided_by,periods_integrated"),
        "{head}"
    );
    let runs = std::fs::read_to_string(d.join("runs.csv")).unwrap();
    assert!(runs.lines().next().unwrap().contains("decided_by"));
    assert_eq!(runs.lines().count(), 1 + 22);
    assert!(d.join("response.png").exists() && d.join("jumps.json").exists());
    let (code, _, err) = geardyn(&[
        "bifurcation",
        "--range",
        "1:2",
        "--out",
        d.to_str().unwrap(),
    ]);
    assert_ne!(code, 0);
    assert!(err.contains("START:STOP:COUNT"), "{err}");
    let (code, _, err) = geardyn(&[
        "bifurcation",
        "--sections",
        "strobe,foo",
        "--out",
        d.to_str().unwrap(),
    ]);
    assert_ne!(code, 0);
    assert!(err.contains("unknown section 'foo'"), "{err}");
}

#[test]
fn stiffness_command_and_physical_show() {
    let d = tmp("stiff");
    let out = geardyn_ok(&[
        "stiffness",
        "--preset",
        "breakage",
        "--out",
        d.to_str().unwrap(),
    ]);
    assert!(out.contains("eps_b"), "{out}");
    let csv = std::fs::read_to_string(d.join("stiffness.csv")).unwrap();
    assert!(csv.starts_with("position_cycles,k_pair1_N_per_m"));
    assert!(csv.lines().count() > 40 * 1024);
    assert!(d.join("mesh_stiffness.png").exists() && d.join("pairs_sharing_friction.svg").exists());
    let (code, out, _) = geardyn(&["show", "--preset", "internal"]);
    assert_eq!(code, 0);
    assert!(
        out.contains("k_av = 4.0000e8") && out.contains("rpm"),
        "{out}"
    );
    // physical fields can be overridden, and bad ones are named
    let (code, out, _) = geardyn(&[
        "show",
        "--preset",
        "breakage",
        "--set",
        "pair.breakage.removed_height_mm=0.5",
    ]);
    assert_eq!(code, 0);
    assert!(out.contains("removed_height_mm = 0.5"));
    let (code, _, err) = geardyn(&[
        "show",
        "--preset",
        "breakage",
        "--set",
        "pair.face_width_mm=-3",
    ]);
    assert_ne!(code, 0);
    assert!(
        err.contains("face_width_mm") && err.contains("[1e-2, 1e4] mm"),
        "{err}"
    );
    let (code, _, err) = geardyn(&["simulate", "--preset", "breakage", "--set", "mu=0.3"]);
    assert_ne!(code, 0);
    assert!(err.contains("pair.mu"), "{err}");
}

#[test]
fn basins_continuation_and_map_commands() {
    let d = tmp("basins");
    let out = geardyn_ok(&[
        "basins",
        "--set",
        "omega=1.8",
        "--grid",
        "x:-3:3:24",
        "--grid",
        "v:-2:2:24",
        "--transient",
        "200",
        "--periods",
        "24",
        "--out",
        d.to_str().unwrap(),
    ]);
    assert!(
        out.contains("attractor #0") && out.contains("attractor #1"),
        "{out}"
    );
    for f in [
        "basins.csv",
        "basins.npy",
        "attractors.json",
        "basins.png",
        "basins.svg",
    ] {
        assert!(d.join(f).exists(), "{f}");
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("attractors.json")).unwrap()).unwrap();
    let sum: f64 = json["attractors"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| a["fraction"].as_f64().unwrap())
        .sum::<f64>()
        + json["diverged"].as_f64().unwrap()
        + json["failed"].as_f64().unwrap();
    assert!((sum - 1.0).abs() < 1e-12);
    let (code, _, err) = geardyn(&["basins", "--grid", "y:0:1:4", "--out", d.to_str().unwrap()]);
    assert_ne!(code, 0);
    assert!(err.contains("--grid"), "{err}");

    let c = tmp("cont");
    let out = geardyn_ok(&[
        "continuation",
        "--range",
        "1.75:1.85:3",
        "--ics",
        "12",
        "--transient",
        "200",
        "--periods",
        "24",
        "--out",
        c.to_str().unwrap(),
    ]);
    assert!(out.contains("healthy {"), "{out}");
    assert!(
        c.join("continuation.csv").exists()
            && c.join("continuation.json").exists()
            && c.join("continuation.png").exists()
    );

    let m = tmp("map");
    let out = geardyn_ok(&[
        "map2d",
        "--x",
        "xi:0.05:0.3:3",
        "--y",
        "F:0.02:0.2:3",
        "--transient",
        "100",
        "--periods",
        "10",
        "--out",
        m.to_str().unwrap(),
    ]);
    assert!(out.contains("max_force in"), "{out}");
    let map = std::fs::read_to_string(m.join("map.csv")).unwrap();
    assert_eq!(map.lines().count(), 10);
    assert!(
        map.lines()
            .next()
            .unwrap()
            .ends_with(",class,decided_by,periods_integrated"),
        "{map}"
    );
    assert!(
        map.lines().skip(1).all(|l| !l.ends_with(",error,0")),
        "{map}"
    );
    let (code, _, err) = geardyn(&["map2d", "--metric", "nope", "--out", m.to_str().unwrap()]);
    assert_ne!(code, 0);
    assert!(err.contains("max_force"), "{err}");
}

#[test]
fn the_built_in_numba_yardstick_is_the_project_one() {
    // the copy bench runs by default must be the shared reference script, byte for byte (when
    // the shared folder sits beside the checkout, as in CI)
    let here = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let ours = std::fs::read_to_string(here.join("bench/c1_numba_rk4.py")).unwrap();
    assert!(ours.contains("def bifurcation_rk4"));
    let shared = here.join("../../../shared/bench/c1_numba_rk4.py");
    match std::fs::read_to_string(&shared) {
        Ok(s) => assert_eq!(
            ours,
            s,
            "crates/cli/bench/c1_numba_rk4.py differs from {}",
            shared.display()
        ),
        Err(_) => eprintln!("{} not present: compared nothing", shared.display()),
    }
}

#[test]
fn report_takes_the_decision_flags() {
    // the quick classic page at a horizon of 200 periods instead of the quick 1000: every
    // chaotic run's escape test had the exposure of two horizons at least (its lifetime bound is
    // 400 / ln 20 = 133.5 or more), and the page says so
    let d = tmp("report-decision");
    geardyn_ok(&[
        "report",
        "--preset",
        "classic",
        "--quick",
        "--decision-periods",
        "200",
        "--out",
        d.to_str().unwrap(),
    ]);
    let runs = std::fs::read_to_string(d.join("classic/bifurcation/bif_omega_runs.csv")).unwrap();
    let header: Vec<&str> = runs.lines().next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (by, class, life) = (col("decided_by"), col("class"), col("lifetime"));
    let chaotic: Vec<f64> = runs
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect::<Vec<_>>())
        .filter(|f| f[class] == "chaotic")
        .map(|f| {
            assert_eq!(f[by], "escape");
            f[life].parse().unwrap()
        })
        .collect();
    assert!(!chaotic.is_empty());
    assert!(chaotic.iter().all(|&l| l >= 133.5), "{chaotic:?}");
    let page = std::fs::read_to_string(d.join("classic/index.html")).unwrap();
    assert!(page.contains("a horizon of 200 excitation periods"));
    // the page's configuration states the horizon its runs were decided at
    let cfg = std::fs::read_to_string(d.join("classic/config.toml")).unwrap();
    assert!(cfg.contains("decision_periods = 200"), "{cfg}");
    // given twice: refused, naming both
    let (code, _, err) = geardyn(&[
        "report",
        "--decision-periods",
        "100",
        "--set",
        "decision_periods=200",
        "--out",
        d.to_str().unwrap(),
    ]);
    assert_ne!(code, 0);
    assert!(err.contains("given twice"), "{err}");
}

/// A box of random initial states wholly behind the broken pair's rigid back stop holds no state
/// of the model: multi-initial sweeps and continuations refuse it up front.
#[test]
fn initial_states_wholly_behind_the_back_stop_are_refused() {
    for cmd in [vec!["bifurcation", "--mode", "multi"], vec!["continuation"]] {
        let out = tmp(&format!("behind-{}", cmd[0]));
        let mut args = cmd.clone();
        args.extend([
            "--preset",
            "breakage",
            "--param",
            "F",
            "--range",
            "0.05:0.1:2",
            "--ics",
            "2",
            "--x0-range=-3:-2",
            "--out",
        ]);
        args.push(out.to_str().unwrap());
        let (code, _, err) = geardyn(&args);
        assert!(
            code != 0 && err.contains("behind the rigid back stop"),
            "{cmd:?}: {err}"
        );
    }
}
