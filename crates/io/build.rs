//! Records the git commit of the build (for `run.json`), when the source is a git checkout.
fn main() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    // (a worktree or a source tarball has no .git directory: then only this script counts,
    // since a missing path would make cargo rerun it on every build)
    let mut watched = false;
    for p in ["../../.git/HEAD", "../../.git/refs/heads"] {
        if std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join(p)
            .exists()
        {
            println!("cargo:rerun-if-changed={p}");
            watched = true;
        }
    }
    if !watched {
        println!("cargo:rerun-if-changed=build.rs");
    }
    if let Ok(out) = std::process::Command::new("git")
        .args(["rev-parse", "HEAD"])
        .current_dir(&dir)
        .output()
    {
        if out.status.success() {
            let commit = String::from_utf8_lossy(&out.stdout).trim().to_string();
            println!("cargo:rustc-env=GEARDYN_GIT_COMMIT={commit}");
        }
    }
}
