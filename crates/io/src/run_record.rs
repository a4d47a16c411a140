//! What ran, written beside every result (`run.json`), and the rule that output folders never
//! mix: a folder holds the results of one command, and a checkpointed command resumes only the
//! run it was started with (docs/configuration.md).

use crate::config::Config;
use crate::output::{write_json, OutputError};
use geardyn_scenario::{ResolvedRecord, Scenario};
use serde::{Deserialize, Serialize};
use std::path::Path;

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
    /// A file error.
    #[error(transparent)]
    Output(#[from] OutputError),
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

/// Prepares `out` for a run of `kind`: refuses a folder holding another command's results, and a
/// checkpoint whose first line is not `key` (unless `force`, which sets it aside as
/// `checkpoint.jsonl.old`). Pass `key = None` for commands without a checkpoint.
pub fn prepare_folder(
    out: &Path,
    kind: &str,
    key: Option<&str>,
    force: bool,
) -> Result<(), FolderError> {
    let path = out.display().to_string();
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
    if cp.exists() {
        let first = std::fs::read(&cp)
            .map(|b| {
                let end = b.iter().position(|&c| c == b'\n').unwrap_or(b.len());
                String::from_utf8_lossy(&b[..end]).into_owned()
            })
            .unwrap_or_default();
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
                std::fs::rename(&cp, out.join("checkpoint.jsonl.old")).map_err(|e| io(&cp, e))?;
            }
            _ => {}
        }
    }
    std::fs::create_dir_all(out).map_err(|e| io(out, e))?;
    Ok(())
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
    write_sweep_record(out, kind, cfg, scenario, &[], started_unix_s, elapsed_s)
}

/// Writes `run.json` of a sweep or map into `out`: `scenario` is the base point, `swept` the
/// parameters it varied.
pub fn write_sweep_record(
    out: &Path,
    kind: &str,
    cfg: &Config,
    scenario: &Scenario,
    swept: &[Swept],
    started_unix_s: f64,
    elapsed_s: f64,
) -> Result<(), OutputError> {
    let rec = RunRecord {
        swept: swept.to_vec(),
        version: env!("CARGO_PKG_VERSION").to_string(),
        git_commit: option_env!("GEARDYN_GIT_COMMIT").map(String::from),
        kind: kind.to_string(),
        command: std::env::args().collect(),
        config: serde_json::to_value(cfg.to_value()).unwrap_or(serde_json::Value::Null),
        resolved: scenario.record(),
        threads: rayon_threads(),
        started_unix_s,
        elapsed_s,
    };
    write_json(&out.join("run.json"), &rec)
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
