//! Writing a result file so that nothing outside the output folder is touched and no reader
//! sees half a file: the destination must be absent or a regular file (a symbolic link or a
//! FIFO in its place is refused, never followed), the content goes to a temporary sibling
//! (same folder, so the rename is atomic) and is renamed over the destination.
//!
//! Hand-written rather than a crate (`tempfile`'s `persist` does the same rename) because the
//! temporary name must keep the destination's extension: the PNG encoder picks the format from
//! it.

use std::io::Write;
use std::path::{Path, PathBuf};

/// Output failure.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// File system error.
    #[error("cannot write {path}")]
    Io {
        /// Path.
        path: String,
        /// Cause.
        source: std::io::Error,
    },
    /// A destination geardyn will not write (a symbolic link, a non-regular file).
    #[error("refusing to write {path}: {reason}")]
    Refused {
        /// Path.
        path: String,
        /// Why.
        reason: String,
    },
    /// CSV error.
    #[error("cannot write {path}")]
    Csv {
        /// Path.
        path: String,
        /// Cause.
        source: csv::Error,
    },
}

/// Refuses a destination that exists and is not a regular file (a symbolic link is refused
/// even when it points to one: writing through it would change a file outside the folder).
pub fn check_target(path: &Path) -> Result<(), OutputError> {
    match std::fs::symlink_metadata(path) {
        Err(_) => Ok(()),
        Ok(m) if m.file_type().is_symlink() => Err(OutputError::Refused {
            path: path.display().to_string(),
            reason: "it is a symbolic link (geardyn never writes through one: remove it or choose another --out)".into(),
        }),
        Ok(m) if !m.is_file() => Err(OutputError::Refused {
            path: path.display().to_string(),
            reason: "it exists and is not a regular file".into(),
        }),
        Ok(_) => Ok(()),
    }
}

/// `dir/.name.<pid>.tmp.ext` beside `path`, keeping its extension.
pub fn temp_sibling(path: &Path) -> PathBuf {
    let stem = path
        .file_stem()
        .map_or_else(|| "file".into(), |s| s.to_string_lossy().into_owned());
    let name = match path.extension() {
        Some(ext) => format!(
            ".{stem}.{}.tmp.{}",
            std::process::id(),
            ext.to_string_lossy()
        ),
        None => format!(".{stem}.{}.tmp", std::process::id()),
    };
    path.with_file_name(name)
}

/// Renames the finished temporary file `tmp` over `path` (removing `tmp` on failure).
pub fn commit(tmp: &Path, path: &Path) -> Result<(), OutputError> {
    check_target(path)
        .and_then(|_| {
            std::fs::rename(tmp, path).map_err(|source| OutputError::Io {
                path: path.display().to_string(),
                source,
            })
        })
        .inspect_err(|_| {
            let _ = std::fs::remove_file(tmp);
        })
}

/// Writes `path` through `write`, which gets the temporary path to write (whole) and returns
/// its own error type, mapped by `err`.
pub fn write_via<E>(
    path: &Path,
    write: impl FnOnce(&Path) -> Result<(), E>,
    err: impl FnOnce(E) -> OutputError,
) -> Result<(), OutputError> {
    check_target(path)?;
    let tmp = temp_sibling(path);
    // whatever holds the temporary name (a leftover, a planted link) goes first: the writers
    // below create the file and would follow a link
    let _ = std::fs::remove_file(&tmp);
    if let Err(e) = write(&tmp) {
        let _ = std::fs::remove_file(&tmp);
        return Err(err(e));
    }
    commit(&tmp, path)
}

/// Draws a figure file through `draw` (given the temporary path, with the destination's
/// extension) and renames it into place; errors as text, for the plotting layers.
pub fn draw_to(path: &Path, draw: impl FnOnce(&Path) -> Result<(), String>) -> Result<(), String> {
    write_via(path, draw, |msg| OutputError::Refused {
        path: path.display().to_string(),
        reason: msg,
    })
    .map_err(|e| match e {
        OutputError::Refused { reason, .. } => reason,
        other => other.to_string(),
    })
}

/// Reads a regular file of at most `max` bytes (an error of kind `InvalidData` above it, naming
/// the limit; `NotFound` when absent). Refuses what is not a regular file, so that a FIFO cannot
/// block the read.
pub fn read_bounded(path: &Path, max: u64) -> std::io::Result<Vec<u8>> {
    use std::io::Read;
    let m = std::fs::metadata(path)?;
    if !m.is_file() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "not a regular file",
        ));
    }
    let mut buf = Vec::new();
    std::fs::File::open(path)?
        .take(max + 1)
        .read_to_end(&mut buf)?;
    if buf.len() as u64 > max {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!("larger than the {max} bytes allowed"),
        ));
    }
    Ok(buf)
}

/// A free name to set `path` aside: `path.old`, else `path.old.2`, `path.old.3`, ... (an earlier
/// one is never replaced).
pub fn aside_name(path: &Path) -> PathBuf {
    let with = |suffix: String| {
        let mut s = path.as_os_str().to_os_string();
        s.push(suffix);
        PathBuf::from(s)
    };
    let first = with(".old".into());
    if std::fs::symlink_metadata(&first).is_err() {
        return first;
    }
    (2..)
        .map(|i| with(format!(".old.{i}")))
        .find(|p| std::fs::symlink_metadata(p).is_err())
        .expect("a free name")
}

/// Writes `bytes` to `path` (see the module doc).
pub fn write_bytes(path: &Path, bytes: &[u8]) -> Result<(), OutputError> {
    write_via(
        path,
        |tmp| -> std::io::Result<()> {
            let mut f = std::fs::File::create(tmp)?;
            f.write_all(bytes)?;
            f.flush()
        },
        |source| OutputError::Io {
            path: path.display().to_string(),
            source,
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("geardyn-safe-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn a_symbolic_link_in_the_way_is_refused_and_its_target_untouched() {
        let d = dir("link");
        let outside = d.join("outside.txt");
        std::fs::write(&outside, "precious").unwrap();
        let inside = d.join("out");
        std::fs::create_dir_all(&inside).unwrap();
        let link = inside.join("summary.json");
        std::os::unix::fs::symlink(&outside, &link).unwrap();
        let e = write_bytes(&link, b"{}").unwrap_err().to_string();
        assert!(e.contains("symbolic link"), "{e}");
        assert_eq!(std::fs::read_to_string(&outside).unwrap(), "precious");
        // no temporary file is left behind
        assert_eq!(std::fs::read_dir(&inside).unwrap().count(), 1);
        std::fs::remove_dir_all(d).ok();
    }

    #[test]
    fn a_file_is_replaced_whole_and_the_extension_kept_for_the_temporary() {
        let d = dir("replace");
        let p = d.join("a.png");
        write_bytes(&p, b"one").unwrap();
        write_bytes(&p, b"two").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"two");
        assert!(temp_sibling(&p).to_string_lossy().ends_with(".tmp.png"));
        // a folder in the way is not a regular file
        let sub = d.join("sub.csv");
        std::fs::create_dir_all(&sub).unwrap();
        assert!(write_bytes(&sub, b"x").is_err());
        std::fs::remove_dir_all(d).ok();
    }
}
