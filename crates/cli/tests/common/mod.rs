//! Helpers shared by the tests of the `geardyn` binary (each test file uses some of them).
#![allow(dead_code)]

use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The binary under test.
pub fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_geardyn"))
}

/// Exit code (-1 when killed by a signal), stdout and stderr of a finished command.
pub fn outcome(out: Output) -> (i32, String, String) {
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Runs `geardyn args` to its end: exit code, stdout, stderr.
pub fn geardyn<S: AsRef<OsStr>>(args: &[S]) -> (i32, String, String) {
    outcome(bin().args(args).output().unwrap())
}

/// Runs `geardyn args`, which must succeed (else the test fails with its stderr): its stdout.
pub fn geardyn_ok<S: AsRef<OsStr>>(args: &[S]) -> String {
    let (code, stdout, stderr) = geardyn(args);
    assert_eq!(code, 0, "{stderr}");
    stdout
}

/// A path `geardyn-TAG-PID-NAME` in the temporary folder, with nothing there.
pub fn tmp(tag: &str, name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("geardyn-{tag}-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// Owned arguments of a command line.
pub fn strs(v: &[&str]) -> Vec<String> {
    v.iter().map(|s| s.to_string()).collect()
}

/// A path as a command-line argument.
pub fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}
