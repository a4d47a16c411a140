//! Digests of the source a report is computed by. A study's cached data is keyed by
//! `GEARDYN_LIBRARY_DIGEST`, the source of the library crates it computes through (solvers,
//! physics, scenario, model, analysis, the executor crate, and the checkpoints and configuration of
//! io):
//! a change of an integrator or a classification rule recomputes the studies, a change of the
//! report (a rendering, a claim, a comment) or of the plots does not. A study whose rendered
//! section is cached is keyed by `GEARDYN_SOURCE_DIGEST`, which adds the report and every other
//! crate it draws with.

use std::path::{Path, PathBuf};

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return;
    };
    for e in rd.flatten() {
        let p = e.path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// FNV-1a (64 bit) over each file's path (relative to `crates`) and bytes, in path order.
fn digest(crates: &Path, mut files: Vec<PathBuf>) -> String {
    files.sort();
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut eat = |bytes: &[u8]| {
        for &b in bytes {
            h = (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3);
        }
    };
    for f in &files {
        eat(f
            .strip_prefix(crates)
            .unwrap_or(f)
            .to_string_lossy()
            .as_bytes());
        eat(&std::fs::read(f).unwrap_or_default());
    }
    format!("{h:016x}")
}

fn main() {
    let here = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("set by cargo"));
    let crates = here.parent().map(Path::to_path_buf).unwrap_or_default();
    let files_of = |names: &[&str]| {
        let mut files = Vec::new();
        for name in names {
            let src = crates.join(name).join("src");
            println!("cargo:rerun-if-changed={}", src.display());
            rust_files(&src, &mut files);
        }
        files
    };
    let mut library = files_of(&[
        "analysis", "model", "physics", "scenario", "solvers", "exec",
    ]);
    library.push(crates.join("io").join("src").join("checkpoint.rs"));
    rust_files(&crates.join("io").join("src").join("config"), &mut library);
    let all = files_of(&[
        "report", "analysis", "model", "physics", "scenario", "solvers", "files", "plots", "io",
        "exec",
    ]);
    println!(
        "cargo:rustc-env=GEARDYN_LIBRARY_DIGEST={}",
        digest(&crates, library)
    );
    println!(
        "cargo:rustc-env=GEARDYN_SOURCE_DIGEST={}",
        digest(&crates, all)
    );
}
