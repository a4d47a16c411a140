//! Writing a plan into a store ([`plan`]) and reading it back, verified ([`open`]).

use super::*;
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
        git_commit: geardyn_io::run_record::GIT_COMMIT.map(String::from),
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
