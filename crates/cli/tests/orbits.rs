//! `geardyn orbits` as a user meets it: one orbit on every preset, a branch with its
//! bifurcations and figure, and clear refusals of bad settings.

mod common;
use common::{geardyn, geardyn_ok};

/// A fresh path for this file's test `name`.
fn tmp(name: &str) -> std::path::PathBuf {
    common::tmp("orb", name)
}

#[test]
fn one_orbit_on_every_preset_with_its_multipliers_and_record() {
    for preset in ["classic", "breakage", "internal"] {
        let out = tmp(preset);
        let o = out.to_str().unwrap();
        let (code, stdout, stderr) = geardyn(&["orbits", "--preset", preset, "--out", o]);
        assert_eq!(code, 0, "{preset}: {stderr}");
        assert!(stdout.contains("multipliers"), "{stdout}");
        let text = std::fs::read_to_string(out.join("branch.csv")).unwrap();
        let mut lines = text.lines();
        assert_eq!(
            lines.next().unwrap(),
            "branch,x,v,period,label,stable,mu1_re,mu1_im,mu2_re,mu2_im,max_force,p_id"
        );
        let row: Vec<&str> = lines.next().unwrap().split(',').collect();
        assert_eq!(row.len(), 12);
        assert_eq!(
            row[5], "true",
            "{preset}: the default start is the attractor"
        );
        // the label of the orbit's record, without numbers beyond its counts
        assert!(
            row[4].starts_with(&format!("{}-", row[3])),
            "{preset}: {}",
            row[4]
        );
        let run: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("run.json")).unwrap()).unwrap();
        assert_eq!(run["kind"], "orbits");
    }
}

#[test]
fn a_branch_writes_its_bifurcations_and_figure() {
    let out = tmp("branch");
    let o = out.to_str().unwrap();
    let stdout = geardyn_ok(&[
        "orbits",
        "--preset",
        "classic",
        "--set",
        "omega=0.8",
        "--param",
        "omega",
        "--range",
        "0.8:0.95",
        "--diagram",
        "10",
        "--out",
        o,
    ]);
    assert!(stdout.contains("period-doubling"), "{stdout}");
    let b = std::fs::read_to_string(out.join("bifurcations.csv")).unwrap();
    assert!(b.starts_with("kind,omega,branch,x,v,period,mu1_re"), "{b}");
    assert!(
        b.lines().any(|l| l.starts_with("period-doubling,0.87")),
        "{b}"
    );
    let branch = std::fs::read_to_string(out.join("branch.csv")).unwrap();
    assert!(branch.starts_with("omega,branch,x,v"));
    assert!(branch.lines().count() > 10);
    for ext in ["png", "svg"] {
        assert!(
            std::fs::metadata(out.join(format!("branch.{ext}")))
                .unwrap()
                .len()
                > 1000
        );
    }
}

#[test]
fn bad_settings_are_refused_with_the_flag_and_its_range() {
    let out = tmp("bad");
    let o = out.to_str().unwrap();
    for (args, want) in [
        (vec!["--period", "0"], "bad period 0"),
        (vec!["--period", "100000"], "bad period"),
        (vec!["--range", "0.5:1"], "--range needs --param"),
        (vec!["--param", "omega"], "--param needs --range"),
        (vec!["--param", "omega", "--range", "0.5:nan"], "--range"),
        (vec!["--param", "omega", "--range", "1:1"], "--range"),
        (vec!["--param", "nonsense", "--range", "0.5:1"], "nonsense"),
        (
            vec!["--param", "omega", "--range", "0.5:1", "--ds", "-1"],
            "bad ds",
        ),
        (vec!["--rtol", "0.5"], "bad rtol"),
        (vec!["--set", "omega=1.3"], "is chaotic"),
    ] {
        let mut a = vec!["orbits", "--preset", "classic", "--out", o];
        a.extend(args.iter().copied());
        let (code, _, stderr) = geardyn(&a);
        assert_ne!(code, 0, "{args:?} was accepted");
        assert!(stderr.contains(want), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{stderr}");
    }
}
