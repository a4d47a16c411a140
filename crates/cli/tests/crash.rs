//! kill -9 at any moment of a sweep or a basin computation, including right at resume, loses no
//! finished record and the finished result equals an uninterrupted run byte for byte.

mod common;

/// A fresh path for this file's test `name`.
fn tmp(name: &str) -> std::path::PathBuf {
    common::tmp("crash", name)
}

use std::process::Stdio;
use std::time::Duration;

fn geardyn(args: &[String]) -> std::process::Child {
    common::bin()
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap()
}

fn killed_and_resumed_equals_clean(cmd: &[&str], result: &str, name: &str) {
    let clean = tmp(&format!("{name}-clean"));
    let hurt = tmp(&format!("{name}-hurt"));
    let args = |d: &std::path::Path| -> Vec<String> {
        let mut a: Vec<String> = cmd.iter().map(|s| s.to_string()).collect();
        a.extend(["--out".to_string(), d.to_string_lossy().into_owned()]);
        a
    };
    assert!(geardyn(&args(&clean)).wait().unwrap().success());
    // kill at increasing delays, starting right at (re)start
    for ms in [0u64, 5, 20, 60, 120, 250, 400] {
        let mut c = geardyn(&args(&hurt));
        std::thread::sleep(Duration::from_millis(ms));
        let _ = c.kill(); // SIGKILL
        let _ = c.wait();
    }
    // (the resume's messages are kept: a failure here says why)
    let resumed = common::bin().args(args(&hurt)).output().unwrap();
    let listing: Vec<String> = std::fs::read_dir(&hurt)
        .map(|rd| {
            rd.filter_map(|e| e.ok())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    assert!(
        resumed.status.success(),
        "{name}: the resumed run failed: {}\nfolder: {listing:?}",
        String::from_utf8_lossy(&resumed.stderr)
    );
    assert_eq!(
        std::fs::read(clean.join(result)).unwrap(),
        std::fs::read(hurt.join(result)).unwrap(),
        "{name}: resumed result differs"
    );
    let _ = std::fs::remove_dir_all(&clean);
    let _ = std::fs::remove_dir_all(&hurt);
}

#[test]
fn a_killed_bifurcation_resumes_to_the_same_bytes() {
    killed_and_resumed_equals_clean(
        &[
            "bifurcation",
            "--range",
            "0.8:1.6:24",
            "--periods",
            "20",
            "--transient",
            "100",
        ],
        "bifurcation.csv",
        "bif",
    );
}

#[test]
fn killed_basins_resume_to_the_same_bytes() {
    killed_and_resumed_equals_clean(
        &[
            "basins",
            "--set",
            "omega=1.8",
            "--grid",
            "x:-2:2:24",
            "--grid",
            "v:-1.5:1.5:24",
            "--periods",
            "10",
            "--transient",
            "100",
        ],
        "basins.csv",
        "basins",
    );
}
