//! What ran, written beside every result (`run.json`, and with it `config.toml` at the end of a
//! sweep, map, basin or orbit run: [`write_config_and_record`]), and the rule that output folders
//! never mix: a folder holds the results of one command, and a checkpointed command resumes only
//! the run it was started with (docs/configuration.md).

use crate::config::Config;
use crate::output::{write_json, write_text, OutputError};
use geardyn_scenario::{ResolvedRecord, Scenario};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The git commit the library was built from (`run.json`'s `git_commit`, a shard plan's), when
/// it was built from a git checkout.
pub const GIT_COMMIT: Option<&str> = option_env!("GEARDYN_GIT_COMMIT");

/// The record of one run (`run.json`).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RunRecord {
    /// geardyn version.
    pub version: String,
    /// Git commit of the build, when known.
    pub git_commit: Option<String>,
    /// The command (`simulate`, `bifurcation`, ...).
    pub kind: String,
    /// The command line (argv).
    pub command: Vec<String>,
    /// The configuration used (inputs of the builder and simulation settings).
    pub config: serde_json::Value,
    /// The dimensionless parameters that were integrated; for a sweep or a map, the base point
    /// (each swept parameter takes the values in `swept` instead; every value's own resolved
    /// parameters are in the sweep's results).
    pub resolved: ResolvedRecord,
    /// The parameters a sweep or map varied, with their values (empty for a single run).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub swept: Vec<Swept>,
    /// Worker threads.
    pub threads: usize,
    /// Start time (seconds since the Unix epoch, UTC).
    pub started_unix_s: f64,
    /// Elapsed wall time (s).
    pub elapsed_s: f64,
}

/// A swept parameter and its values.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Swept {
    /// The parameter (a `--set` name).
    pub param: String,
    /// First value.
    pub from: f64,
    /// Last value.
    pub to: f64,
    /// Number of values.
    pub count: usize,
}

impl Swept {
    /// `param` over `values` (in order).
    pub fn of(param: &str, values: &[f64]) -> Self {
        Swept {
            param: param.to_string(),
            from: values.first().copied().unwrap_or(f64::NAN),
            to: values.last().copied().unwrap_or(f64::NAN),
            count: values.len(),
        }
    }
}

/// Errors of the folder rules.
#[derive(Debug, thiserror::Error)]
pub enum FolderError {
    /// The folder holds another command's results.
    #[error("{path} holds the results of `geardyn {other}`; choose another --out (outputs of different commands never share a folder)")]
    OtherCommand {
        /// Folder.
        path: String,
        /// The command whose results are there.
        other: String,
    },
    /// The folder's checkpoint belongs to another configuration or command line.
    #[error("{path} holds a checkpoint of a run with different settings; rerun with --force to discard it and start over, or choose another --out")]
    OtherRun {
        /// Folder.
        path: String,
    },
    /// The folder holds files geardyn did not write.
    #[error("{path} already holds files geardyn did not write ({example}); geardyn writes only into a new or empty folder or one it made: choose another --out")]
    NotOurs {
        /// Folder.
        path: String,
        /// One of the files.
        example: String,
    },
    /// Another run writes into the folder.
    #[error("{path} is in use by another geardyn run ({holder}); wait for it, or choose another --out (the lock goes with that run: a run that ended, however it ended, holds none)")]
    Busy {
        /// Folder.
        path: String,
        /// pid, host and start of the holder.
        holder: String,
    },
    /// A file error.
    #[error(transparent)]
    Output(#[from] OutputError),
}

/// The file that marks a folder as made by geardyn (kept; older versions are recognised by their
/// `run.json` or `checkpoint.jsonl`).
pub const MARKER: &str = ".geardyn";
/// The lock file of a folder being written (removed when the run ends).
pub const LOCK: &str = ".geardyn.lock";

/// Takes `out` as geardyn's folder: creates it when absent; refuses an existing folder that is
/// not empty and holds neither geardyn's marker nor a `run.json` or checkpoint of an earlier
/// version (a user's own files, or `/`). Leaves the marker.
pub fn claim_folder(out: &Path) -> Result<(), FolderError> {
    let path = out.display().to_string();
    if std::fs::metadata(out).is_ok_and(|m| !m.is_dir()) {
        return Err(FolderError::Output(OutputError::Refused {
            path,
            reason: "it is a file, not a folder: --out names the folder the results go into".into(),
        }));
    }
    if let Ok(rd) = std::fs::read_dir(out) {
        let mut names: Vec<String> = Vec::new();
        let mut special = None;
        for e in rd.filter_map(|e| e.ok()) {
            let name = e.file_name().to_string_lossy().into_owned();
            let special_here = e.file_type().is_ok_and(|t| {
                // a folder where a result file goes (its name ends like one) is refused now, not
                // after the computation at its write
                !(t.is_file() || t.is_dir()) || (t.is_dir() && is_result_name(&name))
            });
            if special_here {
                special.get_or_insert(e.path());
            }
            names.push(name);
        }
        if !names.is_empty() && !is_ours(out, &names) {
            names.sort();
            return Err(FolderError::NotOurs {
                path,
                example: names[0].clone(),
            });
        }
        // a link or a special file in a result folder is never geardyn's: refused before
        // anything is written (a refusal halfway left a folder of two runs)
        if let Some(p) = special {
            return Err(FolderError::Output(OutputError::Refused {
                path: p.display().to_string(),
                reason: "the output folder holds a symbolic link, a special file or a folder named like a result file there (geardyn never writes through one: remove it or choose another --out)".into(),
            }));
        }
    }
    std::fs::create_dir_all(out).map_err(|e| io(out, e))?;
    let marker = out.join(MARKER);
    if std::fs::symlink_metadata(&marker).is_err() {
        crate::safe_write::write_bytes(&marker, b"geardyn output folder\n")?;
    }
    Ok(())
}

/// Whether `name` is the temporary sibling of the marker ([`crate::safe_write`]:
/// `..geardyn.<pid>.tmp`), left by a run killed between writing the marker and renaming it.
fn is_marker_temp(name: &str) -> bool {
    name.strip_prefix(&format!(".{MARKER}."))
        .and_then(|rest| rest.strip_suffix(".tmp"))
        .is_some_and(|pid| !pid.is_empty() && pid.bytes().all(|b| b.is_ascii_digit()))
}

/// Whether `name` ends like a file geardyn writes (a result, a figure, a record or a checkpoint).
fn is_result_name(name: &str) -> bool {
    const ENDINGS: [&str; 10] = [
        ".csv", ".json", ".jsonl", ".npy", ".png", ".svg", ".html", ".toml", ".txt", ".md",
    ];
    ENDINGS.iter().any(|e| name.ends_with(e))
}

/// A folder is geardyn's when it holds its marker or lock, a `run.json` that is a run record
/// (`kind` and `version`), or a checkpoint whose key line names a `kind` (earlier versions left
/// no marker). A file merely named `run.json` is not enough.
fn is_ours(out: &Path, names: &[String]) -> bool {
    // (a run killed while it wrote the marker leaves the marker's temporary sibling only)
    if names
        .iter()
        .any(|n| n == MARKER || n == LOCK || is_marker_temp(n))
    {
        return true;
    }
    let record = crate::safe_write::read_bounded(&out.join("run.json"), 1 << 20)
        .ok()
        .and_then(|b| serde_json::from_slice::<serde_json::Value>(&b).ok())
        .is_some_and(|v| v.get("kind").is_some() && v.get("version").is_some());
    let checkpoint = names.iter().any(|n| n == "checkpoint.jsonl")
        && serde_json::from_str::<serde_json::Value>(&first_line(&out.join("checkpoint.jsonl")))
            .is_ok_and(|v| v.get("kind").is_some());
    record || checkpoint
}

/// The lock of an output folder, held while a run writes into it: the file `.geardyn.lock`
/// under an advisory lock of the operating system (`flock`, through the `fs4` crate), which the
/// system releases when the process ends however it ends, so a lock is never stale. The file
/// holds `pid P on H since T` for the message of a run that finds it taken; dropping the lock
/// removes the file (a killed run leaves it, unlocked: the next run takes it over and says so).
#[derive(Debug)]
pub struct FolderLock {
    path: std::path::PathBuf,
    /// The open lock file: the lock lives as long as it does.
    _file: std::fs::File,
}

/// Whether the open `file` is still the file named `path` (a holder that let go removed the
/// name, and a third run may have made a new file under it: a lock of the old one guards
/// nothing).
fn is_named(file: &std::fs::File, path: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        match (file.metadata(), std::fs::symlink_metadata(path)) {
            (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    {
        let _ = (file, path);
        true
    }
}

impl FolderLock {
    /// Locks `out` (which must exist) for this process.
    pub fn take(out: &Path) -> Result<FolderLock, FolderError> {
        use std::io::{Read, Seek, Write};
        let path = out.join(LOCK);
        let busy = |holder: String| FolderError::Busy {
            path: out.display().to_string(),
            holder,
        };
        for _ in 0..3 {
            if std::fs::symlink_metadata(&path).is_ok_and(|m| !m.is_file()) {
                return Err(FolderError::Output(OutputError::Refused {
                    path: path.display().to_string(),
                    reason: "it is not a lock file geardyn wrote (remove it)".into(),
                }));
            }
            let mut file = std::fs::OpenOptions::new()
                .read(true)
                .write(true)
                .create(true)
                .truncate(false)
                .open(&path)
                .map_err(|e| io(&path, e))?;
            let mut holder = String::new();
            match fs4::FileExt::try_lock(&file) {
                Ok(()) => {}
                Err(fs4::TryLockError::WouldBlock) => {
                    let _ = file.take(4096).read_to_string(&mut holder);
                    return Err(busy(holder.trim().to_string()));
                }
                Err(fs4::TryLockError::Error(e)) => return Err(io(&path, e)),
            }
            if !is_named(&file, &path) {
                continue;
            }
            let _ = (&file).take(4096).read_to_string(&mut holder);
            if !holder.trim().is_empty() {
                eprintln!(
                    "note: {} held a stale lock ({}); taken over",
                    out.display(),
                    holder.trim()
                );
            }
            let me = format!(
                "pid {} on {} since {:.0}",
                std::process::id(),
                host(),
                now_unix_s()
            );
            file.set_len(0)
                .and_then(|_| file.rewind())
                .and_then(|_| file.write_all(me.as_bytes()))
                .map_err(|e| io(&path, e))?;
            announce_held(&path);
            return Ok(FolderLock { path, _file: file });
        }
        Err(busy("another process took the lock first".into()))
    }
}

/// The lock file this process holds (a run holds one folder's lock at a time).
static HELD: std::sync::Mutex<Option<std::path::PathBuf>> = std::sync::Mutex::new(None);

fn announce_held(path: &Path) {
    *HELD.lock().unwrap_or_else(|e| e.into_inner()) = Some(path.to_path_buf());
}

/// Removes the lock file this process holds, if any: a Ctrl-C handler that ends the process at
/// once calls it, so that the interrupted folder is not left with a lock file (the lock itself
/// goes with the process).
pub fn release_held_lock() {
    if let Some(p) = HELD.lock().unwrap_or_else(|e| e.into_inner()).take() {
        let _ = std::fs::remove_file(p);
    }
}

impl Drop for FolderLock {
    fn drop(&mut self) {
        let mut held = HELD.lock().unwrap_or_else(|e| e.into_inner());
        if held.as_deref() == Some(self.path.as_path()) {
            *held = None;
        }
        let _ = std::fs::remove_file(&self.path);
    }
}

/// This machine's name (for the lock).
fn host() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .or_else(|_| std::fs::read_to_string("/etc/hostname"))
        .map(|s| s.trim().to_string())
        .unwrap_or_else(|_| "unknown-host".into())
}

/// Start time of a run, for [`RunRecord`].
pub fn now_unix_s() -> f64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0.0, |d| d.as_secs_f64())
}

fn io(path: &Path, source: std::io::Error) -> FolderError {
    FolderError::Output(OutputError::Io {
        path: path.display().to_string(),
        source,
    })
}

/// Prepares `out` for a run of `kind` and locks it ([`FolderLock`], held until dropped): refuses
/// a folder geardyn did not make ([`claim_folder`]), one another run writes into, one holding
/// another command's results, and a checkpoint whose first line is not `key` (unless `force`,
/// which sets it aside as `checkpoint.jsonl.old`, or `.old.2`, ...: an earlier one is kept).
/// Pass `key = None` for commands without a checkpoint.
pub fn prepare_folder(
    out: &Path,
    kind: &str,
    key: Option<&str>,
    force: bool,
) -> Result<FolderLock, FolderError> {
    let path = out.display().to_string();
    claim_folder(out)?;
    let lock = FolderLock::take(out)?;
    if let Ok(text) = std::fs::read_to_string(out.join("run.json")) {
        if let Ok(rec) = serde_json::from_str::<serde_json::Value>(&text) {
            if let Some(other) = rec.get("kind").and_then(|k| k.as_str()) {
                if other != kind {
                    return Err(FolderError::OtherCommand {
                        path,
                        other: other.to_string(),
                    });
                }
            }
        }
    }
    let cp = out.join("checkpoint.jsonl");
    if std::fs::symlink_metadata(&cp).is_ok() {
        // a link or a FIFO in the checkpoint's place is refused before it is read
        crate::safe_write::check_target(&cp)?;
        let first = first_line(&cp);
        match key {
            None => {
                return Err(FolderError::OtherCommand {
                    path,
                    other: serde_json::from_str::<serde_json::Value>(&first)
                        .ok()
                        .and_then(|v| v.get("kind").and_then(|k| k.as_str()).map(String::from))
                        .unwrap_or_else(|| "a checkpointed command".into()),
                })
            }
            Some(k) if k != first => {
                if !force {
                    return Err(FolderError::OtherRun { path });
                }
                let aside = crate::safe_write::aside_name(&cp);
                std::fs::rename(&cp, aside).map_err(|e| io(&cp, e))?;
            }
            _ => {}
        }
    }
    Ok(lock)
}

/// The first line of a file (its key), read in bounded pieces: a key is a few kilobytes.
fn first_line(path: &Path) -> String {
    use std::io::{BufRead, Read};
    let Ok(f) = std::fs::File::open(path) else {
        return String::new();
    };
    let mut line = Vec::new();
    let _ = std::io::BufReader::new(f.take(16 << 20)).read_until(b'\n', &mut line);
    if line.last() == Some(&b'\n') {
        line.pop();
    }
    String::from_utf8_lossy(&line).into_owned()
}

/// Writes `config.toml` and `run.json` into `out` at the end of a run that began at
/// `started_unix_s` (`swept`: the parameters a sweep or map varied, `scenario` its base point;
/// empty for a run at one point).
pub fn write_config_and_record(
    out: &Path,
    kind: &str,
    cfg: &Config,
    scenario: &Scenario,
    swept: &[Swept],
    started_unix_s: f64,
) -> Result<(), OutputError> {
    write_text(&out.join("config.toml"), &cfg.to_toml())?;
    let elapsed_s = now_unix_s() - started_unix_s;
    let rec = RunRecord::new(kind, cfg, scenario, swept, started_unix_s, elapsed_s);
    write_json(&out.join("run.json"), &rec)
}

/// Writes `run.json` into `out` (a run at one point: nothing swept).
pub fn write_run_record(
    out: &Path,
    kind: &str,
    cfg: &Config,
    scenario: &Scenario,
    started_unix_s: f64,
    elapsed_s: f64,
) -> Result<(), OutputError> {
    let rec = RunRecord::new(kind, cfg, scenario, &[], started_unix_s, elapsed_s);
    write_json(&out.join("run.json"), &rec)
}

/// Writes `run.json` of a gear train's run into `out`: the fields of a [`RunRecord`] without the
/// pair's configuration and resolved parameters, and `system` (the train's name, source and
/// operating point) in their place. A `config.toml` of an earlier pair run of the same command
/// (the folder taken over with `--force`) is removed: the folder's description is its
/// `system.toml`.
pub fn write_train_record(
    out: &Path,
    kind: &str,
    system: serde_json::Value,
    swept: &[Swept],
    elapsed_s: f64,
) -> Result<(), OutputError> {
    let stale = out.join("config.toml");
    if stale.is_file() {
        std::fs::remove_file(&stale).map_err(|e| OutputError::Io {
            path: stale.display().to_string(),
            source: e,
        })?;
    }
    let rec = serde_json::json!({
        "version": env!("CARGO_PKG_VERSION"),
        "git_commit": GIT_COMMIT,
        "kind": kind,
        "command": std::env::args().collect::<Vec<_>>(),
        "system": system,
        "swept": swept,
        "threads": rayon_threads(),
        "started_unix_s": now_unix_s() - elapsed_s,
        "elapsed_s": elapsed_s,
    });
    write_json(&out.join("run.json"), &rec)
}

impl RunRecord {
    /// The record of a run of command `kind` by this build and process.
    fn new(
        kind: &str,
        cfg: &Config,
        scenario: &Scenario,
        swept: &[Swept],
        started_unix_s: f64,
        elapsed_s: f64,
    ) -> Self {
        RunRecord {
            swept: swept.to_vec(),
            version: env!("CARGO_PKG_VERSION").to_string(),
            git_commit: GIT_COMMIT.map(String::from),
            kind: kind.to_string(),
            command: std::env::args().collect(),
            config: serde_json::to_value(cfg.to_value()).unwrap_or(serde_json::Value::Null),
            resolved: scenario.record(),
            threads: rayon_threads(),
            started_unix_s,
            elapsed_s,
        }
    }
}

fn rayon_threads() -> usize {
    std::env::var("RAYON_NUM_THREADS")
        .ok()
        .and_then(|v| v.parse().ok())
        .filter(|&n: &usize| n > 0)
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_run_killed_while_writing_the_marker_leaves_a_folder_geardyn_resumes() {
        // kill -9 between the marker's temporary file and its rename (seen by the crash test
        // under load): the folder holds `..geardyn.<pid>.tmp` alone, and the rerun must not
        // refuse it as somebody else's
        let dir = std::env::temp_dir().join(format!("geardyn-marker-tmp-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("..geardyn.19925.tmp"), "geardyn output").unwrap();
        prepare_folder(&dir, "bifurcation", Some("K1"), false).unwrap();
        assert!(dir.join(MARKER).exists());
        // a file merely named alike is not taken for it
        let other = dir.with_extension("other");
        let _ = std::fs::remove_dir_all(&other);
        std::fs::create_dir_all(&other).unwrap();
        std::fs::write(other.join("..geardyn.x.tmp"), "").unwrap();
        assert!(prepare_folder(&other, "bifurcation", Some("K1"), false).is_err());
        let _ = std::fs::remove_dir_all(&dir);
        let _ = std::fs::remove_dir_all(&other);
    }

    #[test]
    fn folders_never_mix() {
        let dir = std::env::temp_dir().join(format!("geardyn-folder-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        prepare_folder(&dir, "bifurcation", Some("K1"), false).unwrap();
        std::fs::write(dir.join("checkpoint.jsonl"), "K1\n{}\n").unwrap();
        std::fs::write(dir.join("run.json"), r#"{"kind":"bifurcation"}"#).unwrap();
        // same run resumes
        prepare_folder(&dir, "bifurcation", Some("K1"), false).unwrap();
        // different settings refuse, naming --force
        let e = prepare_folder(&dir, "bifurcation", Some("K2"), false).unwrap_err();
        assert!(e.to_string().contains("--force"), "{e}");
        // another command refuses
        let e = prepare_folder(&dir, "simulate", None, false).unwrap_err();
        assert!(e.to_string().contains("geardyn bifurcation"), "{e}");
        // --force sets the old checkpoint aside
        prepare_folder(&dir, "bifurcation", Some("K2"), true).unwrap();
        assert!(dir.join("checkpoint.jsonl.old").exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
