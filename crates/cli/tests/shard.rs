//! Sharded plans (issue 32): a C1 map planned in 4 shards, run as 4 processes at once and merged
//! equals the single-process `geardyn map2d` byte for byte; a shard killed mid-run (or left with
//! partial chunks and no done marker) and run again writes the same bytes; a store of another
//! request or version is refused; bad input is named.

mod common;
use common::{bin, s};

/// A fresh path for this file's test `name`.
fn tmp(name: &str) -> std::path::PathBuf {
    common::tmp("shard", name)
}

use std::path::{Path, PathBuf};
use std::process::{Output, Stdio};
use std::time::Duration;

/// The short runs of every plan here (chaos decided at 300 periods, not 10 000: seconds less per
/// chaotic cell, still 7 of the map's 30).
const SHORT: &[&str] = &[
    "--periods",
    "20",
    "--transient",
    "60",
    "--decision-periods",
    "300",
];

/// The arguments of the map planned here: a 6 x 5 C1 map of short runs.
fn map() -> Vec<&'static str> {
    let grid = [
        "--preset",
        "classic",
        "--x",
        "omega:0.6:1.2:6",
        "--y",
        "F:0.05:0.2:5",
    ];
    [&grid[..], SHORT].concat()
}

fn run(args: &[&str]) -> Output {
    bin().args(args).output().unwrap()
}

fn ok(args: &[&str]) -> String {
    let o = run(args);
    assert!(
        o.status.success(),
        "geardyn {args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn refused(args: &[&str]) -> String {
    let o = run(args);
    assert_eq!(o.status.code(), Some(2), "geardyn {args:?} should fail");
    let e = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(!e.contains("panicked"), "{e}");
    e
}

fn with(base: &[&str], more: &[&str]) -> Vec<String> {
    base.iter().chain(more).map(|x| x.to_string()).collect()
}

fn strs(v: &[String]) -> Vec<&str> {
    v.iter().map(String::as_str).collect()
}

/// Plans `args` (a map2d) in 4 shards into `store`, runs the 4 shards as processes at once.
fn plan_and_run_all(args: &[&str], store: &Path) {
    let plan = with(&["plan", "map2d"], args);
    let plan = with(&strs(&plan), &["--shards", "4", "--out", s(store)]);
    let out = ok(&strs(&plan));
    assert!(out.contains("4 shards"), "{out}");
    let kids: Vec<_> = (0..4)
        .map(|i| {
            bin()
                .args(["run-shard", s(store), "--shard", &i.to_string()])
                .stdout(Stdio::null())
                .spawn()
                .unwrap()
        })
        .collect();
    for mut k in kids {
        assert!(k.wait().unwrap().success());
    }
}

/// Every file of a store's arrays and markers (not the merged folder), path -> bytes.
fn store_files(store: &Path) -> Vec<(String, Vec<u8>)> {
    fn walk(root: &Path, d: &Path, out: &mut Vec<(String, Vec<u8>)>) {
        for e in std::fs::read_dir(d).unwrap() {
            let p = e.unwrap().path();
            // (temporary files of a killed writer: never renamed into the store's names)
            if p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with('.'))
            {
                continue;
            }
            if p.is_dir() {
                walk(root, &p, out);
            } else if p.parent() != Some(root) {
                let rel = p.strip_prefix(root).unwrap().to_string_lossy().into_owned();
                out.push((rel, std::fs::read(&p).unwrap()));
            }
        }
    }
    let mut out = Vec::new();
    walk(store, store, &mut out);
    out.sort();
    out
}

/// Asserts that the `files` of the folders `a` and `b` are the same bytes.
fn same_files(a: &Path, b: &Path, files: &[&str]) {
    for f in files {
        let (x, y) = (
            std::fs::read(a.join(f)).unwrap(),
            std::fs::read(b.join(f)).unwrap(),
        );
        assert!(x == y, "{f} of {} and {} differ", a.display(), b.display());
    }
}

fn single_map(args: &[&str], name: &str) -> PathBuf {
    let single = tmp(name);
    let a = with(&["map2d"], args);
    ok(&strs(&with(&strs(&a), &["--out", s(&single)])));
    single
}

#[test]
fn four_shards_in_parallel_merge_to_the_single_process_map() {
    for (name, extra) in [("dopri", &[][..]), ("rk4", &["--integrator", "rk4"][..])] {
        let args = with(&map(), extra);
        let args = strs(&args);
        let single = single_map(&args, &format!("single-{name}"));
        let store = tmp(&format!("store-{name}"));
        plan_and_run_all(&args, &store);
        let st = ok(&["status", s(&store)]);
        assert!(st.contains("4 done, 0 missing"), "{st}");
        assert_eq!(ok(&["status", s(&store), "--missing"]).trim(), "");
        ok(&["merge", s(&store)]);
        same_files(&store, &single, &["map.csv", "map.npy", "config.toml"]);
        // merge again, elsewhere: the same files (idempotent)
        let other = tmp(&format!("merged-{name}"));
        ok(&["merge", s(&store), "--out", s(&other)]);
        same_files(&other, &single, &["map.csv"]);
        // a done shard is not computed again
        assert!(ok(&["run-shard", s(&store), "--shard", "1"]).contains("done already"));
        for d in [single, store, other] {
            std::fs::remove_dir_all(d).ok();
        }
    }
}

#[test]
fn a_killed_shard_run_again_writes_the_same_bytes() {
    let single = single_map(&map(), "kill-single");
    let clean = tmp("kill-clean");
    plan_and_run_all(&map(), &clean);
    let hurt = tmp("kill-hurt");
    let plan = with(&["plan", "map2d"], &map());
    ok(&strs(&with(
        &strs(&plan),
        &["--shards", "4", "--out", s(&hurt)],
    )));
    // shard 0 killed at several moments of its run
    for ms in [0u64, 10, 30, 60, 150] {
        let mut c = bin()
            .args(["run-shard", s(&hurt), "--shard", "0"])
            .stdout(Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(Duration::from_millis(ms));
        let _ = c.kill();
        let _ = c.wait();
        std::fs::remove_file(hurt.join("shards/0.json")).ok();
    }
    // partial output without a done marker: a chunk of shard 0 half written
    std::fs::create_dir_all(hurt.join("label/c/0")).unwrap();
    std::fs::write(hurt.join("label/c/0/0"), b"\x09\x00\x00").unwrap();
    let st = ok(&["status", s(&hurt)]);
    assert!(st.contains("missing: 0"), "{st}");
    assert!(refused(&["merge", s(&hurt)]).contains("not done"));
    SetSlurm::run_all(&hurt);
    assert_eq!(store_files(&hurt), store_files(&clean));
    ok(&["merge", s(&hurt)]);
    same_files(&hurt, &single, &["map.csv"]);
    for d in [single, clean, hurt] {
        std::fs::remove_dir_all(d).ok();
    }
}

#[test]
fn a_done_shard_whose_chunk_changed_is_damaged_and_runs_again() {
    let clean = tmp("damaged-clean");
    plan_and_run_all(&map(), &clean);
    let hurt = tmp("damaged-hurt");
    plan_and_run_all(&map(), &hurt);
    assert!(ok(&["status", s(&hurt)]).contains("4 done, 0 missing"));
    // a chunk of a finished shard truncated after the shard wrote its marker (a full disk, a
    // copy interrupted): the marker alone no longer makes the shard done
    let chunk = hurt.join("label/c/0/0");
    let bytes = std::fs::read(&chunk).unwrap();
    std::fs::write(&chunk, &bytes[..bytes.len() / 2]).unwrap();
    let st = ok(&["status", s(&hurt)]);
    assert!(st.contains("missing: 0"), "{st}");
    assert!(st.contains("damaged"), "{st}");
    assert_eq!(ok(&["status", s(&hurt), "--missing"]).trim(), "0");
    assert!(refused(&["merge", s(&hurt)]).contains("not done"));
    // run again, the shard rewrites its chunks: the store equals the clean one
    ok(&["run-shard", s(&hurt), "--shard", "0"]);
    assert!(ok(&["status", s(&hurt)]).contains("4 done, 0 missing"));
    assert_eq!(store_files(&hurt), store_files(&clean));
    for d in [clean, hurt] {
        std::fs::remove_dir_all(d).ok();
    }
}

/// The shards of a store run as a Slurm array would: the index from SLURM_ARRAY_TASK_ID.
struct SetSlurm;

impl SetSlurm {
    fn run_all(store: &Path) {
        for i in 0..4 {
            let o = bin()
                .args(["run-shard", s(store)])
                .env("SLURM_ARRAY_TASK_ID", i.to_string())
                .output()
                .unwrap();
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        }
    }
}

#[test]
fn plans_of_another_request_or_version_and_bad_input_are_refused() {
    let store = tmp("refuse");
    let plan = with(&["plan", "map2d"], &map());
    ok(&strs(&with(
        &strs(&plan),
        &["--shards", "4", "--out", s(&store)],
    )));
    // the same plan again: kept
    assert!(ok(&strs(&with(
        &strs(&plan),
        &["--shards", "4", "--out", s(&store)]
    )))
    .contains("holds this plan already"));
    // another configuration into the same store
    let e = refused(&strs(&with(
        &strs(&plan),
        &["--set", "xi=0.07", "--shards", "4", "--out", s(&store)],
    )));
    assert!(e.contains("another request"), "{e}");
    // bad shard counts and indices, missing stores, named
    let e = refused(&strs(&with(
        &strs(&plan),
        &["--shards", "0", "--out", s(&tmp("zero"))],
    )));
    assert!(e.contains("--shards 0"), "{e}");
    let e = refused(&["run-shard", s(&store), "--shard", "4"]);
    assert!(e.contains("--shard 4") && e.contains("4 shards"), "{e}");
    let e = refused(&["run-shard", s(&store)]);
    assert!(e.contains("SLURM_ARRAY_TASK_ID"), "{e}");
    let missing = tmp("missing");
    for cmd in ["status", "merge", "run-shard"] {
        let e =
            refused(&[cmd, s(&missing), "--shard", "0"][..if cmd == "run-shard" { 4 } else { 2 }]);
        assert!(e.contains("STORE") && e.contains("no such folder"), "{e}");
    }
    // an edited request, a corrupt group, another version
    let meta = std::fs::read_to_string(store.join("zarr.json")).unwrap();
    std::fs::write(
        store.join("zarr.json"),
        meta.replace("\"metric\": \"max_force\"", "\"metric\": \"class\""),
    )
    .unwrap();
    let e = refused(&["run-shard", s(&store), "--shard", "0"]);
    assert!(e.contains("edited or corrupt"), "{e}");
    std::fs::write(store.join("zarr.json"), "{not json").unwrap();
    let e = refused(&["status", s(&store)]);
    assert!(e.contains("not a readable geardyn plan"), "{e}");
    std::fs::write(
        store.join("zarr.json"),
        meta.replace(
            &format!("\"version\": \"{}\"", env!("CARGO_PKG_VERSION")),
            "\"version\": \"0.0.1\"",
        ),
    )
    .unwrap();
    let e = refused(&["run-shard", s(&store), "--shard", "0"]);
    assert!(e.contains("planned by geardyn 0.0.1"), "{e}");
    // a continuation sweep cannot be sharded
    let e = refused(&[
        "plan",
        "bifurcation",
        "--mode",
        "sweep",
        "--range",
        "0.5:1:4",
        "--shards",
        "2",
        "--out",
        s(&tmp("sweep")),
    ]);
    assert!(e.contains("--mode sweep"), "{e}");
    std::fs::remove_dir_all(store).ok();
}

#[test]
fn a_multi_initial_bifurcation_in_shards_equals_the_single_process() {
    let sweep = [
        "--preset",
        "classic",
        "--param",
        "F",
        "--range",
        "0.05:0.2:4",
        "--mode",
        "multi",
        "--ics",
        "3",
        "--integrator",
        "rk4",
    ];
    let args = [&sweep[..], SHORT].concat();
    let single = tmp("bif-single");
    ok(&strs(&with(
        &strs(&with(&["bifurcation"], &args)),
        &["--out", s(&single)],
    )));
    let store = tmp("bif-store");
    ok(&strs(&with(
        &strs(&with(&["plan", "bifurcation"], &args)),
        &["--shards", "2", "--out", s(&store)],
    )));
    for i in ["0", "1"] {
        ok(&["run-shard", s(&store), "--shard", i]);
    }
    ok(&["merge", s(&store)]);
    same_files(
        &store,
        &single,
        &["runs.csv", "bifurcation.csv", "impact_force.csv"],
    );
    for d in [single, store] {
        std::fs::remove_dir_all(d).ok();
    }
}
