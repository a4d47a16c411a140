//! Gear trains on the command line: `modes`, `simulate`, `bifurcation`, `basins` and `map2d` with
//! the train presets and a description file, and the errors of bad trains and of commands that
//! run only the pair.

mod common;
use common::{geardyn, geardyn_ok, s};

fn tmp(name: &str) -> std::path::PathBuf {
    common::tmp("trn", name)
}

fn csv_rows(path: &std::path::Path) -> Vec<Vec<String>> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect()
}

#[test]
fn modes_of_every_train_preset_with_their_multiplicities() {
    for (preset, coords, planet) in [("planetary", 5, 2), ("two-stage", 4, 0), ("pair", 2, 0)] {
        let out = tmp(&format!("modes-{preset}"));
        let text = geardyn_ok(&["modes", "--preset", preset, "--out", s(&out)]);
        assert!(text.contains("rigid-body"), "{text}");
        let rows = csv_rows(&out.join("modes.csv"));
        assert_eq!(rows.len(), coords, "{preset}");
        assert_eq!(rows.iter().filter(|r| r[2] == "planet").count(), planet);
        for f in ["system.toml", "modes.json", "campbell.csv", "campbell.png"] {
            assert!(out.join(f).exists(), "{preset}: {f}");
        }
    }
    // four planets: three planet modes of one frequency
    let out = tmp("modes-4");
    geardyn_ok(&["modes", "--set", "stage.planets=4", "--out", s(&out)]);
    let rows = csv_rows(&out.join("modes.csv"));
    let planet: Vec<&Vec<String>> = rows.iter().filter(|r| r[2] == "planet").collect();
    assert_eq!(planet.len(), 3);
    let f0: f64 = planet[0][1].parse().unwrap();
    for r in &planet {
        let f: f64 = r[1].parse().unwrap();
        assert!(r[3] == "3" && (f - f0).abs() < 1e-9 * f0, "{r:?}");
    }
}

#[test]
fn a_written_description_runs_again_and_bad_ones_name_their_field() {
    let out = tmp("desc");
    geardyn_ok(&["modes", "--preset", "two-stage", "--out", s(&out)]);
    let file = out.join("system.toml");
    let again = tmp("desc-again");
    geardyn_ok(&["modes", "--system", s(&file), "--out", s(&again)]);
    assert_eq!(
        std::fs::read_to_string(out.join("modes.csv")).unwrap(),
        std::fs::read_to_string(again.join("modes.csv")).unwrap()
    );
    let text = std::fs::read_to_string(&file).unwrap();
    let bad = tmp("bad.toml");
    std::fs::create_dir_all(bad.parent().unwrap()).unwrap();
    for (edit, want) in [
        (
            text.replacen("\"wheel 1\"", "\"wheel 9\"", 1),
            "mesh[0].gears = \"wheel 1\"",
        ),
        (
            text.replace(
                "gears = [\"pinion 2\", \"output wheel\"]",
                "gears = [\"pinion 2\", \"nowhere\"]",
            ),
            "mesh[1].gears",
        ),
        (
            text.replacen("stiffness_n_per_m = ", "stiffness_n_per_m = -", 1),
            "mesh[0].stiffness_n_per_m",
        ),
        (
            text.replacen("contact_ratio = ", "contact_ratio = 2", 1),
            "mesh[0].contact_ratio",
        ),
        (format!("{text}\nbogus = 1\n"), "bogus"),
    ] {
        std::fs::write(&bad, edit).unwrap();
        let (code, _, err) = geardyn(&["modes", "--system", s(&bad), "--out", s(&tmp("bad-out"))]);
        assert_eq!(code, 2, "{err}");
        assert!(
            err.contains(want) && !err.contains("panicked"),
            "{want}: {err}"
        );
    }
}

#[test]
fn bad_planetary_stages_are_refused() {
    for (set, want) in [
        ("stage.planets=7", "stage.planets = 7"),
        ("stage.planets=5", "interfere"),
        ("stage.ring_teeth=96", "stage.ring_teeth = 96"),
        ("stage.sun_teeth=nan", "stage.sun_teeth"),
        ("stage.module_mm=0", "stage.module_mm = 0"),
        ("omega=-1", "omega = -1"),
    ] {
        for cmd in ["modes", "simulate"] {
            let (code, _, err) = geardyn(&[
                cmd,
                "--preset",
                "planetary",
                "--set",
                set,
                "--out",
                s(&tmp("bad-stage")),
            ]);
            if cmd == "modes" && set.starts_with("omega") {
                continue;
            }
            assert_eq!(code, 2, "{cmd} {set}: {err}");
            assert!(
                err.contains(want) && !err.contains("panicked"),
                "{cmd} {set}: {err}"
            );
        }
    }
    // the pair's commands say that they do not run trains, and which do
    let (code, _, err) = geardyn(&["stiffness", "--preset", "planetary"]);
    assert_eq!(code, 2);
    assert!(
        err.contains("gear train") && err.contains("basins, continuation, orbits, map2d"),
        "{err}"
    );
}

#[test]
fn a_planetary_stage_simulates_and_sweeps_with_one_label_per_mesh() {
    let out = tmp("sim");
    let text = geardyn_ok(&[
        "simulate",
        "--preset",
        "planetary",
        "--periods",
        "20",
        "--transient",
        "200",
        "--out",
        s(&out),
    ]);
    assert!(text.contains("load sharing sun-planet 1"), "{text}");
    let rows = csv_rows(&out.join("meshes.csv"));
    assert_eq!(rows.len(), 6);
    for r in &rows {
        // equal planets, periodic motion: every mesh carries the static force 0.1 on average
        assert!((r[4].parse::<f64>().unwrap() - 0.1).abs() < 1e-12, "{r:?}");
        assert!(r[5].parse::<f64>().unwrap() > 1.0);
    }
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    for l in summary["load_sharing"].as_array().unwrap() {
        assert!((l["factor"].as_f64().unwrap() - 1.0).abs() < 1e-4, "{l}");
    }
    let out = tmp("bif");
    let text = geardyn_ok(&[
        "bifurcation",
        "--preset",
        "planetary",
        "--param",
        "omega",
        "--range",
        "0.5:1.5:6",
        "--periods",
        "10",
        "--transient",
        "100",
        "--out",
        s(&out),
    ]);
    assert!(text.contains("6 values"), "{text}");
    assert_eq!(csv_rows(&out.join("runs.csv")).len(), 6);
    assert!(out.join("bifurcation.png").exists());
    let (code, _, err) = geardyn(&[
        "bifurcation",
        "--preset",
        "planetary",
        "--param",
        "mu",
        "--out",
        s(&tmp("bif-mu")),
    ]);
    assert_eq!(code, 2);
    assert!(
        err.contains("--param mu") && err.contains("omega, F"),
        "{err}"
    );
}

/// `lyapunov` of a train: the single pair written as a train at case C1's chaotic point
/// (`omega` = 1.3: TLE 0.080 by the pair model, docs/analyses.md) gives the pair's exponent; the
/// planetary stage's periodic motion a negative one; the pair's two-trajectory options refused.
#[test]
fn lyapunov_of_a_train_matches_the_pair_model_and_refuses_the_pair_options() {
    let c1 = [
        "--set",
        "omega=1.3",
        "--set",
        "kappa=0.2",
        "--set",
        "xi=0.2",
        "--set",
        "c=0.1",
    ];
    let tle = |text: &str| -> f64 {
        let line = text
            .lines()
            .find(|l| l.starts_with("TLE (variational"))
            .unwrap_or_else(|| panic!("{text}"));
        line.split_whitespace().nth(3).unwrap().parse().unwrap()
    };
    let mut args = vec!["lyapunov", "--preset", "pair", "--periods", "1600"];
    args.extend(c1);
    let pair_as_train = tle(&geardyn_ok(&args));
    assert!((pair_as_train - 0.080).abs() < 0.006, "{pair_as_train}");
    let stage = tle(&geardyn_ok(&["lyapunov", "--preset", "planetary"]));
    assert!(stage < -0.01, "{stage}");
    let (code, _, e) = geardyn(&[
        "lyapunov",
        "--preset",
        "planetary",
        "--method",
        "two-trajectory",
    ]);
    assert!(code != 0 && e.contains("variational"), "{e}");
    let (code, _, e) = geardyn(&["lyapunov", "--preset", "planetary", "--d0", "1e-4"]);
    assert!(code != 0 && e.contains("--d0"), "{e}");
}

/// A planet pin error through the preset field: planet 1 unloads, the others share its load
/// (the closed form is tested in the analysis crate); out of range refused by name.
#[test]
fn a_pin_error_unloads_its_planet() {
    let out = tmp("pin-error");
    geardyn_ok(&[
        "simulate",
        "--preset",
        "planetary",
        "--set",
        "stage.pin_error=0.04",
        "--out",
        s(&out),
    ]);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let f: Vec<f64> = json["static_forces"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    assert!(f[0] < 0.09 && f[2] > 0.105, "{f:?}");
    assert!(std::fs::read_to_string(out.join("system.toml"))
        .unwrap()
        .contains("pin_error = 0.04"));
    let (code, _, e) = geardyn(&[
        "simulate",
        "--preset",
        "planetary",
        "--set",
        "stage.pin_error=-1e9",
    ]);
    assert!(code == 2 && e.contains("stage.pin_error"), "{e}");
}

/// A pin error that unloads its planet: the static forces are those of the two other planets
/// sharing the load (not the linear formula's negative one), the unloaded planet's dynamic factor
/// is empty; an error that jams the planet is refused by name; lyapunov's lengths as for the pair.
#[test]
fn an_unloaded_planet_and_a_jammed_one() {
    let out = tmp("pin-unloaded");
    geardyn_ok(&[
        "simulate",
        "--preset",
        "planetary",
        "--set",
        "stage.pin_error=0.3",
        "--out",
        s(&out),
    ]);
    let rows = csv_rows(&out.join("meshes.csv"));
    assert_eq!(rows[0][4], "0", "{rows:?}");
    assert_eq!(rows[0][5], "", "{rows:?}");
    let f: f64 = rows[2][4].parse().unwrap();
    assert!((f - 0.15).abs() < 1e-9, "{rows:?}");
    let (code, _, e) = geardyn(&[
        "simulate",
        "--preset",
        "planetary",
        "--set",
        "stage.pin_error=100",
    ]);
    assert!(
        code == 2 && e.contains("pin_error") && e.contains("jams"),
        "{e}"
    );
    let text = geardyn_ok(&["lyapunov", "--preset", "planetary", "--periods", "5"]);
    assert!(text.contains("over 5 periods"), "{text}");
    let (code, _, e) = geardyn(&["lyapunov", "--preset", "planetary", "--max-periods", "0"]);
    assert!(code == 2 && e.contains("--max-periods"), "{e}");
}

/// `show` of a train prints the resolved description, which runs again as `--system`, and as
/// comments the operating point, the speeds and each mesh's static force.
#[test]
fn show_prints_a_train_resolved() {
    let text = geardyn_ok(&[
        "show",
        "--preset",
        "planetary",
        "--set",
        "stage.pin_error=0.04",
        "--set",
        "F=0.2",
    ]);
    assert!(text.contains("pin_error = 0.04"), "{text}");
    // the operating point is part of the description: `--system` runs it again
    assert!(
        text.contains("[operating]") && text.contains("load = 0.2"),
        "{text}"
    );
    assert!(text.contains("#   carrier"), "{text}");
    let file = tmp("show").with_extension("toml");
    std::fs::create_dir_all(file.parent().unwrap()).unwrap();
    std::fs::write(&file, &text).unwrap();
    let again = geardyn_ok(&["show", "--system", s(&file)]);
    assert_eq!(again, text);
    // ... and every train command writes it into its folder, overrides applied
    let out = tmp("show-run");
    geardyn_ok(&[
        "simulate",
        "--system",
        s(&file),
        "--set",
        "omega=1.5",
        "--periods",
        "5",
        "--out",
        s(&out),
    ]);
    let sys = std::fs::read_to_string(out.join("system.toml")).unwrap();
    assert!(
        sys.contains("omega = 1.5") && sys.contains("load = 0.2"),
        "{sys}"
    );
    let run: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("run.json")).unwrap()).unwrap();
    assert_eq!(run["kind"], "simulate");
    assert_eq!(run["system"]["operating"]["omega"], 1.5);
    // so that another command's outputs are refused there
    let (code, _, e) = geardyn(&["basins", "--system", s(&file), "--out", s(&out)]);
    assert!(code == 2 && e.contains("geardyn simulate"), "{e}");
    let (code, _, e) = geardyn(&["show", "--preset", "planetary", "--set", "stage.planets=7"]);
    assert!(code == 2 && e.contains("stage.planets"), "{e}");
}

/// The attractor column of a basins.csv.
fn basin_cells(out: &std::path::Path) -> Vec<String> {
    csv_rows(&out.join("basins.csv"))
        .into_iter()
        .map(|r| r[2].clone())
        .collect()
}

/// The single pair written as a train has the pair's basins on its mesh's plane (case C1 at
/// omega = 2: a healthy 1-1-0 orbit beside a 3-1-1 orbit with back-side contacts), cell for
/// cell; a planetary stage's basins lie on the mesh named by `--mesh`.
#[test]
fn basins_of_a_train_on_a_mesh_plane() {
    let grid = ["--grid", "x:-2:2:16", "--grid", "v:-1.5:1.5:16"];
    let (pair, train) = (tmp("basins-c1"), tmp("basins-pair"));
    let mut a = vec!["basins", "--preset", "classic", "--set", "omega=2"];
    a.extend(grid);
    a.extend(["--out", s(&pair)]);
    let text_pair = geardyn_ok(&a);
    let mut b = vec![
        "basins",
        "--preset",
        "pair",
        "--set",
        "kappa=0.2",
        "--set",
        "xi=0.2",
        "--set",
        "omega=2",
    ];
    b.extend(grid);
    b.extend(["--out", s(&train)]);
    let text_train = geardyn_ok(&b);
    assert!(
        text_pair.contains("3-1-1") && text_train.contains("3-1-1"),
        "{text_train}"
    );
    assert_eq!(basin_cells(&pair), basin_cells(&train));
    let js: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(train.join("attractors.json")).unwrap())
            .unwrap();
    assert_eq!(js["mesh"], "mesh");
    // a planetary stage on its second mesh; a mesh that does not exist, --mesh on the pair
    let out = tmp("basins-planetary");
    let text = geardyn_ok(&[
        "basins",
        "--preset",
        "planetary",
        "--set",
        "xi=0.1",
        "--mesh",
        "ring-planet 1",
        "--grid",
        "x:-2:2:6",
        "--grid",
        "v:-1:1:6",
        "--periods",
        "20",
        "--transient",
        "100",
        "--out",
        s(&out),
    ]);
    assert!(text.contains("attractor #0"), "{text}");
    let js: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("attractors.json")).unwrap())
            .unwrap();
    assert_eq!(js["mesh"], "ring-planet 1");
    assert!(out.join("basins.png").exists() && out.join("system.toml").exists());
    let (code, _, err) = geardyn(&["basins", "--preset", "planetary", "--mesh", "7"]);
    assert_eq!(code, 2);
    assert!(
        err.contains("--mesh 7") && err.contains("'sun-planet 1'"),
        "{err}"
    );
    let (code, _, err) = geardyn(&["basins", "--preset", "classic", "--mesh", "1"]);
    assert_eq!(code, 2);
    assert!(err.contains("--mesh"), "{err}");
}

/// A train's two-parameter map: the single pair written as a train gives the pair's map (labels,
/// peak forces to the force extremes' accuracy); a planetary stage's has a column per mesh and
/// load-sharing factors of at least 1, and resumes from its folder.
#[test]
fn maps_of_a_train_with_columns_per_mesh() {
    // (both from the static deflection: the pair's x0 = D + F; at omega = 1.2, F = 0.15 a 2-1-0
    // orbit coexists with the 2-2-0 one that the static state leads to)
    let axes = [
        "--x",
        "omega:0.8:1.6:3",
        "--y",
        "xi:0.1:0.2:2",
        "--set",
        "F=0.15",
    ];
    let (pair, train) = (tmp("map-c1"), tmp("map-pair"));
    let mut a = vec!["map2d", "--preset", "classic", "--set", "x0=1.15"];
    a.extend(axes);
    a.extend(["--out", s(&pair)]);
    geardyn_ok(&a);
    let mut b = vec![
        "map2d",
        "--preset",
        "pair",
        "--set",
        "kappa=0.2",
        "--set",
        "xi=0.2",
    ];
    b.extend(axes);
    b.extend(["--out", s(&train)]);
    geardyn_ok(&b);
    let (rp, rt) = (
        csv_rows(&pair.join("map.csv")),
        csv_rows(&train.join("map.csv")),
    );
    assert_eq!(rp.len(), 6);
    for (p, t) in rp.iter().zip(&rt) {
        // omega, F, label, period, healthy, max_force (of a periodic motion: a chaotic one's
        // record differs with the trajectory)
        assert_eq!(p[..5], t[..5]);
        let (fp, ft): (f64, f64) = (p[5].parse().unwrap(), t[5].parse().unwrap());
        assert!(p[3] == "0" || (fp - ft).abs() < 1e-4 * fp, "{p:?} {t:?}");
    }
    assert!(rp.iter().filter(|r| r[3] != "0").count() >= 3, "{rp:?}");
    let out = tmp("map-planetary");
    let args = [
        "map2d",
        "--preset",
        "planetary",
        "--set",
        "xi=0.1",
        "--x",
        "omega:0.9:1.3:2",
        "--y",
        "F:0.05:0.1:2",
        "--metric",
        "load_sharing",
        "--periods",
        "20",
        "--out",
        s(&out),
    ];
    geardyn_ok(&args);
    let text = std::fs::read_to_string(out.join("map.csv")).unwrap();
    let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    assert!(header.contains(&"max_force ring-planet 3") && header.contains(&"load_sharing_max"));
    let col = header
        .iter()
        .position(|h| *h == "load_sharing_max")
        .unwrap();
    for r in csv_rows(&out.join("map.csv")) {
        let f: f64 = r[col].parse().unwrap();
        assert!(f >= 1.0 - 1e-9, "{r:?}");
    }
    assert!(out.join("map.png").exists() && out.join("map.npy").exists());
    let (code, _, err) = geardyn(&args);
    assert_eq!(code, 0);
    assert!(err.contains("resuming: 4 items"), "{err}");
    let (code, _, err) = geardyn(&["map2d", "--preset", "planetary", "--metric", "tle"]);
    assert_eq!(code, 2);
    assert!(err.contains("load_sharing"), "{err}");
}

/// A train's attractor continuation: the single pair written as a train continues the pair's
/// attractors (the same initial states on its mesh's plane: the same table); a stiffness form
/// swept beside a `--set` of the other is refused.
#[test]
fn continuation_of_a_train_on_a_mesh_plane() {
    let args = ["--range", "1.6:2.4:3", "--ics", "8"];
    let (pair, train) = (tmp("cont-c1"), tmp("cont-pair"));
    let mut a = vec!["continuation", "--preset", "classic"];
    a.extend(args);
    a.extend(["--out", s(&pair)]);
    geardyn_ok(&a);
    let mut b = vec![
        "continuation",
        "--preset",
        "pair",
        "--set",
        "kappa=0.2",
        "--set",
        "xi=0.2",
    ];
    b.extend(args);
    b.extend(["--out", s(&train)]);
    geardyn_ok(&b);
    let cut = |out: &std::path::Path| -> Vec<Vec<String>> {
        csv_rows(&out.join("continuation.csv"))
            .into_iter()
            .map(|r| r[..6].to_vec())
            .collect()
    };
    let rows = cut(&pair);
    assert!(rows.len() >= 4, "{rows:?}");
    assert_eq!(rows, cut(&train));
    assert!(rows.iter().any(|r| r[2] == "chaotic") && rows.iter().any(|r| r[2] == "1-1-0"));
    let (code, _, e) = geardyn(&[
        "continuation",
        "--preset",
        "planetary",
        "--set",
        "kappa=0.2",
        "--param",
        "ratio",
    ]);
    assert!(code == 2 && e.contains("--set kappa"), "{e}");
}

/// A map's cells that have no result (a pin error the backlash cannot take up: the planet jams)
/// are failed, with no forces.
#[test]
fn a_train_map_marks_cells_without_a_result_failed() {
    let out = tmp("map-jam");
    geardyn_ok(&[
        "map2d",
        "--preset",
        "planetary",
        "--set",
        "stage.pin_error=0.5",
        "--x",
        "D:0.1:1:2",
        "--y",
        "F:0.05:0.2:2",
        "--periods",
        "20",
        "--out",
        s(&out),
    ]);
    let text = std::fs::read_to_string(out.join("map.csv")).unwrap();
    let jammed: Vec<&str> = text.lines().filter(|l| l.starts_with("0.1,")).collect();
    assert_eq!(jammed.len(), 2, "{text}");
    for l in jammed {
        assert!(
            l.contains("jams") && l.contains(",false,,,,0,,failed,"),
            "{l}"
        );
    }
}

/// A train's periodic orbits: the single pair written as a train has the pair's orbit and
/// multipliers (C1 at omega = 0.8), and its orbit followed over omega turns unstable by a flip
/// between the two values that bracket the pair's located period doubling (omega = 0.877).
#[test]
fn orbits_of_a_train_match_the_pair_and_find_its_doubling() {
    let c1 = ["--set", "kappa=0.2", "--set", "xi=0.2"];
    let out = tmp("orbit-pair");
    let mut a = vec!["orbits", "--preset", "pair", "--set", "omega=0.8"];
    a.extend(c1);
    a.extend(["--out", s(&out)]);
    let text = geardyn_ok(&a);
    assert!(
        text.contains("stable") && text.contains("label 1-1-0"),
        "{text}"
    );
    let pair = tmp("orbit-c1");
    let text_pair = geardyn_ok(&[
        "orbits",
        "--preset",
        "classic",
        "--set",
        "omega=0.8",
        "--out",
        s(&pair),
    ]);
    // the deflection and the leading multiplier, to the digits printed
    let x = |t: &str, key: &str| -> f64 {
        let i = t.find(key).unwrap() + key.len();
        t[i..]
            .split([',', ' ', ';'])
            .find(|w| !w.is_empty())
            .unwrap()
            .parse()
            .unwrap()
    };
    assert!(
        (x(&text, "deflection ") - x(&text_pair, "x = ")).abs() < 1e-6,
        "{text}\n{text_pair}"
    );
    assert!(text.contains("multipliers -0.687358+0.487060i"), "{text}");
    assert!(
        text_pair.contains("multipliers -0.687358+0.487060i"),
        "{text_pair}"
    );
    // over omega
    let out = tmp("orbits-pair-omega");
    let mut b = vec![
        "orbits",
        "--preset",
        "pair",
        "--param",
        "omega",
        "--range",
        "0.6:1.2:13",
    ];
    b.extend(c1);
    b.extend(["--out", s(&out)]);
    let text = geardyn_ok(&b);
    assert!(
        text.contains("between omega = 0.85 and 0.9: period doubling (flip)"),
        "{text}"
    );
    let pair = tmp("orbits-c1-omega");
    let text_pair = geardyn_ok(&[
        "orbits",
        "--preset",
        "classic",
        "--param",
        "omega",
        "--range",
        "0.6:1.2",
        "--diagram",
        "0",
        "--out",
        s(&pair),
    ]);
    let at = x(
        &text_pair,
        "period-doubling of the period-1 branch at omega = ",
    );
    assert!(at > 0.85 && at < 0.9, "{text_pair}");
    let rows = csv_rows(&out.join("branch.csv"));
    assert_eq!(rows.len(), 13);
    assert!(out.join("branch.png").exists() && out.join("run.json").exists());
    // the pair's branch switching is refused, an unknown parameter named
    let (code, _, e) = geardyn(&["orbits", "--preset", "planetary", "--switch-up-to", "4"]);
    assert!(code == 2 && e.contains("--switch-up-to"), "{e}");
    let (code, _, e) = geardyn(&[
        "orbits",
        "--preset",
        "planetary",
        "--param",
        "eps",
        "--range",
        "1:2",
    ]);
    assert!(code == 2 && e.contains("--param eps"), "{e}");
}

/// A train's frequency response: the single pair written as a train has the pair's up and down
/// sweeps (both from the static deflection, the pair's `x0 = 1 + F - xi`), label by label
/// through the chaotic band and over the coexistence of C1's 3-1-1 and 1-1-0 orbits above it
/// (below omega = 1.1 the down sweep crosses fractal basins: labels there may differ with the
/// last digits), and says where the sweeps end on different motions.
#[test]
fn response_of_a_train_shows_the_pairs_hysteresis() {
    let (pair, train) = (tmp("resp-c1"), tmp("resp-pair"));
    let range = ["--range", "0.5:2:31"];
    let mut a = vec!["response", "--preset", "classic", "--set", "x0=0.9"];
    a.extend(range);
    a.extend(["--out", s(&pair)]);
    geardyn_ok(&a);
    let mut b = vec![
        "response",
        "--preset",
        "pair",
        "--set",
        "kappa=0.2",
        "--set",
        "xi=0.2",
    ];
    b.extend(range);
    b.extend(["--out", s(&train)]);
    let text = geardyn_ok(&b);
    assert!(text.contains("different motions"), "{text}");
    let labels = |path: &std::path::Path, label_col: usize| -> Vec<(String, String, String)> {
        let mut v: Vec<(String, String, String)> = csv_rows(path)
            .into_iter()
            .filter(|r| r[0].parse::<f64>().unwrap() >= 1.1)
            .map(|r| (r[0].clone(), r[1].clone(), r[label_col].clone()))
            .collect();
        v.sort();
        v
    };
    // runs.csv: omega, branch, ic, x0, v0, class, label; response.csv: omega, sweep, class, label
    let (p, t) = (
        labels(&pair.join("runs.csv"), 6),
        labels(&train.join("response.csv"), 3),
    );
    assert_eq!(p, t);
    assert!(
        t.contains(&("2".into(), "up".into(), "3-1-1".into())),
        "{t:?}"
    );
    assert!(
        t.contains(&("2".into(), "down".into(), "1-1-0".into())),
        "{t:?}"
    );
    let js: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(train.join("jumps.json")).unwrap()).unwrap();
    assert!(js["coexisting"].as_array().unwrap().len() >= 4, "{js}");
    assert!(train.join("response.png").exists() && train.join("run.json").exists());
}
