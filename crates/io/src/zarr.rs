//! The small part of Zarr v3 a sharded plan writes (<https://zarr-specs.readthedocs.io/en/latest/v3/core/index.html>):
//! a group (`zarr.json` with attributes and inline consolidated metadata), arrays on a regular
//! chunk grid with the default chunk-key encoding (`c/0/1`), the `bytes` codec (little endian,
//! uncompressed) for numbers and flags, and zarr-python's `vlen-utf8` codec for strings (the
//! `string` data type, which xarray reads as text). Every chunk file is written whole by an
//! atomic rename ([`crate::safe_write`]), so a chunk is either absent (the fill value) or complete,
//! and writers of different chunks need no lock.
//!
//! Why written here rather than with the `zarrs` crate: `zarrs` needs Rust 1.91 while every crate
//! of the workspace builds with 1.87 (rust-version), and a plan needs none of its codecs,
//! storage back-ends or readers — the metadata is a few JSON documents and an uncompressed chunk
//! is the values' bytes. Raising the MSRV for that (and compiling its dependency tree in every
//! build of the CLI) bought nothing the hidden format details do not already give: the tests
//! open these stores with zarr-python 3 and xarray (python/tests/test_distributed.py).

use crate::output::OutputError;
use crate::safe_write::write_bytes;
use serde_json::{json, Value};
use std::path::Path;

/// The element type of an array.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DataType {
    /// `float64`, fill value NaN.
    F64,
    /// `int64`, fill value 0 (or the array's fill value).
    I64,
    /// `int8`, fill value -1 (codes with `flag_values`).
    I8,
    /// `bool`, fill value false.
    Bool,
    /// zarr-python's variable-length UTF-8 `string`, fill value "".
    Str,
}

impl DataType {
    fn name(self) -> &'static str {
        match self {
            DataType::F64 => "float64",
            DataType::I64 => "int64",
            DataType::I8 => "int8",
            DataType::Bool => "bool",
            DataType::Str => "string",
        }
    }

    fn fill(self) -> Value {
        match self {
            DataType::F64 => json!("NaN"),
            DataType::I64 => json!(0),
            DataType::I8 => json!(-1),
            DataType::Bool => json!(false),
            DataType::Str => json!(""),
        }
    }
}

/// The values of one chunk, in C order over the whole chunk shape (an edge chunk is padded with
/// the fill value, as [`Chunk::filled`] makes it).
#[derive(Clone, Debug, PartialEq)]
pub enum Chunk {
    /// `float64` values.
    F64(Vec<f64>),
    /// `int64` values.
    I64(Vec<i64>),
    /// `int8` values.
    I8(Vec<i8>),
    /// `bool` values.
    Bool(Vec<bool>),
    /// `string` values.
    Str(Vec<String>),
}

impl Chunk {
    /// Encodes the chunk: little-endian bytes, or the `vlen-utf8` layout (item count, then each
    /// item's byte length and bytes, lengths as little-endian u32).
    pub fn encode(&self) -> Vec<u8> {
        match self {
            Chunk::F64(v) => v.iter().flat_map(|x| x.to_le_bytes()).collect(),
            Chunk::I64(v) => v.iter().flat_map(|x| x.to_le_bytes()).collect(),
            Chunk::I8(v) => v.iter().flat_map(|x| x.to_le_bytes()).collect(),
            Chunk::Bool(v) => v.iter().map(|&b| u8::from(b)).collect(),
            Chunk::Str(v) => {
                let mut out = Vec::new();
                out.extend((v.len() as u32).to_le_bytes());
                for s in v {
                    out.extend((s.len() as u32).to_le_bytes());
                    out.extend(s.as_bytes());
                }
                out
            }
        }
    }

    /// The data type of the values.
    pub fn data_type(&self) -> DataType {
        match self {
            Chunk::F64(_) => DataType::F64,
            Chunk::I64(_) => DataType::I64,
            Chunk::I8(_) => DataType::I8,
            Chunk::Bool(_) => DataType::Bool,
            Chunk::Str(_) => DataType::Str,
        }
    }

    /// An all-fill chunk of `n` values of type `t`.
    pub fn filled(t: DataType, n: usize) -> Chunk {
        match t {
            DataType::F64 => Chunk::F64(vec![f64::NAN; n]),
            DataType::I64 => Chunk::I64(vec![0; n]),
            DataType::I8 => Chunk::I8(vec![-1; n]),
            DataType::Bool => Chunk::Bool(vec![false; n]),
            DataType::Str => Chunk::Str(vec![String::new(); n]),
        }
    }

    /// Sets value `at` from value `from` of `src` (same type).
    pub fn set_from(&mut self, at: usize, src: &Chunk, from: usize) {
        match (self, src) {
            (Chunk::F64(a), Chunk::F64(b)) => a[at] = b[from],
            (Chunk::I64(a), Chunk::I64(b)) => a[at] = b[from],
            (Chunk::I8(a), Chunk::I8(b)) => a[at] = b[from],
            (Chunk::Bool(a), Chunk::Bool(b)) => a[at] = b[from],
            (Chunk::Str(a), Chunk::Str(b)) => a[at] = b[from].clone(),
            _ => panic!("chunk types differ"),
        }
    }
}

/// The metadata (`zarr.json`) of an array of `shape` on chunks of `chunk` with dimension names
/// `dims` and `attributes`.
pub fn array_meta(
    t: DataType,
    shape: &[usize],
    chunk: &[usize],
    dims: &[&str],
    attributes: Value,
) -> Value {
    let codec = match t {
        DataType::Str => json!({"name": "vlen-utf8", "configuration": {}}),
        DataType::I8 | DataType::Bool => json!({"name": "bytes", "configuration": {}}),
        _ => json!({"name": "bytes", "configuration": {"endian": "little"}}),
    };
    json!({
        "zarr_format": 3,
        "node_type": "array",
        "shape": shape,
        "data_type": t.name(),
        "chunk_grid": {"name": "regular", "configuration": {"chunk_shape": chunk}},
        "chunk_key_encoding": {"name": "default", "configuration": {"separator": "/"}},
        "fill_value": t.fill(),
        "codecs": [codec],
        "attributes": attributes,
        "dimension_names": dims,
        "storage_transformers": [],
    })
}

/// The metadata of a group with `attributes` and the metadata of its arrays `members` (name,
/// metadata) consolidated inline, as zarr-python 3 writes and reads it (`must_understand`
/// false: other readers list the arrays themselves).
pub fn group_meta(attributes: Value, members: &[(String, Value)]) -> Value {
    let metadata: serde_json::Map<String, Value> = members.iter().cloned().collect();
    json!({
        "zarr_format": 3,
        "node_type": "group",
        "attributes": attributes,
        "consolidated_metadata": {
            "kind": "inline",
            "must_understand": false,
            "metadata": metadata,
        },
    })
}

/// Writes a metadata document as `dir/zarr.json` (pretty JSON, keys in a fixed order).
pub fn write_meta(dir: &Path, meta: &Value) -> Result<(), OutputError> {
    std::fs::create_dir_all(dir).map_err(|source| OutputError::Io {
        path: dir.display().to_string(),
        source,
    })?;
    let text = serde_json::to_string_pretty(meta).expect("JSON values serialise");
    write_bytes(&dir.join("zarr.json"), text.as_bytes())
}

/// Writes the chunk at grid coordinates `at` of the array in `dir` (whole, by an atomic rename).
/// Returns the file written and its bytes.
pub fn write_chunk(
    dir: &Path,
    at: &[usize],
    chunk: &Chunk,
) -> Result<(std::path::PathBuf, Vec<u8>), OutputError> {
    let mut path = dir.join("c");
    for (k, i) in at.iter().enumerate() {
        if k + 1 < at.len() {
            path = path.join(i.to_string());
        }
    }
    std::fs::create_dir_all(&path).map_err(|source| OutputError::Io {
        path: path.display().to_string(),
        source,
    })?;
    let name = at.last().map_or("0".to_string(), |i| i.to_string());
    let file = path.join(name);
    let bytes = chunk.encode();
    write_bytes(&file, &bytes)?;
    Ok((file, bytes))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chunks_encode_as_zarr_python_reads_them() {
        assert_eq!(Chunk::I64(vec![1, -1]).encode().len(), 16);
        assert_eq!(Chunk::Bool(vec![true, false]).encode(), vec![1, 0]);
        assert_eq!(
            Chunk::Str(vec!["ab".into(), String::new()]).encode(),
            vec![2, 0, 0, 0, 2, 0, 0, 0, b'a', b'b', 0, 0, 0, 0]
        );
        let m = array_meta(DataType::F64, &[3, 4], &[2, 4], &["F", "omega"], json!({}));
        assert_eq!(m["fill_value"], "NaN");
        assert_eq!(m["dimension_names"][1], "omega");
    }
}
