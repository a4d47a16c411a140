//! Sweeps beyond one machine: a plan split into shards over a Zarr v3 store, each shard computed
//! by any process on any machine (a Slurm array task, a Dask worker), then merged into the
//! single command's folder.
//!
//! * [`plan`] writes the store: the resolved [`Request`] (the options the single command would
//!   use), the geardyn version, a hash of the request and the shard table as attributes of the
//!   root group, the coordinate arrays, and the metadata of every result array (inline
//!   consolidated). A shard writes whole chunks of the result arrays: one chunk when the grid allows
//!   a regular chunking into the shards asked, else a run of row or cell chunks.
//! * [`run_shard`] computes one shard: the single command's job run on the shard's items
//!   ([`crate::execute_items`]; the lanes give the same per-point results whatever the grouping
//!   of the points) into the shard's [`ShardStore`], which writes its chunk
//!   of every array (whole files renamed into place: no locks, a rerun writes the same bytes)
//!   and last its done marker `shards/<I>.json`, which holds the shard's typed results (the
//!   records a folder checkpoint holds) and is renamed into place atomically.
//! * [`status`] lists done and missing shards; [`merge`] checks that all are done and writes the
//!   single command's folder from the markers with its own writers ([`crate::request`]), plus
//!   the Parquet table of the runs when built with the `parquet` feature, and rewrites the
//!   consolidated metadata.
//!
//! A store is refused when it was planned by another geardyn version, when its request does not
//! hash to the hash it carries (edited or corrupt), and [`plan`] refuses a store that holds a plan
//! of another request.

use crate::job::{execute_items, ExecError};
use crate::jobs::{MapJob, SweepJob};
use crate::request::{FolderWriteError, Request};
use crate::store::Store;
use geardyn_analysis::bifurcation::{SweepMode, Task, TaskResult};
use geardyn_analysis::classify::Motion;
use geardyn_analysis::map2d::MapCell;
use geardyn_io::checkpoint::fnv1a;
use geardyn_io::output::OutputError;
use geardyn_io::safe_write::{read_bounded, write_bytes};
use geardyn_io::zarr::{self, Chunk, DataType};
use serde::{Deserialize, Serialize};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// The format of a plan this version writes and reads.
pub const FORMAT: &str = "geardyn-plan/1";
/// Most strobe points kept per run in the `strobe_x`/`strobe_v` arrays of a bifurcation store.
pub const MAX_STROBE: usize = 10_000;
/// Largest metadata document read (`zarr.json` holds the request: kilobytes).
pub(super) const MAX_META: u64 = 64 << 20;
/// Largest done marker (and chunk file) read.
pub(super) const MAX_MARKER: u64 = 4 << 30;

/// Why a plan, a shard or a merge failed.
#[derive(Debug, thiserror::Error)]
pub enum ShardError {
    /// Bad input, named (the store, a shard index, the request).
    #[error("{0}")]
    Input(String),
    /// A file could not be written.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// The merged folder could not be written.
    #[error(transparent)]
    Folder(#[from] FolderWriteError),
    /// The computation refused its options.
    #[error("{0}")]
    Analysis(String),
}

pub(super) fn input(s: impl Into<String>) -> ShardError {
    ShardError::Input(s.into())
}

/// One chunk of the result arrays: its coordinates in the chunk grid and the region of the grid
/// it covers (`start..stop` per dimension).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ChunkSpec {
    /// Chunk coordinates in the chunk grid.
    pub chunk: Vec<usize>,
    /// First index of the region, per grid dimension.
    pub start: Vec<usize>,
    /// One past the last index, per grid dimension.
    pub stop: Vec<usize>,
}

/// One shard: the chunks it alone writes (one, when the grid's shape allows a regular chunking
/// into the shards asked; else a run of consecutive row or cell chunks).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ShardSpec {
    /// Shard index (the Slurm array index).
    pub shard: usize,
    /// Its chunks, in row-major order.
    pub chunks: Vec<ChunkSpec>,
}

impl ShardSpec {
    /// Points of the grid (cells, or values x initial states) the shard covers.
    pub fn points(&self) -> usize {
        self.chunks
            .iter()
            .map(|c| {
                c.start
                    .iter()
                    .zip(&c.stop)
                    .map(|(a, b)| b - a)
                    .product::<usize>()
            })
            .sum()
    }
}

/// The plan a store holds (the root group's attribute `geardyn`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Plan {
    /// [`FORMAT`].
    pub format: String,
    /// geardyn version that made the plan (another version refuses it).
    pub version: String,
    /// Git commit of that build, when known (for the record).
    pub git_commit: Option<String>,
    /// Hash of the request's JSON (FNV-1a 64, hex).
    pub config_hash: String,
    /// The grid's dimension names (swept parameters; `ic` for multi-initial).
    pub dims: Vec<String>,
    /// The grid's shape.
    pub shape: Vec<usize>,
    /// The chunk shape (a chunk belongs to one shard).
    pub chunk: Vec<usize>,
    /// The shard table.
    pub shards: Vec<ShardSpec>,
    /// The resolved request.
    pub request: Request,
}

/// The hash of a request (FNV-1a 64 of its JSON, hex).
pub fn request_hash(r: &Request) -> String {
    let text = serde_json::to_string(r).expect("a request serialises");
    format!("{:016x}", fnv1a(text.as_bytes()))
}

mod layout;
mod merge;
mod plan;
mod store;

use layout::*;
use merge::read_marker;
pub use merge::{merge, Merged};
pub use plan::{open, plan, Planned};
use store::*;
pub use store::{run_shard, shard_index, status, ShardRun, ShardStore, Status};
