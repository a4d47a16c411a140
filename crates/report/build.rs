//! Digest of the source a report is computed by: the report crate and every library crate it
//! computes through. A cached study (`section.json`) is keyed by it, so that a change of code —
//! a claim's threshold, a classification rule, an integrator — recomputes the studies instead
//! of serving verdicts the new code would not give.

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

fn main() {
    let here = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("set by cargo"));
    let crates = here.parent().map(Path::to_path_buf).unwrap_or_default();
    let mut files = Vec::new();
    for name in [
        "report", "analysis", "model", "physics", "scenario", "solvers", "files", "plots", "io",
        "exec",
    ] {
        let src = crates.join(name).join("src");
        println!("cargo:rerun-if-changed={}", src.display());
        rust_files(&src, &mut files);
    }
    files.sort();
    // FNV-1a (64 bit) over each file's path (relative) and bytes
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut eat = |bytes: &[u8]| {
        for &b in bytes {
            h = (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3);
        }
    };
    for f in &files {
        eat(f
            .strip_prefix(&crates)
            .unwrap_or(f)
            .to_string_lossy()
            .as_bytes());
        eat(&std::fs::read(f).unwrap_or_default());
    }
    println!("cargo:rustc-env=GEARDYN_SOURCE_DIGEST={h:016x}");
}
