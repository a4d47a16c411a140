//! Checkpoints of long sweeps: one JSON line per finished task, appended and flushed as it
//! finishes, so an interrupted run loses at most the tasks in flight. The first line holds the
//! run's key (the command and its full resolved settings); a checkpoint with another key is set
//! aside, never mixed in.

use crate::output::OutputError;
use serde::{de::DeserializeOwned, Serialize};
use std::fs::{File, OpenOptions};
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// An open checkpoint file.
pub struct Checkpoint {
    path: PathBuf,
    file: Mutex<File>,
}

fn io_err(path: &Path, source: std::io::Error) -> OutputError {
    OutputError::Io {
        path: path.display().to_string(),
        source,
    }
}

impl Checkpoint {
    /// Opens `path` for the run identified by `key`, returning the records already finished by
    /// an earlier run with the same key (unreadable trailing lines of a killed run are dropped).
    pub fn open<T: Serialize + DeserializeOwned>(
        path: &Path,
        key: &str,
    ) -> Result<(Self, Vec<T>), OutputError> {
        let mut done: Vec<T> = Vec::new();
        let mut reuse = false;
        if let Ok(f) = File::open(path) {
            let mut lines = BufReader::new(f).lines();
            if let Some(Ok(first)) = lines.next() {
                if first == key {
                    reuse = true;
                    for line in lines.map_while(Result::ok) {
                        if let Ok(rec) = serde_json::from_str(&line) {
                            done.push(rec);
                        }
                    }
                }
            }
            if !reuse {
                let aside = path.with_extension("jsonl.old");
                std::fs::rename(path, &aside).map_err(|e| io_err(path, e))?;
            }
        }
        // (re)write the header and the kept records: drops a torn last line of a killed run
        let mut f = File::create(path).map_err(|e| io_err(path, e))?;
        writeln!(f, "{key}").map_err(|e| io_err(path, e))?;
        for r in &done {
            let line = serde_json::to_string(r).expect("serialisable");
            writeln!(f, "{line}").map_err(|e| io_err(path, e))?;
        }
        f.flush().map_err(|e| io_err(path, e))?;
        drop(f);
        let file = OpenOptions::new()
            .append(true)
            .open(path)
            .map_err(|e| io_err(path, e))?;
        Ok((
            Checkpoint {
                path: path.to_path_buf(),
                file: Mutex::new(file),
            },
            done,
        ))
    }

    /// Appends one record and flushes it to disk.
    pub fn append<T: Serialize>(&self, rec: &T) -> Result<(), OutputError> {
        let line = serde_json::to_string(rec).expect("serialisable");
        let mut f = self.file.lock().unwrap_or_else(|e| e.into_inner());
        writeln!(f, "{line}")
            .and_then(|_| f.flush())
            .map_err(|e| io_err(&self.path, e))
    }
}
