//! Output folders as a hostile user meets them: links and foreign files in the way, two writers,
//! FIFOs and endless files given as inputs, damaged caches. Each test fails without its rule.

mod common;
use common::s;

/// A fresh path for this file's test `name`.
fn tmp(name: &str) -> std::path::PathBuf {
    common::tmp("folders", name)
}

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Exit code and stderr of `geardyn args` (no input).
fn geardyn(args: &[&str]) -> (i32, String) {
    let out = common::bin().args(args).stdin(Stdio::null()).output();
    let (code, _, err) = common::outcome(out.unwrap());
    (code, err)
}

/// A short run of classic into `out`: exit code and stderr.
fn simulate_classic(out: &Path) -> (i32, String) {
    geardyn(&[
        "simulate",
        "--preset",
        "classic",
        "--periods",
        "3",
        "--out",
        s(out),
    ])
}

/// A fresh folder for the test `name` and its `out` holding a finished short run of classic.
fn simulated_folder(name: &str) -> (PathBuf, PathBuf) {
    let d = tmp(name);
    let out = d.join("out");
    assert_eq!(simulate_classic(&out).0, 0);
    (d, out)
}

#[test]
fn a_link_in_the_output_folder_is_refused_and_its_target_untouched() {
    let (d, out) = simulated_folder("link");
    let outside = d.join("precious.txt");
    std::fs::write(&outside, "precious").unwrap();
    for name in [
        "summary.json",
        "trajectory.csv",
        "config.toml",
        "run.json",
        "time_history.png",
    ] {
        let link = out.join(name);
        std::fs::remove_file(&link).unwrap();
        std::os::unix::fs::symlink(&outside, &link).unwrap();
        let (code, err) = simulate_classic(&out);
        assert_ne!(code, 0, "{name}");
        assert!(err.contains("symbolic link"), "{name}: {err}");
        assert_eq!(
            std::fs::read_to_string(&outside).unwrap(),
            "precious",
            "{name}"
        );
        std::fs::remove_file(&link).unwrap();
    }
    std::fs::remove_dir_all(d).ok();
}

#[test]
fn a_folder_geardyn_did_not_make_is_refused() {
    let d = tmp("foreign");
    std::fs::create_dir_all(&d).unwrap();
    std::fs::write(d.join("summary.json"), "my own notes").unwrap();
    let (code, err) = geardyn(&["simulate", "--preset", "classic", "--out", s(&d)]);
    assert_ne!(code, 0);
    assert!(err.contains("did not write"), "{err}");
    assert_eq!(
        std::fs::read_to_string(d.join("summary.json")).unwrap(),
        "my own notes"
    );
    let (code, err) = geardyn(&["simulate", "--preset", "classic", "--out", "/"]);
    assert_ne!(code, 0);
    assert!(err.contains("did not write"), "{err}");
    std::fs::remove_dir_all(d).ok();
}

#[test]
fn one_writer_per_folder_and_a_stale_lock_is_taken_over() {
    let d = tmp("lock");
    let mut first = common::bin()
        .args([
            "simulate",
            "--preset",
            "breakage",
            "--periods",
            "400",
            "--out",
            s(&d),
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let t = Instant::now();
    while !d.join(".geardyn.lock").exists() && t.elapsed() < Duration::from_secs(20) {
        std::thread::sleep(Duration::from_millis(10));
    }
    let (code, err) = geardyn(&["simulate", "--preset", "classic", "--out", s(&d)]);
    let _ = first.kill();
    let _ = first.wait();
    assert_ne!(code, 0);
    assert!(err.contains("in use by another geardyn run"), "{err}");
    // the killed run left its lock: stale (no such process), taken over
    assert!(d.join(".geardyn.lock").exists());
    let (code, err) = simulate_classic(&d);
    assert_eq!(code, 0, "{err}");
    assert!(!d.join(".geardyn.lock").exists());
    std::fs::remove_dir_all(d).ok();
}

#[test]
fn fifos_and_endless_files_as_inputs_are_refused_at_once() {
    let d = tmp("fifo");
    std::fs::create_dir_all(&d).unwrap();
    let fifo = d.join("config.toml");
    assert!(Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    let t = Instant::now();
    let (code, err) = geardyn(&["simulate", "--config", s(&fifo), "--out", s(&d.join("o"))]);
    assert_ne!(code, 0);
    assert!(err.contains("not a regular file"), "{err}");
    // a checkpoint that is a link to /dev/zero
    let out = d.join("sweep");
    let args = [
        "bifurcation",
        "--preset",
        "classic",
        "--range",
        "0.9:1.1:2",
        "--periods",
        "2",
        "--transient",
        "2",
        "--out",
        s(&out),
    ];
    assert_eq!(geardyn(&args).0, 0);
    std::fs::remove_file(out.join("checkpoint.jsonl")).ok();
    std::os::unix::fs::symlink("/dev/zero", out.join("checkpoint.jsonl")).unwrap();
    let (code, err) = geardyn(&args);
    assert_ne!(code, 0);
    assert!(
        err.contains("symbolic link") || err.contains("not a regular"),
        "{err}"
    );
    assert!(t.elapsed() < Duration::from_secs(30));
    std::fs::remove_dir_all(d).ok();
}

#[test]
fn a_second_force_keeps_the_first_set_aside_checkpoint() {
    let d = tmp("force");
    let run = |range: &str| {
        geardyn(&[
            "bifurcation",
            "--preset",
            "classic",
            "--range",
            range,
            "--periods",
            "2",
            "--transient",
            "2",
            "--force",
            "--out",
            s(&d),
        ])
    };
    assert_eq!(run("0.9:1.1:2").0, 0);
    std::fs::write(d.join("checkpoint.jsonl"), "K-one\n").unwrap();
    assert_eq!(run("0.8:1.1:2").0, 0);
    std::fs::write(d.join("checkpoint.jsonl"), "K-two\n").unwrap();
    assert_eq!(run("0.7:1.1:2").0, 0);
    assert_eq!(
        std::fs::read_to_string(d.join("checkpoint.jsonl.old")).unwrap(),
        "K-one\n"
    );
    assert_eq!(
        std::fs::read_to_string(d.join("checkpoint.jsonl.old.2")).unwrap(),
        "K-two\n"
    );
    std::fs::remove_dir_all(d).ok();
}

#[test]
fn work_above_the_cap_is_refused_at_once_and_the_decision_keeps_its_budget() {
    // 10^6 steps per cycle x 10^6 periods: each knob legal, the product days of work
    let t = Instant::now();
    let (code, err) = geardyn(&[
        "simulate",
        "--preset",
        "classic",
        "--integrator",
        "rk4",
        "--steps-per-cycle",
        "1000000",
        "--periods",
        "1000000",
        "--out",
        s(&tmp("cap")),
    ]);
    assert_ne!(code, 0);
    assert!(
        err.contains("--max-work") && err.contains("4.0e12"),
        "{err}"
    );
    assert!(t.elapsed() < Duration::from_secs(5));
    // at omega = 0.001 a revolution costs ten million evaluations: the extensions and the
    // exponent stay within the decision's budget (they took minutes beyond it)
    let d = tmp("slow");
    let t = Instant::now();
    let out = common::bin()
        .args([
            "simulate",
            "--preset",
            "breakage",
            "--set",
            "omega=0.001",
            "--periods",
            "1",
            "--transient",
            "0",
            "--decision-budget",
            "100000000",
            "--out",
            s(&d),
        ])
        .output()
        .unwrap();
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("work budget"), "{text}");
    assert!(t.elapsed() < Duration::from_secs(60), "{:?}", t.elapsed());
    std::fs::remove_dir_all(d).ok();
}

#[test]
fn a_refusal_comes_before_any_write_and_names_alone_do_not_make_a_folder_ours() {
    // a link anywhere in the folder (here a linked study-like folder) is refused before the run
    // writes anything: a refusal halfway left config.toml of one run beside results of another
    let (d, out) = simulated_folder("early");
    let before = std::fs::read_to_string(out.join("config.toml")).unwrap();
    let outside = d.join("elsewhere");
    std::fs::create_dir_all(&outside).unwrap();
    std::os::unix::fs::symlink(&outside, out.join("linked")).unwrap();
    let (code, err) = geardyn(&[
        "simulate",
        "--preset",
        "classic",
        "--set",
        "omega=1.3",
        "--periods",
        "3",
        "--out",
        s(&out),
    ]);
    assert_ne!(code, 0);
    assert!(err.contains("symbolic link"), "{err}");
    assert_eq!(
        std::fs::read_to_string(out.join("config.toml")).unwrap(),
        before
    );
    assert_eq!(std::fs::read_dir(&outside).unwrap().count(), 0);
    // a user's own file that happens to be called run.json does not make the folder geardyn's
    let mine = d.join("mine");
    std::fs::create_dir_all(&mine).unwrap();
    std::fs::write(mine.join("run.json"), r#"{"my": "notes"}"#).unwrap();
    let (code, err) = geardyn(&["simulate", "--preset", "classic", "--out", s(&mine)]);
    assert_ne!(code, 0);
    assert!(err.contains("did not write"), "{err}");
    assert_eq!(
        std::fs::read_to_string(mine.join("run.json")).unwrap(),
        r#"{"my": "notes"}"#
    );
    assert!(!mine.join(".geardyn").exists());
    // a folder where the lock goes is named as such, not as another run
    let locked = d.join("locked");
    std::fs::create_dir_all(locked.join(".geardyn.lock")).unwrap();
    std::fs::write(locked.join(".geardyn"), "").unwrap();
    let (code, err) = geardyn(&["simulate", "--preset", "classic", "--out", s(&locked)]);
    assert_ne!(code, 0);
    assert!(
        err.contains(".geardyn.lock") && !err.contains("in use"),
        "{err}"
    );
    std::fs::remove_dir_all(d).ok();
}

#[test]
fn a_folder_named_like_a_result_file_is_refused_before_the_run() {
    // it was refused only at its write, after the whole computation
    let (d, out) = simulated_folder("dirnamed");
    std::fs::remove_file(out.join("summary.json")).unwrap();
    std::fs::create_dir_all(out.join("summary.json")).unwrap();
    let t = Instant::now();
    // a run of a minute or more were it not refused at once
    let (code, err) = geardyn(&[
        "simulate",
        "--preset",
        "breakage",
        "--periods",
        "3",
        "--transient",
        "100000",
        "--out",
        s(&out),
    ]);
    assert_ne!(code, 0);
    assert!(err.contains("named like a result file"), "{err}");
    assert!(t.elapsed() < Duration::from_secs(10), "{:?}", t.elapsed());
    std::fs::remove_dir_all(d).ok();
}

#[test]
fn a_report_folder_and_another_commands_folder_never_mix() {
    // the report wrote its pages among simulate's files, and simulate into a report's folder
    let d = tmp("mix");
    let sim = d.join("sim");
    assert_eq!(
        geardyn(&["simulate", "--periods", "3", "--out", s(&sim)]).0,
        0
    );
    let (code, err) = geardyn(&["report", "--preset", "classic", "--quick", "--out", s(&sim)]);
    assert_ne!(code, 0);
    assert!(
        err.contains("holds the results of `geardyn simulate`"),
        "{err}"
    );
    assert!(!sim.join("classic").exists() && !sim.join("index.html").exists());
    // a report root (as the report leaves it: its marker and a record of kind "reports")
    let root = d.join("reports");
    std::fs::create_dir_all(&root).unwrap();
    std::fs::write(root.join(".geardyn"), "geardyn output folder\n").unwrap();
    std::fs::write(
        root.join("run.json"),
        r#"{"kind": "reports", "version": "0.1.0"}"#,
    )
    .unwrap();
    let (code, err) = geardyn(&["simulate", "--periods", "3", "--out", s(&root)]);
    assert_ne!(code, 0);
    assert!(
        err.contains("holds the results of `geardyn reports`"),
        "{err}"
    );
    assert!(!root.join("summary.json").exists());
    // --out naming a file: said so (it was "File exists (os error 17)")
    let file = d.join("a-file");
    std::fs::write(&file, "x").unwrap();
    let (code, err) = geardyn(&["simulate", "--periods", "3", "--out", s(&file)]);
    assert_ne!(code, 0);
    assert!(err.contains("is a file, not a folder"), "{err}");
}

/// `run.json` names the commit the binary was built from: in a git checkout, the checkout's
/// HEAD (a build stamp once stayed at the commit of a build made elsewhere for 122 commits).
#[test]
fn the_run_record_names_the_commit_of_the_build() {
    let head = Command::new("git")
        .args(["rev-parse", "HEAD"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output();
    let Some(head) = head
        .ok()
        .filter(|o| o.status.success())
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
    else {
        return; // not a git checkout: nothing to compare with
    };
    let (_d, out) = simulated_folder("commit");
    let run: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("run.json")).unwrap()).unwrap();
    assert_eq!(run["git_commit"].as_str(), Some(head.as_str()));
}
