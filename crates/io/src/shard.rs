//! Sweeps beyond one machine: a plan split into shards over a Zarr v3 store, each shard computed
//! by any process on any machine (a Slurm array task, a Dask worker), then merged into the
//! single command's folder.
//!
//! * [`plan`] writes the store: the resolved [`Request`] (the options the single command would
//!   use), the geardyn version, a hash of the request and the shard table as attributes of the
//!   root group, the coordinate arrays, and the metadata of every result array (inline
//!   consolidated). A shard writes whole chunks of the result arrays: one chunk when the grid allows
//!   a regular chunking into the shards asked, else a run of row or cell chunks.
//! * [`run_shard`] computes one shard with the library functions of the single command
//!   ([`geardyn_analysis::map2d::map2d_cells`], [`geardyn_analysis::bifurcation::run_sweep_tasks`]:
//!   the lanes, the same per-point results whatever the grouping of the points), writes its chunk
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

use crate::checkpoint::fnv1a;
use crate::output::OutputError;
use crate::request::{FolderWriteError, Request};
use crate::safe_write::{read_bounded, write_bytes};
use crate::zarr::{self, Chunk, DataType};
use geardyn_analysis::bifurcation::{run_sweep_tasks, SweepMode, Task, TaskResult};
use geardyn_analysis::classify::Motion;
use geardyn_analysis::map2d::{map2d_cells, MapCell};
use serde::{Deserialize, Serialize};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// The format of a plan this version writes and reads.
pub const FORMAT: &str = "geardyn-plan/1";
/// Most strobe points kept per run in the `strobe_x`/`strobe_v` arrays of a bifurcation store.
pub const MAX_STROBE: usize = 10_000;
/// Largest metadata document read (`zarr.json` holds the request: kilobytes).
const MAX_META: u64 = 64 << 20;
/// Largest done marker (and chunk file) read.
const MAX_MARKER: u64 = 4 << 30;

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

fn input(s: impl Into<String>) -> ShardError {
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

/// The region of each of `n` chunks along an axis of `len` with chunks of `c`.
fn spans(len: usize, c: usize) -> Vec<(usize, usize)> {
    (0..len.div_ceil(c))
        .map(|k| (k * c, ((k + 1) * c).min(len)))
        .collect()
}

/// Chunk sizes along an axis of `len` that give distinct chunk counts, with those counts.
fn chunk_options(len: usize) -> Vec<(usize, usize)> {
    let mut out: Vec<(usize, usize)> = Vec::new();
    for count in 1..=len {
        let c = len.div_ceil(count);
        if len.div_ceil(c) == count {
            out.push((c, count));
        }
    }
    out
}

/// The chunk shape of a `shape` grid split along its first one or two dimensions (the rest
/// whole) for `n` shards: a regular chunking into exactly `n` chunks when one exists (whole rows
/// preferred: the second dimension split as little as possible), else single rows (single cells
/// when there are fewer rows than shards), grouped into shards by [`shard_table`].
fn chunking(shape: &[usize], split_dims: usize, n: usize) -> Vec<usize> {
    let mut chunk = shape.to_vec();
    if split_dims == 1 {
        chunk[0] = chunk_options(shape[0])
            .into_iter()
            .find(|&(_, k)| k == n)
            .map_or(1, |(c, _)| c);
        return chunk;
    }
    let rows = chunk_options(shape[0]);
    let cols = chunk_options(shape[1]);
    let mut best: Option<(usize, usize, usize)> = None; // (column chunks, cy, cx)
    for &(cy, ky) in &rows {
        for &(cx, kx) in &cols {
            if ky * kx == n && best.is_none_or(|b| kx < b.0) {
                best = Some((kx, cy, cx));
            }
        }
    }
    match best {
        Some((_, cy, cx)) => {
            chunk[0] = cy;
            chunk[1] = cx;
        }
        None => {
            chunk[0] = 1;
            if shape[0] < n {
                chunk[1] = 1;
            }
        }
    }
    chunk
}

/// The shard table of a grid of `shape` on chunks of `chunk` for `n` shards: the chunks in
/// row-major order, split into `n` runs of consecutive chunks as equal as can be.
fn shard_table(shape: &[usize], chunk: &[usize], n: usize) -> Vec<ShardSpec> {
    let per_dim: Vec<Vec<(usize, usize)>> = shape
        .iter()
        .zip(chunk)
        .map(|(&l, &c)| spans(l, c))
        .collect();
    let counts: Vec<usize> = per_dim.iter().map(Vec::len).collect();
    let total: usize = counts.iter().product();
    let chunks: Vec<ChunkSpec> = (0..total)
        .map(|s| {
            let mut rem = s;
            let mut coords = vec![0; counts.len()];
            for d in (0..counts.len()).rev() {
                coords[d] = rem % counts[d];
                rem /= counts[d];
            }
            ChunkSpec {
                start: coords
                    .iter()
                    .enumerate()
                    .map(|(d, &k)| per_dim[d][k].0)
                    .collect(),
                stop: coords
                    .iter()
                    .enumerate()
                    .map(|(d, &k)| per_dim[d][k].1)
                    .collect(),
                chunk: coords,
            }
        })
        .collect();
    let n = n.clamp(1, total.max(1));
    (0..n)
        .map(|s| ShardSpec {
            shard: s,
            chunks: chunks[s * total / n..(s + 1) * total / n].to_vec(),
        })
        .collect()
}

/// A result variable: name, type, extra trailing dimensions (name, length), attributes.
struct Var {
    name: &'static str,
    t: DataType,
    extra: Vec<(String, usize)>,
    attrs: Value,
}

fn var(name: &'static str, t: DataType, attrs: Value) -> Var {
    Var {
        name,
        t,
        extra: vec![],
        attrs,
    }
}

/// Codes of `class` in a map store (those of [`MapCell::metric`]`("class")`).
const MAP_CLASSES: &str =
    "healthy_periodic non_healthy_periodic chaotic failed quasi_periodic unsettled";
/// Codes of `class` in a bifurcation store (the words of [`Motion::word`]).
const RUN_CLASSES: [&str; 6] = [
    "periodic",
    "quasi-periodic",
    "chaotic",
    "unsettled",
    "diverged",
    "failed",
];

fn class_attrs(meanings: &str) -> Value {
    json!({
        "flag_values": [0, 1, 2, 3, 4, 5],
        "flag_meanings": meanings,
        "long_name": "class of the motion (-1: not computed yet)",
    })
}

fn common_vars() -> Vec<Var> {
    vec![
        var(
            "label",
            DataType::Str,
            json!({"long_name": "motion label n-p-q-r-s, or the class (empty: not computed yet)"}),
        ),
        var(
            "period",
            DataType::I64,
            json!({"long_name": "period in excitation periods (0: not periodic)"}),
        ),
        var(
            "healthy",
            DataType::Bool,
            json!({"long_name": "periodic without back-side contact or impact"}),
        ),
        var(
            "max_force",
            DataType::F64,
            json!({"long_name": "maximum mesh force", "units": "k_av b_c"}),
        ),
        var(
            "min_force",
            DataType::F64,
            json!({"long_name": "minimum mesh force", "units": "k_av b_c"}),
        ),
        var(
            "p_id",
            DataType::F64,
            json!({"long_name": "dynamic instability proportion"}),
        ),
        var(
            "impacts",
            DataType::I64,
            json!({"long_name": "back-side impacts in the record"}),
        ),
        var(
            "tle",
            DataType::F64,
            json!({"long_name": "top Lyapunov exponent (NaN: not computed)"}),
        ),
    ]
}

/// Strobe points kept per run of a bifurcation request (0: no strobe section).
fn strobe_len(r: &crate::request::BifurcationRequest) -> usize {
    if r.options
        .sections
        .contains(&geardyn_analysis::bifurcation::Section::Strobe)
    {
        (r.options.sim.record_periods as usize).min(MAX_STROBE)
    } else {
        0
    }
}

fn ics(r: &crate::request::BifurcationRequest) -> Option<usize> {
    match r.options.mode {
        SweepMode::Multi { ics, .. } => Some(ics.max(1)),
        _ => None,
    }
}

/// The result variables of a request.
fn variables(req: &Request) -> Vec<Var> {
    match req {
        Request::Map2d(_) => {
            let mut v = vec![var("class", DataType::I8, class_attrs(MAP_CLASSES))];
            v.extend(common_vars());
            v
        }
        Request::Bifurcation(r) => {
            let mut v = vec![
                var("x0", DataType::F64, json!({"long_name": "initial x"})),
                var("v0", DataType::F64, json!({"long_name": "initial v"})),
                var("class", DataType::I8, class_attrs(&RUN_CLASSES.join(" "))),
            ];
            v.extend(common_vars());
            let s = strobe_len(r);
            if s > 0 {
                for (name, what) in [("strobe_x", "x"), ("strobe_v", "v")] {
                    v.push(Var {
                        name,
                        t: DataType::F64,
                        extra: vec![("strobe".into(), s)],
                        attrs: json!({"long_name": format!("{what} at the stroboscopic instants of the record (the first {s}; NaN: fewer)")}),
                    });
                }
            }
            v
        }
    }
}

/// The grid of a request: dimension names, shape, how many leading dimensions shards split.
fn grid(req: &Request) -> Result<(Vec<String>, Vec<usize>, usize), ShardError> {
    match req {
        Request::Map2d(r) => {
            let o = &r.options;
            Ok((
                vec![o.y_param.clone(), o.x_param.clone()],
                vec![o.y_values.len(), o.x_values.len()],
                2,
            ))
        }
        Request::Bifurcation(r) => {
            if r.options.mode == SweepMode::Sweep {
                return Err(input(
                    "bifurcation --mode sweep cannot be sharded: each value starts from the previous one's final state (use --mode fixed or multi, or run it on one machine)",
                ));
            }
            let n = r.options.values.len();
            Ok(match ics(r) {
                Some(k) => (vec![r.options.param.clone(), "ic".into()], vec![n, k], 1),
                None => (vec![r.options.param.clone()], vec![n], 1),
            })
        }
    }
}

/// The coordinate arrays of a request: name, values (f64 or i64).
fn coordinates(req: &Request) -> Vec<(String, Chunk)> {
    match req {
        Request::Map2d(r) => vec![
            (
                r.options.x_param.clone(),
                Chunk::F64(r.options.x_values.clone()),
            ),
            (
                r.options.y_param.clone(),
                Chunk::F64(r.options.y_values.clone()),
            ),
        ],
        Request::Bifurcation(r) => {
            let mut c = vec![(
                r.options.param.clone(),
                Chunk::F64(r.options.values.clone()),
            )];
            if let Some(k) = ics(r) {
                c.push(("ic".into(), Chunk::I64((0..k as i64).collect())));
            }
            c
        }
    }
}

/// Every array's metadata (name, `zarr.json` content), coordinates first.
fn array_metas(plan: &Plan) -> Vec<(String, Value)> {
    let mut out = Vec::new();
    for (name, values) in coordinates(&plan.request) {
        let n = match &values {
            Chunk::F64(v) => v.len(),
            Chunk::I64(v) => v.len(),
            _ => 0,
        };
        out.push((
            name.clone(),
            zarr::array_meta(values.data_type(), &[n], &[n], &[&name], json!({})),
        ));
    }
    for v in variables(&plan.request) {
        let mut dims: Vec<&str> = plan.dims.iter().map(String::as_str).collect();
        let mut shape = plan.shape.clone();
        let mut chunk = plan.chunk.clone();
        for (d, n) in &v.extra {
            dims.push(d);
            shape.push(*n);
            chunk.push(*n);
        }
        out.push((
            v.name.to_string(),
            zarr::array_meta(v.t, &shape, &chunk, &dims, v.attrs),
        ));
    }
    out
}

fn group_meta(plan: &Plan) -> Value {
    zarr::group_meta(
        json!({
            "geardyn": plan,
            "title": format!("geardyn {} plan", plan.request.command()),
        }),
        &array_metas(plan),
    )
}

/// What [`plan`] did.
#[derive(Clone, Debug, PartialEq)]
pub struct Planned {
    /// Shards in the plan.
    pub shards: usize,
    /// Shards already done (a plan made before with the same request).
    pub done: usize,
    /// The plan was there already.
    pub existed: bool,
}

/// Writes the plan of `request` in `shards` shards into the store `store` (created). A store
/// that holds the same plan is kept as it is (its done shards stay done); one that holds another
/// plan, or a folder that is not a store, is refused.
pub fn plan(store: &Path, request: Request, shards: usize) -> Result<Planned, ShardError> {
    let (dims, shape, split) = grid(&request)?;
    let along: usize = shape[..split].iter().product();
    if shards == 0 || shards > along {
        return Err(input(format!(
            "bad --shards {shards}: allowed 1 ..= {along} (the points of the {} grid {})",
            request.command(),
            shape[..split]
                .iter()
                .map(|n| n.to_string())
                .collect::<Vec<_>>()
                .join(" x ")
        )));
    }
    let chunk = chunking(&shape, split, shards);
    let table = shard_table(&shape, &chunk, shards);
    let p = Plan {
        format: FORMAT.into(),
        version: env!("CARGO_PKG_VERSION").into(),
        git_commit: option_env!("GEARDYN_GIT_COMMIT").map(String::from),
        config_hash: request_hash(&request),
        dims,
        shape,
        chunk,
        shards: table,
        request,
    };
    if store.join("zarr.json").exists() {
        let old = open(store)?;
        if old.config_hash != p.config_hash || old.shards.len() != p.shards.len() {
            return Err(input(format!(
                "--out {}: the store holds a plan of another request (config hash {}, {} shards; this request: {}, {} shards): choose another --out, or remove the store to plan again",
                store.display(),
                old.config_hash,
                old.shards.len(),
                p.config_hash,
                p.shards.len()
            )));
        }
        let st = status(store)?;
        return Ok(Planned {
            shards: old.shards.len(),
            done: st.done.len(),
            existed: true,
        });
    }
    if let Ok(mut entries) = std::fs::read_dir(store) {
        if entries.next().is_some() {
            return Err(input(format!(
                "--out {}: a folder that is not empty and holds no plan (no zarr.json): give a new or empty folder",
                store.display()
            )));
        }
    }
    for (name, values) in coordinates(&p.request) {
        zarr::write_chunk(&store.join(&name), &[0], &values)?;
    }
    for (name, meta) in array_metas(&p) {
        zarr::write_meta(&store.join(name), &meta)?;
    }
    std::fs::create_dir_all(store.join("shards")).map_err(|source| OutputError::Io {
        path: store.join("shards").display().to_string(),
        source,
    })?;
    // the group's metadata last: a store without it is no plan (and may be planned again)
    zarr::write_meta(store, &group_meta(&p))?;
    Ok(Planned {
        shards: p.shards.len(),
        done: 0,
        existed: false,
    })
}

/// Reads and checks the plan of `store`: present, of this format and version, its request
/// hashing to its hash.
pub fn open(store: &Path) -> Result<Plan, ShardError> {
    let meta = store.join("zarr.json");
    if !store.is_dir() {
        return Err(input(format!(
            "STORE {}: no such folder (make one with `geardyn plan`)",
            store.display()
        )));
    }
    let bytes = read_bounded(&meta, MAX_META).map_err(|e| {
        input(format!(
            "STORE {}: no plan ({}: {e}); make one with `geardyn plan`",
            store.display(),
            meta.display()
        ))
    })?;
    let corrupt = |why: String| {
        input(format!(
            "STORE {}: not a readable geardyn plan ({why}); plan it again into a new folder",
            store.display()
        ))
    };
    let v: Value =
        serde_json::from_slice(&bytes).map_err(|e| corrupt(format!("zarr.json: {e}")))?;
    let g = v
        .get("attributes")
        .and_then(|a| a.get("geardyn"))
        .ok_or_else(|| corrupt("zarr.json has no attribute geardyn".into()))?;
    let format = g.get("format").and_then(Value::as_str).unwrap_or("");
    let version = g.get("version").and_then(Value::as_str).unwrap_or("");
    if format != FORMAT {
        return Err(corrupt(format!(
            "format '{format}', this geardyn reads {FORMAT}"
        )));
    }
    if version != env!("CARGO_PKG_VERSION") {
        return Err(input(format!(
            "STORE {}: planned by geardyn {version}, this is geardyn {}: results of another version would not merge with the same bytes; plan again with this version into a new folder",
            store.display(),
            env!("CARGO_PKG_VERSION")
        )));
    }
    let p: Plan =
        serde_json::from_value(g.clone()).map_err(|e| corrupt(format!("the plan: {e}")))?;
    let h = request_hash(&p.request);
    if h != p.config_hash {
        return Err(input(format!(
            "STORE {}: its request hashes to {h}, not to the config hash {} it was planned with (edited or corrupt); plan again into a new folder",
            store.display(),
            p.config_hash
        )));
    }
    let (dims, shape, split) = grid(&p.request).map_err(|e| corrupt(e.to_string()))?;
    if dims != p.dims
        || shape != p.shape
        || p.chunk.len() != shape.len()
        || p.chunk.contains(&0)
        || p.chunk[split..] != shape[split..]
        || p.shards.is_empty()
        || p.shards != shard_table(&p.shape, &p.chunk, p.shards.len())
    {
        return Err(corrupt("its shard table does not fit its request".into()));
    }
    Ok(p)
}

/// A done marker: the shard's typed results, written last, with the digest of every chunk file
/// the shard wrote (a chunk truncated or replaced after it makes the shard not done).
#[derive(Serialize, Deserialize)]
struct Marker<T> {
    shard: usize,
    config_hash: String,
    /// `(path relative to the store, FNV-1a digest of its bytes)` of each chunk file.
    chunks: Vec<(String, String)>,
    results: T,
}

/// The digest a marker records of a chunk file.
fn digest(bytes: &[u8]) -> String {
    format!("{:016x}", fnv1a(bytes))
}

fn marker_path(store: &Path, shard: usize) -> PathBuf {
    store.join("shards").join(format!("{shard}.json"))
}

/// Whether the marker of `shard` is there, of this plan.
fn is_done(store: &Path, plan: &Plan, shard: usize) -> bool {
    let Ok(bytes) = read_bounded(&marker_path(store, shard), MAX_MARKER) else {
        return false;
    };
    serde_json::from_slice::<Marker<serde::de::IgnoredAny>>(&bytes).is_ok_and(|m| {
        m.shard == shard
            && m.config_hash == plan.config_hash
            && !m.chunks.is_empty()
            && m.chunks.iter().all(|(rel, want)| {
                read_bounded(&store.join(rel), MAX_MARKER).is_ok_and(|b| digest(&b) == *want)
            })
    })
}

/// Done and missing shards of a store.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Status {
    /// The command planned.
    pub command: String,
    /// Shards in the plan.
    pub shards: usize,
    /// Shards done, in order.
    pub done: Vec<usize>,
    /// Shards missing, in order.
    pub missing: Vec<usize>,
    /// The missing shards that had finished but whose chunk files have changed since (truncated,
    /// removed or rewritten): their marker is there, their data is not theirs any more.
    pub damaged: Vec<usize>,
}

/// The done and missing shards of `store`.
pub fn status(store: &Path) -> Result<Status, ShardError> {
    let p = open(store)?;
    let (done, missing): (Vec<usize>, Vec<usize>) =
        (0..p.shards.len()).partition(|&s| is_done(store, &p, s));
    let damaged = missing
        .iter()
        .copied()
        .filter(|&s| marker_path(store, s).exists())
        .collect();
    Ok(Status {
        command: p.request.command().into(),
        shards: p.shards.len(),
        done,
        missing,
        damaged,
    })
}

/// The shard index to run: `shard`, else `SLURM_ARRAY_TASK_ID`.
pub fn shard_index(shard: Option<usize>) -> Result<usize, ShardError> {
    match shard {
        Some(s) => Ok(s),
        None => {
            let v = std::env::var("SLURM_ARRAY_TASK_ID").map_err(|_| {
                input("no --shard given and SLURM_ARRAY_TASK_ID is not set: give --shard I")
            })?;
            v.trim().parse().map_err(|_| {
                input(format!(
                    "SLURM_ARRAY_TASK_ID '{v}' is not a shard index (a non-negative integer)"
                ))
            })
        }
    }
}

/// What [`run_shard`] did.
#[derive(Clone, Debug, PartialEq)]
pub struct ShardRun {
    /// The shard.
    pub shard: usize,
    /// Points (cells or values) of the shard.
    pub points: usize,
    /// It was done already (nothing computed).
    pub already: bool,
}

/// The flat positions in a chunk of `chunk` shape of its region `c.start..c.stop` (grid
/// coordinates), in row-major order of the region, with their grid coordinates.
fn region(c: &ChunkSpec, chunk: &[usize]) -> Vec<(usize, Vec<usize>)> {
    let dims = c.start.len();
    let mut out = Vec::new();
    let mut idx = c.start.clone();
    if c.start.iter().zip(&c.stop).any(|(a, b)| a >= b) {
        return out;
    }
    loop {
        let mut flat = 0;
        for d in 0..dims {
            flat = flat * chunk[d] + (idx[d] - c.start[d]);
        }
        out.push((flat, idx.clone()));
        let mut d = dims;
        loop {
            if d == 0 {
                return out;
            }
            d -= 1;
            idx[d] += 1;
            if idx[d] < c.stop[d] {
                break;
            }
            idx[d] = c.start[d];
        }
    }
}

fn map_class(c: &MapCell) -> i8 {
    c.metric("class").map_or(3, |v| v as i8)
}

fn run_class(m: &Motion) -> i8 {
    RUN_CLASSES
        .iter()
        .position(|w| *w == m.word())
        .map_or(5, |k| k as i8)
}

/// The values of one point of the grid (one map cell, or one run), per variable in
/// [`variables`] order; a variable with extra dimensions gives that many values.
fn map_values(c: &MapCell) -> Vec<Chunk> {
    vec![
        Chunk::I8(vec![map_class(c)]),
        Chunk::Str(vec![c.label.clone()]),
        Chunk::I64(vec![c.period as i64]),
        Chunk::Bool(vec![c.healthy]),
        Chunk::F64(vec![c.max_force]),
        Chunk::F64(vec![c.min_force]),
        Chunk::F64(vec![c.p_id]),
        Chunk::I64(vec![c.impacts as i64]),
        Chunk::F64(vec![c.tle.unwrap_or(f64::NAN)]),
    ]
}

fn run_values(u: &geardyn_analysis::bifurcation::Run, strobe: usize) -> Vec<Chunk> {
    let mut v = vec![
        Chunk::F64(vec![u.y0[0]]),
        Chunk::F64(vec![u.y0[1]]),
        Chunk::I8(vec![run_class(&u.motion)]),
        Chunk::Str(vec![u.label.clone()]),
        Chunk::I64(vec![u.period as i64]),
        Chunk::Bool(vec![u.healthy]),
        Chunk::F64(vec![u.max_force]),
        Chunk::F64(vec![u.min_force]),
        Chunk::F64(vec![u.p_id]),
        Chunk::I64(vec![u.impacts as i64]),
        Chunk::F64(vec![u.tle.unwrap_or(f64::NAN)]),
    ];
    if strobe > 0 {
        let pts: Vec<(f64, f64)> = u
            .points
            .iter()
            .filter(|p| p.0 == geardyn_analysis::bifurcation::Section::Strobe)
            .map(|p| (p.1, p.2))
            .take(strobe)
            .collect();
        let mut xs = vec![f64::NAN; strobe];
        let mut vs = vec![f64::NAN; strobe];
        for (k, (x, v)) in pts.into_iter().enumerate() {
            xs[k] = x;
            vs[k] = v;
        }
        v.push(Chunk::F64(xs));
        v.push(Chunk::F64(vs));
    }
    v
}

/// Writes the chunks of shard `spec` of every variable from `point`, the values at a grid point.
/// Writes every chunk of `spec`; returns `(path relative to the store, digest)` of each file.
fn write_chunks(
    store: &Path,
    plan: &Plan,
    spec: &ShardSpec,
    point: &dyn Fn(&[usize]) -> Vec<Chunk>,
) -> Result<Vec<(String, String)>, ShardError> {
    let mut files = Vec::new();
    for c in &spec.chunks {
        files.extend(write_chunk_of(store, plan, c, point)?);
    }
    Ok(files)
}

/// Writes chunk `spec` of every variable from `point`.
fn write_chunk_of(
    store: &Path,
    plan: &Plan,
    spec: &ChunkSpec,
    point: &dyn Fn(&[usize]) -> Vec<Chunk>,
) -> Result<Vec<(String, String)>, ShardError> {
    let vars = variables(&plan.request);
    let per_point: usize = plan.chunk.iter().product();
    let mut chunks: Vec<Chunk> = vars
        .iter()
        .map(|v| {
            let extra: usize = v.extra.iter().map(|e| e.1).product();
            Chunk::filled(v.t, per_point * extra)
        })
        .collect();
    for (flat, at) in region(spec, &plan.chunk) {
        for (k, (vals, v)) in point(&at).iter().zip(&vars).enumerate() {
            let extra: usize = v.extra.iter().map(|e| e.1).product();
            for j in 0..extra {
                chunks[k].set_from(flat * extra + j, vals, j);
            }
        }
    }
    let mut files = Vec::new();
    for (v, c) in vars.iter().zip(&chunks) {
        let mut at = spec.chunk.clone();
        at.extend(v.extra.iter().map(|_| 0));
        let (file, bytes) = zarr::write_chunk(&store.join(v.name), &at, c)?;
        let rel = file.strip_prefix(store).unwrap_or(&file);
        // (forward slashes on every system: the marker is read wherever the store is)
        let rel: Vec<String> = rel
            .components()
            .map(|p| p.as_os_str().to_string_lossy().into_owned())
            .collect();
        files.push((rel.join("/"), digest(&bytes)));
    }
    Ok(files)
}

/// Computes shard `shard` of the plan in `store` (see the module doc); a shard done already is
/// left as it is.
pub fn run_shard(store: &Path, shard: usize) -> Result<ShardRun, ShardError> {
    let plan = open(store)?;
    let n = plan.shards.len();
    let spec = plan.shards.get(shard).cloned().ok_or_else(|| {
        input(format!(
            "--shard {shard} is out of range: the plan in {} has {n} shards (0 ..= {})",
            store.display(),
            n - 1
        ))
    })?;
    let points = spec.points();
    if is_done(store, &plan, shard) {
        return Ok(ShardRun {
            shard,
            points,
            already: true,
        });
    }
    let cfg = plan.request.config();
    let scenario = cfg
        .resolve()
        .map_err(|e| input(format!("the plan's configuration is rejected: {e}")))?;
    let marker = match &plan.request {
        Request::Map2d(r) => {
            let nx = r.options.x_values.len();
            let indices: Vec<usize> = spec
                .chunks
                .iter()
                .flat_map(|c| region(c, &plan.chunk))
                .map(|(_, at)| at[0] * nx + at[1])
                .collect();
            let cells = map2d_cells(&scenario, &r.options, &indices, |_| {})
                .map_err(|e| ShardError::Analysis(e.to_string()))?;
            if geardyn_solvers::cancel::requested() {
                return Err(ShardError::Analysis("interrupted".into()));
            }
            let by_index: std::collections::HashMap<usize, &MapCell> =
                cells.iter().map(|c| (c.index, c)).collect();
            let chunks = write_chunks(store, &plan, &spec, &|at| {
                map_values(by_index[&(at[0] * nx + at[1])])
            })?;
            serde_json::to_string(&Marker {
                shard,
                config_hash: plan.config_hash.clone(),
                chunks,
                results: &cells,
            })
        }
        Request::Bifurcation(r) => {
            let tasks: Vec<Task> = spec
                .chunks
                .iter()
                .flat_map(|c| c.start[0]..c.stop[0])
                .map(|index| Task { index, branch: 0 })
                .collect();
            let results = run_sweep_tasks(&scenario, &r.options, &tasks, |_| {})
                .map_err(|e| ShardError::Analysis(e.to_string()))?;
            if geardyn_solvers::cancel::requested() {
                return Err(ShardError::Analysis("interrupted".into()));
            }
            let strobe = strobe_len(r);
            let by_index: std::collections::HashMap<usize, &TaskResult> =
                results.iter().map(|t| (t.task.index, t)).collect();
            let chunks = write_chunks(store, &plan, &spec, &|at| {
                let t = by_index[&at[0]];
                run_values(&t.runs[at.get(1).copied().unwrap_or(0)], strobe)
            })?;
            serde_json::to_string(&Marker {
                shard,
                config_hash: plan.config_hash.clone(),
                chunks,
                results: &results,
            })
        }
    }
    .map_err(|e| ShardError::Analysis(format!("shard {shard}: results not serialisable: {e}")))?;
    // last: the marker, renamed into place whole
    write_bytes(&marker_path(store, shard), marker.as_bytes())?;
    Ok(ShardRun {
        shard,
        points,
        already: false,
    })
}

fn read_marker<T: serde::de::DeserializeOwned>(
    store: &Path,
    plan: &Plan,
    shard: usize,
) -> Result<T, ShardError> {
    let path = marker_path(store, shard);
    let bytes = read_bounded(&path, MAX_MARKER).map_err(|e| {
        input(format!(
            "shard {shard}: cannot read {}: {e}",
            path.display()
        ))
    })?;
    let m: Marker<T> = serde_json::from_slice(&bytes).map_err(|e| {
        input(format!(
            "shard {shard}: {} is corrupt ({e}): remove it and run the shard again",
            path.display()
        ))
    })?;
    if m.shard != shard || m.config_hash != plan.config_hash {
        return Err(input(format!(
            "shard {shard}: {} belongs to another plan: remove it and run the shard again",
            path.display()
        )));
    }
    Ok(m.results)
}

/// What [`merge`] wrote.
#[derive(Clone, Debug, PartialEq)]
pub struct Merged {
    /// The command's folder.
    pub out: PathBuf,
    /// The command.
    pub command: String,
    /// Points merged (cells or runs).
    pub points: usize,
    /// The Parquet table written, if any.
    pub parquet: Option<PathBuf>,
}

/// Merges the shards of `store` into the single command's folder `out` (the store itself when
/// `None`): refuses while shards are missing; can be rerun (it writes the same files again).
pub fn merge(store: &Path, out: Option<&Path>) -> Result<Merged, ShardError> {
    let started = crate::run_record::now_unix_s();
    let plan = open(store)?;
    let st = status(store)?;
    if !st.missing.is_empty() {
        let list: Vec<String> = st.missing.iter().take(20).map(|s| s.to_string()).collect();
        return Err(input(format!(
            "STORE {}: {} of {} shards not done ({}{}): run them first (`geardyn run-shard {} --shard I`)",
            store.display(),
            st.missing.len(),
            st.shards,
            list.join(", "),
            if st.missing.len() > 20 { ", ..." } else { "" },
            store.display()
        )));
    }
    let out = out.unwrap_or(store).to_path_buf();
    if out != store {
        // another folder: one geardyn may write into (new, empty or its own)
        crate::run_record::claim_folder(&out)
            .map_err(|e| input(format!("--out {}: {e}", out.display())))?;
    }
    let scenario = plan
        .request
        .config()
        .resolve()
        .map_err(|e| input(format!("the plan's configuration is rejected: {e}")))?;
    let (points, table) = match &plan.request {
        Request::Map2d(r) => {
            let mut cells: Vec<MapCell> = Vec::new();
            for s in 0..plan.shards.len() {
                cells.extend(read_marker::<Vec<MapCell>>(store, &plan, s)?);
            }
            cells.sort_by_key(|c| c.index);
            let total = r.options.x_values.len() * r.options.y_values.len();
            if cells.len() != total || cells.iter().enumerate().any(|(i, c)| c.index != i) {
                return Err(input(format!(
                    "STORE {}: the shards hold {} cells, not the map's {total}: remove shards/ and run them again",
                    store.display(),
                    cells.len()
                )));
            }
            r.write_folder(&out, &scenario, &cells, started)?;
            (
                cells.len(),
                crate::schema::map_table(&r.options.x_param, &r.options.y_param, &cells),
            )
        }
        Request::Bifurcation(r) => {
            let mut results: Vec<TaskResult> = Vec::new();
            for s in 0..plan.shards.len() {
                results.extend(read_marker::<Vec<TaskResult>>(store, &plan, s)?);
            }
            results.sort_by_key(|t| t.task.index);
            let n = r.options.values.len();
            if results.len() != n || results.iter().enumerate().any(|(i, t)| t.task.index != i) {
                return Err(input(format!(
                    "STORE {}: the shards hold {} values, not the sweep's {n}: remove shards/ and run them again",
                    store.display(),
                    results.len()
                )));
            }
            r.write_folder(&out, &scenario, &results, started)?;
            let runs = results.iter().map(|t| t.runs.len()).sum();
            (runs, crate::schema::runs_table(&r.options.param, &results))
        }
    };
    let parquet = write_parquet(&out, &plan, &table)?;
    // consolidate: the group's metadata with every array's metadata as the store holds it
    let mut members = Vec::new();
    for (name, _) in array_metas(&plan) {
        let bytes = read_bounded(&store.join(&name).join("zarr.json"), MAX_META)
            .map_err(|e| input(format!("STORE {}: array {name}: {e}", store.display())))?;
        let meta: Value = serde_json::from_slice(&bytes)
            .map_err(|e| input(format!("STORE {}: array {name}: {e}", store.display())))?;
        members.push((name, meta));
    }
    let mut g = group_meta(&plan);
    g["consolidated_metadata"]["metadata"] = Value::Object(members.into_iter().collect());
    zarr::write_meta(store, &g)?;
    Ok(Merged {
        out,
        command: plan.request.command().into(),
        points,
        parquet,
    })
}

#[cfg(feature = "parquet")]
fn write_parquet(
    out: &Path,
    plan: &Plan,
    table: &crate::schema::Table,
) -> Result<Option<PathBuf>, ShardError> {
    let name = match plan.request {
        Request::Map2d(_) => "map.parquet",
        Request::Bifurcation(_) => "runs.parquet",
    };
    let path = out.join(name);
    crate::parquet_table::write_table(&path, table)?;
    Ok(Some(path))
}

#[cfg(not(feature = "parquet"))]
fn write_parquet(
    _out: &Path,
    _plan: &Plan,
    _table: &crate::schema::Table,
) -> Result<Option<PathBuf>, ShardError> {
    Ok(None)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chunkings_give_the_shards_asked_when_a_regular_grid_can() {
        // 5 rows cannot make 4 row chunks: 2 x 2 blocks do
        assert_eq!(chunking(&[5, 6], 2, 4), vec![3, 3]);
        assert_eq!(chunking(&[8, 6], 2, 4), vec![2, 6]);
        assert_eq!(chunking(&[10, 8], 1, 4), vec![3, 8]);
        let t = shard_table(&[5, 6], &[3, 3], 4);
        assert_eq!(t.len(), 4);
        assert_eq!(t[3].chunks[0].start, vec![3, 3]);
        assert_eq!(t[3].chunks[0].stop, vec![5, 6]);
        let r = region(&t[3].chunks[0], &[3, 3]);
        assert_eq!(r.len(), 6);
        assert_eq!(r[4], (4, vec![4, 4]));
    }

    #[test]
    fn counts_no_regular_grid_makes_group_row_or_cell_chunks() {
        // 9 values in 4 shards: single values, 2 + 2 + 2 + 3
        assert_eq!(chunking(&[9], 1, 4), vec![1]);
        let t = shard_table(&[9], &[1], 4);
        let sizes: Vec<usize> = t.iter().map(ShardSpec::points).collect();
        assert_eq!(sizes, vec![2, 2, 2, 3]);
        // a 3 x 3 map in 7 shards: single cells; 9 rows of 5 in 7: single rows
        assert_eq!(chunking(&[3, 3], 2, 7), vec![1, 1]);
        assert_eq!(shard_table(&[3, 3], &[1, 1], 7).len(), 7);
        assert_eq!(chunking(&[9, 5], 2, 7), vec![1, 5]);
        let t = shard_table(&[9, 5], &[1, 5], 7);
        assert_eq!(t.iter().map(ShardSpec::points).sum::<usize>(), 45);
        assert!(t.iter().all(|s| !s.chunks.is_empty()));
    }
}
