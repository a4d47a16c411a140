//! Records the git commit of the build (for `run.json`), when the source is a git checkout (a
//! worktree too: git itself says where its HEAD and refs are).
use std::path::{Path, PathBuf};
use std::process::Command;

fn git(dir: &Path, args: &[&str]) -> Option<String> {
    let out = Command::new("git")
        .args(args)
        .current_dir(dir)
        .output()
        .ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
}

fn main() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    println!("cargo:rerun-if-changed=build.rs");
    // HEAD of this checkout, and the branch refs (loose or packed) of its repository; only paths
    // that exist (a missing one would make cargo rerun this on every build)
    let abs = |p: String| -> PathBuf {
        let p = PathBuf::from(p);
        if p.is_absolute() {
            p
        } else {
            dir.join(p)
        }
    };
    let mut watch: Vec<PathBuf> = Vec::new();
    if let Some(d) = git(&dir, &["rev-parse", "--git-dir"]) {
        watch.push(abs(d).join("HEAD"));
    }
    if let Some(c) = git(&dir, &["rev-parse", "--git-common-dir"]) {
        let c = abs(c);
        watch.push(c.join("refs").join("heads"));
        watch.push(c.join("packed-refs"));
    }
    for p in watch.iter().filter(|p| p.exists()) {
        println!("cargo:rerun-if-changed={}", p.display());
    }
    if let Some(commit) = git(&dir, &["rev-parse", "HEAD"]) {
        println!("cargo:rustc-env=GEARDYN_GIT_COMMIT={commit}");
    }
}
