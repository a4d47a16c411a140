//! Where finished items are kept: the [`Store`] trait and its store of a command's folder, a
//! JSONL checkpoint ([`Checkpointed`]). The other store is the Zarr store of a sharded plan
//! ([`crate::shard::ShardStore`]).

use crate::error::ExecError;
use geardyn_io::checkpoint::Checkpoint;
use geardyn_io::run_record::{prepare_folder, FolderLock};
use serde::{de::DeserializeOwned, Serialize};
use std::path::{Path, PathBuf};

/// Where a job's finished records are kept, so that an interrupted job resumes (and a finished
/// one is not computed again).
pub trait Store<R>: Sync {
    /// Opens the store for a job of `kind` with `settings`, returning the records it holds of
    /// that job (the executor trusts only those the job recognises, [`crate::Job::id_of`]). A
    /// store made for another job is set aside or refused, never mixed in.
    fn open(&mut self, kind: &str, settings: serde_json::Value) -> Result<Vec<R>, ExecError>;
    /// Keeps one finished record (called from any thread, as each item finishes).
    fn append(&self, record: &R) -> Result<(), ExecError>;
    /// The records of every item the store was opened for, in item order, once all are
    /// computed ([`crate::execute_items`]): a store that keeps whole results (a shard's chunks
    /// and done marker) writes them here. Default: nothing (the records were appended).
    fn finish(&mut self, _records: &[R]) -> Result<(), ExecError> {
        Ok(())
    }
    /// The job ended: release what the store holds (its file, the folder's lock).
    fn close(&mut self) {}
}

/// The JSONL checkpoint of a command's folder (`out/checkpoint.jsonl`) or a file of its own:
/// one verified JSON line per finished record, the first line the job's key (its kind, the
/// context the store was made with, and its settings).
pub struct Checkpointed {
    path: PathBuf,
    /// What the job's settings are joined with in the store's key (the configuration).
    context: serde_json::Value,
    /// Prepare the command folder holding the file (and hold its lock); with `force`.
    folder: Option<(PathBuf, bool)>,
    open: Option<Checkpoint>,
}

impl Checkpointed {
    /// `out/checkpoint.jsonl` of a command's output folder. Opening prepares the folder and
    /// holds its lock until the job ends ([`prepare_folder`]): it refuses a folder holding
    /// another command's results, or a checkpoint made with another configuration or other
    /// settings (unless `force`, which sets that checkpoint aside and starts over).
    pub fn folder(out: &Path, config: &impl Serialize, force: bool) -> Result<Self, ExecError> {
        Ok(Checkpointed {
            path: out.join("checkpoint.jsonl"),
            context: to_value(config)?,
            folder: Some((out.to_path_buf(), force)),
            open: None,
        })
    }

    /// A checkpoint file of its own (a report study keeps one per computation in its folder); a
    /// file made with another context or other settings is set aside and the job starts over.
    pub fn file(path: &Path, context: &impl Serialize) -> Result<Self, ExecError> {
        Ok(Checkpointed {
            path: path.to_path_buf(),
            context: to_value(context)?,
            folder: None,
            open: None,
        })
    }
}

fn to_value(v: &impl Serialize) -> Result<serde_json::Value, ExecError> {
    serde_json::to_value(v).map_err(ExecError::analysis)
}

impl<R: Serialize + DeserializeOwned + Send + Sync> Store<R> for Checkpointed {
    fn open(&mut self, kind: &str, settings: serde_json::Value) -> Result<Vec<R>, ExecError> {
        let key = serde_json::json!({ "kind": kind, "config": self.context, "settings": settings });
        let key = serde_json::to_string(&key).map_err(ExecError::analysis)?;
        let lock: Option<FolderLock> = match &self.folder {
            Some((out, force)) => Some(prepare_folder(out, kind, Some(&key), *force)?),
            None => None,
        };
        let (cp, done) = Checkpoint::open::<R>(&self.path, &key)?;
        self.open = Some(match lock {
            Some(l) => cp.hold(l),
            None => cp,
        });
        Ok(done)
    }

    fn append(&self, record: &R) -> Result<(), ExecError> {
        match &self.open {
            Some(cp) => Ok(cp.append(record)?),
            None => Err(ExecError::Store(format!(
                "{}: appended to before it was opened",
                self.path.display()
            ))),
        }
    }

    fn close(&mut self) {
        self.open = None;
    }
}
