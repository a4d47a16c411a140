//! Merging a plan's shards into the single command's folder ([`merge`]).

use super::*;
pub(super) fn read_marker<T: serde::de::DeserializeOwned>(
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
    let started = geardyn_io::run_record::now_unix_s();
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
        geardyn_io::run_record::claim_folder(&out)
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
                geardyn_io::schema::map_table(&r.options.x_param, &r.options.y_param, &cells),
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
            (
                runs,
                geardyn_io::schema::runs_table(&r.options.param, &results),
            )
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
pub(super) fn write_parquet(
    out: &Path,
    plan: &Plan,
    table: &geardyn_io::schema::Table,
) -> Result<Option<PathBuf>, ShardError> {
    let name = match plan.request {
        Request::Map2d(_) => "map.parquet",
        Request::Bifurcation(_) => "runs.parquet",
    };
    let path = out.join(name);
    geardyn_io::parquet_table::write_table(&path, table)?;
    Ok(Some(path))
}

#[cfg(not(feature = "parquet"))]
pub(super) fn write_parquet(
    _out: &Path,
    _plan: &Plan,
    _table: &geardyn_io::schema::Table,
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
