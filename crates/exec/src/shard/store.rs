//! A shard's part of the store: its chunks and done marker (the shard store of the executor,
//! [`ShardStore`]), the status of a plan's shards, and [`run_shard`].

use super::*;
/// A done marker: the shard's typed results, written last, with the digest of every chunk file
/// the shard wrote (a chunk truncated or replaced after it makes the shard not done).
#[derive(Serialize, Deserialize)]
pub(super) struct Marker<T> {
    pub(super) shard: usize,
    pub(super) config_hash: String,
    /// `(path relative to the store, FNV-1a digest of its bytes)` of each chunk file.
    pub(super) chunks: Vec<(String, String)>,
    pub(super) results: T,
}

/// The digest a marker records of a chunk file.
pub(super) fn digest(bytes: &[u8]) -> String {
    format!("{:016x}", fnv1a(bytes))
}

pub(super) fn marker_path(store: &Path, shard: usize) -> PathBuf {
    store.join("shards").join(format!("{shard}.json"))
}

/// Whether the marker of `shard` is there, of this plan.
pub(super) fn is_done(store: &Path, plan: &Plan, shard: usize) -> bool {
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
pub(super) fn region(c: &ChunkSpec, chunk: &[usize]) -> Vec<(usize, Vec<usize>)> {
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

pub(super) fn map_class(c: &MapCell) -> i8 {
    c.metric("class").map_or(3, |v| v as i8)
}

pub(super) fn run_class(m: &Motion) -> i8 {
    RUN_CLASSES
        .iter()
        .position(|w| *w == m.word())
        .map_or(5, |k| k as i8)
}

/// The values of one point of the grid (one map cell, or one run), per variable in
/// [`variables`] order; a variable with extra dimensions gives that many values.
pub(super) fn map_values(c: &MapCell) -> Vec<Chunk> {
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

pub(super) fn run_values(u: &geardyn_analysis::bifurcation::Run, strobe: usize) -> Vec<Chunk> {
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
pub(super) fn write_chunks(
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
pub(super) fn write_chunk_of(
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

/// The executor's store of one shard ([`crate::Store`]): a shard is all or nothing, so its
/// records are written whole at the end ([`crate::execute_items`] calls `finish`) as the shard's
/// chunk of every array and, last, its done marker with the records and the chunks' digests
/// (renamed into place). Opened on a shard done before, it gives the marker's records back.
pub struct ShardStore<'a> {
    store: &'a Path,
    plan: &'a Plan,
    spec: &'a ShardSpec,
}

impl<'a> ShardStore<'a> {
    /// Shard `spec` of `plan` in the store folder `store`.
    pub fn new(store: &'a Path, plan: &'a Plan, spec: &'a ShardSpec) -> Self {
        ShardStore { store, plan, spec }
    }

    fn done<T: serde::de::DeserializeOwned>(&self) -> Result<Vec<T>, ExecError> {
        if is_done(self.store, self.plan, self.spec.shard) {
            read_marker(self.store, self.plan, self.spec.shard).map_err(to_exec)
        } else {
            Ok(Vec::new())
        }
    }

    /// Writes the chunks (values of each grid point from `point`) and then the marker.
    fn complete<T: Serialize>(
        &self,
        results: &[T],
        point: &dyn Fn(&[usize]) -> Vec<Chunk>,
    ) -> Result<(), ExecError> {
        let chunks = write_chunks(self.store, self.plan, self.spec, point).map_err(to_exec)?;
        let shard = self.spec.shard;
        let marker = serde_json::to_string(&Marker {
            shard,
            config_hash: self.plan.config_hash.clone(),
            chunks,
            results,
        })
        .map_err(|e| ExecError::Store(format!("shard {shard}: results not serialisable: {e}")))?;
        // last: the marker, renamed into place whole
        write_bytes(&marker_path(self.store, shard), marker.as_bytes()).map_err(ExecError::Output)
    }
}

fn to_exec(e: ShardError) -> ExecError {
    match e {
        ShardError::Output(o) => ExecError::Output(o),
        other => ExecError::Store(other.to_string()),
    }
}

fn from_exec(e: ExecError) -> ShardError {
    match e {
        ExecError::Output(o) => ShardError::Output(o),
        other => ShardError::Analysis(other.to_string()),
    }
}

/// A record a shard store holds: how a shard's records complete the store (each point's values in
/// the chunks of the shard, written by [`ShardStore::complete`]).
trait ShardRecord: Serialize + serde::de::DeserializeOwned + Sized {
    /// Writes the shard's `records` into `store`.
    fn complete(store: &mut ShardStore<'_>, records: &[Self]) -> Result<(), ExecError>;
}

impl<R: ShardRecord> Store<R> for ShardStore<'_> {
    fn open(&mut self, _: &str, _: Value) -> Result<Vec<R>, ExecError> {
        self.done()
    }
    fn append(&self, _: &R) -> Result<(), ExecError> {
        Ok(())
    }
    fn finish(&mut self, records: &[R]) -> Result<(), ExecError> {
        R::complete(self, records)
    }
}

impl ShardRecord for MapCell {
    fn complete(store: &mut ShardStore<'_>, cells: &[MapCell]) -> Result<(), ExecError> {
        let Request::Map2d(r) = &store.plan.request else {
            return Err(ExecError::Store(
                "map cells in a store of another command".into(),
            ));
        };
        let nx = r.options.x_values.len();
        let by_index: std::collections::HashMap<usize, &MapCell> =
            cells.iter().map(|c| (c.index, c)).collect();
        store.complete(cells, &|at| map_values(by_index[&(at[0] * nx + at[1])]))
    }
}

impl ShardRecord for TaskResult {
    fn complete(store: &mut ShardStore<'_>, results: &[TaskResult]) -> Result<(), ExecError> {
        let Request::Bifurcation(r) = &store.plan.request else {
            return Err(ExecError::Store(
                "sweep runs in a store of another command".into(),
            ));
        };
        let strobe = strobe_len(r);
        let by_index: std::collections::HashMap<usize, &TaskResult> =
            results.iter().map(|t| (t.task.index, t)).collect();
        store.complete(results, &|at| {
            let t = by_index[&at[0]];
            run_values(&t.runs[at.get(1).copied().unwrap_or(0)], strobe)
        })
    }
}

/// Computes shard `shard` of the plan in `store` (see the module doc): the job of the plan's
/// request run on the shard's items into its [`ShardStore`]; a shard done already is left as it
/// is.
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
    let mut sink = ShardStore::new(store, &plan, &spec);
    match &plan.request {
        Request::Map2d(r) => {
            let nx = r.options.x_values.len();
            let indices: Vec<usize> = spec
                .chunks
                .iter()
                .flat_map(|c| region(c, &plan.chunk))
                .map(|(_, at)| at[0] * nx + at[1])
                .collect();
            let job = MapJob {
                scenario: &scenario,
                opts: &r.options,
            };
            execute_items(&job, &indices, &mut sink, &()).map_err(from_exec)?;
        }
        Request::Bifurcation(r) => {
            let tasks: Vec<Task> = spec
                .chunks
                .iter()
                .flat_map(|c| c.start[0]..c.stop[0])
                .map(|index| Task { index, branch: 0 })
                .collect();
            let job = SweepJob::new("bifurcation", &scenario, &r.options);
            execute_items(&job, &tasks, &mut sink, &()).map_err(from_exec)?;
        }
    }
    Ok(ShardRun {
        shard,
        points,
        already: false,
    })
}
