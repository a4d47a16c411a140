//! Checkpoints of long sweeps: one JSON line per finished task, so an interrupted run loses at
//! most the tasks in flight. The first line holds the run's key (the command and its full resolved
//! settings); a checkpoint with another key is set aside (`<file>.old`), never mixed in.
//!
//! **Crash safety.**
//! * A record is appended as one complete line in a single write, then flushed and synced to disk
//!   (`fsync`) before [`Checkpoint::append`] returns.
//! * The file is never truncated in place: when it has to be rewritten (a new key, or damaged or
//!   rejected lines to drop), the new content is written to a temporary file beside it, synced,
//!   and renamed over it — a crash leaves either the old file or the new one, complete.
//! * Reading keeps every good record: a line that is not UTF-8, not JSON of the record type, or
//!   rejected by the caller's validation (see [`Checkpoint::open_validated`]) is dropped, and
//!   reading goes on with the next line. A torn last line (a run killed mid-write) is one such line.

use crate::output::OutputError;
use serde::{de::DeserializeOwned, Serialize};
use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// An open checkpoint file.
pub struct Checkpoint {
    path: PathBuf,
    /// The file and the time of its last sync to disk.
    file: Mutex<(File, std::time::Instant)>,
    dropped: usize,
    /// The lock of the folder, held as long as the checkpoint is written ([`Checkpoint::hold`]).
    lock: Option<crate::run_record::FolderLock>,
}

/// Records are synced to disk at most this often (and when the checkpoint is dropped): a written
/// record already survives the process being killed (it is in the kernel's cache); the sync
/// guards against a machine crash, and syncing every record made large basins I/O-bound.
const SYNC_INTERVAL: std::time::Duration = std::time::Duration::from_secs(1);

fn io_err(path: &Path, source: std::io::Error) -> OutputError {
    OutputError::Io {
        path: path.display().to_string(),
        source,
    }
}

/// FNV-1a (64 bit) of a record's JSON: a flipped digit in an otherwise valid record is caught
/// and the record recomputed, not trusted. (A checksum, not a cryptographic hash: it guards
/// against damage, not against forgery.)
/// FNV-1a (64 bit) of `bytes`: a checksum against accidental damage (a torn line, a changed
/// digit), not against an adversary.
pub fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// One record as a complete line: its JSON, a tab (never inside serialised JSON) and the
/// checksum of the JSON in hex, then the newline.
fn json_line<T: Serialize>(path: &Path, rec: &T) -> Result<Vec<u8>, OutputError> {
    let mut line = serde_json::to_vec(rec).map_err(|e| io_err(path, std::io::Error::other(e)))?;
    let sum = fnv1a(&line);
    line.extend_from_slice(format!("\t{sum:016x}\n").as_bytes());
    Ok(line)
}

/// Largest checkpoint read (bytes): 4 GiB, far above the largest sweep's (a record is a few hundred
/// bytes to a few kilobytes).
pub const MAX_CHECKPOINT_BYTES: u64 = 4 << 30;

/// The JSON of a record line whose checksum matches.
fn verified(line: &[u8]) -> Option<&[u8]> {
    let tab = line.iter().rposition(|&b| b == b'\t')?;
    let (json, sum) = (&line[..tab], &line[tab + 1..]);
    let sum = u64::from_str_radix(std::str::from_utf8(sum).ok()?, 16).ok()?;
    (fnv1a(json) == sum).then_some(json)
}

/// `dir/name.tmp` beside `path` (same file system, so the rename is atomic).
fn temp_path(path: &Path) -> PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(".tmp");
    path.with_file_name(name)
}

/// Replaces `path` by `content` through a synced temporary file and a rename.
fn replace_file(path: &Path, content: &[u8]) -> Result<(), OutputError> {
    let tmp = temp_path(path);
    let write = || -> std::io::Result<()> {
        let _ = std::fs::remove_file(&tmp);
        let mut f = OpenOptions::new().write(true).create_new(true).open(&tmp)?;
        f.write_all(content)?;
        f.sync_all()?;
        drop(f);
        std::fs::rename(&tmp, path)?;
        // make the rename itself durable (directories cannot be synced on every platform)
        if let Some(dir) = path.parent() {
            let dir = if dir.as_os_str().is_empty() {
                Path::new(".")
            } else {
                dir
            };
            if let Ok(d) = File::open(dir) {
                let _ = d.sync_all();
            }
        }
        Ok(())
    };
    write().map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        io_err(path, e)
    })
}

/// What an existing checkpoint file holds.
enum Existing<T> {
    /// No file.
    None,
    /// A file of another run (or with an unreadable key line).
    Foreign,
    /// A file of this run: its good records, how many lines were dropped, and whether the file
    /// is clean (nothing dropped, ends with a newline) so that it can be appended to as it is.
    Ours {
        records: Vec<T>,
        dropped: usize,
        clean: bool,
    },
}

fn read_existing<T, V>(path: &Path, key: &str, validate: &mut V) -> Result<Existing<T>, OutputError>
where
    T: DeserializeOwned,
    V: FnMut(&T) -> bool,
{
    // a link, a FIFO or a device in the checkpoint's place is refused before it is opened (a
    // FIFO would block, a link to /dev/zero would be read without end)
    crate::safe_write::check_target(path)?;
    let bytes = match crate::safe_write::read_bounded(path, MAX_CHECKPOINT_BYTES) {
        Ok(b) => b,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Existing::None),
        Err(e) => return Err(io_err(path, e)),
    };
    let mut lines = bytes.split(|&b| b == b'\n');
    let first = lines.next().unwrap_or_default();
    let first = first.strip_suffix(b"\r").unwrap_or(first);
    if first != key.as_bytes() {
        return Ok(Existing::Foreign);
    }
    let mut records = Vec::new();
    let mut dropped = 0;
    for line in lines {
        let line = line.strip_suffix(b"\r").unwrap_or(line);
        if line.iter().all(u8::is_ascii_whitespace) {
            // (the empty piece after the final newline; blank lines carry nothing)
            continue;
        }
        let rec = verified(line)
            .and_then(|j| std::str::from_utf8(j).ok())
            .and_then(|s| serde_json::from_str::<T>(s).ok());
        match rec {
            Some(r) if validate(&r) => records.push(r),
            _ => dropped += 1,
        }
    }
    let clean = dropped == 0 && bytes.last() == Some(&b'\n');
    Ok(Existing::Ours {
        records,
        dropped,
        clean,
    })
}

impl Drop for Checkpoint {
    fn drop(&mut self) {
        let g = self.file.get_mut().unwrap_or_else(|e| e.into_inner());
        let _ = g.0.sync_data();
    }
}

impl Checkpoint {
    /// Opens `path` for the run identified by `key`, returning the records already finished by
    /// an earlier run with the same key. Lines that are not records of type `T` (a torn last line
    /// of a killed run, a damaged line anywhere) are dropped; every other record is kept. Same as
    /// [`Checkpoint::open_validated`] accepting every record.
    pub fn open<T: Serialize + DeserializeOwned>(
        path: &Path,
        key: &str,
    ) -> Result<(Self, Vec<T>), OutputError> {
        Self::open_validated(path, key, |_: &T| true)
    }

    /// As [`Checkpoint::open`], keeping only the records for which `validate` returns `true`
    /// (a record of a task that no longer exists, or with values out of range, say). Rejected
    /// records are dropped from the file like damaged lines; [`Checkpoint::dropped`] counts both.
    ///
    /// A file of another key is renamed to `<file>.old`. The file is rewritten (temporary file,
    /// sync, rename; never truncated in place) only when something was dropped or the last line
    /// lacks its newline; otherwise it is opened for appending as it is.
    pub fn open_validated<T, V>(
        path: &Path,
        key: &str,
        mut validate: V,
    ) -> Result<(Self, Vec<T>), OutputError>
    where
        T: Serialize + DeserializeOwned,
        V: FnMut(&T) -> bool,
    {
        let (records, dropped, rewrite) = match read_existing(path, key, &mut validate)? {
            Existing::None => (Vec::new(), 0, true),
            Existing::Foreign => {
                let aside = crate::safe_write::aside_name(path);
                std::fs::rename(path, aside).map_err(|e| io_err(path, e))?;
                (Vec::new(), 0, true)
            }
            Existing::Ours {
                records,
                dropped,
                clean,
            } => (records, dropped, !clean),
        };
        if rewrite {
            let mut content = Vec::with_capacity(key.len() + 1);
            content.extend_from_slice(key.as_bytes());
            content.push(b'\n');
            for r in &records {
                content.extend_from_slice(&json_line(path, r)?);
            }
            replace_file(path, &content)?;
        }
        let file = OpenOptions::new()
            .append(true)
            .open(path)
            .map_err(|e| io_err(path, e))?;
        Ok((
            Checkpoint {
                path: path.to_path_buf(),
                file: Mutex::new((file, std::time::Instant::now())),
                dropped,
                lock: None,
            },
            records,
        ))
    }

    /// Keeps the output folder's lock until the checkpoint is dropped (the run's end).
    pub fn hold(mut self, lock: crate::run_record::FolderLock) -> Self {
        self.lock = Some(lock);
        self
    }

    /// The line `append` writes for a record (JSON, tab, checksum, newline).
    pub fn line<T: Serialize>(rec: &T) -> String {
        String::from_utf8(json_line(Path::new("<record>"), rec).unwrap_or_default())
            .unwrap_or_default()
    }

    /// Appends one record as a single complete line, written through to the operating system
    /// at once (a killed process loses nothing written) and synced to disk at most every
    /// `SYNC_INTERVAL`.
    pub fn append<T: Serialize>(&self, rec: &T) -> Result<(), OutputError> {
        let line = json_line(&self.path, rec)?;
        let mut g = self.file.lock().unwrap_or_else(|e| e.into_inner());
        let (f, last) = &mut *g;
        f.write_all(&line)
            .and_then(|_| f.flush())
            .map_err(|e| io_err(&self.path, e))?;
        if last.elapsed() >= SYNC_INTERVAL {
            f.sync_data().map_err(|e| io_err(&self.path, e))?;
            *last = std::time::Instant::now();
        }
        Ok(())
    }

    /// Lines dropped when the checkpoint was opened (damaged, torn or rejected by validation).
    pub fn dropped(&self) -> usize {
        self.dropped
    }

    /// The checkpoint file.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_flipped_digit_is_caught_by_the_checksum() {
        let line = json_line(Path::new("x"), &vec![1.25f64, 2.5]).unwrap();
        let body = &line[..line.len() - 1];
        assert_eq!(verified(body), Some(&b"[1.25,2.5]"[..]));
        let mut bad = body.to_vec();
        bad[3] = b'3';
        assert_eq!(verified(&bad), None);
        assert_eq!(verified(b"[1.25,2.5]"), None);
    }

    #[test]
    fn temp_file_is_beside_the_checkpoint() {
        assert_eq!(
            temp_path(Path::new("/a/b/checkpoint.jsonl")),
            PathBuf::from("/a/b/checkpoint.jsonl.tmp")
        );
        assert_eq!(
            temp_path(Path::new("c.jsonl")),
            PathBuf::from("c.jsonl.tmp")
        );
    }
}
