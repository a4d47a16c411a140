//! The layout of a plan's store: how the grid is cut into chunks and shards, the variables
//! (result arrays) of each command, the coordinate arrays and the Zarr metadata.

use super::*;
/// The region of each of `n` chunks along an axis of `len` with chunks of `c`.
pub(super) fn spans(len: usize, c: usize) -> Vec<(usize, usize)> {
    (0..len.div_ceil(c))
        .map(|k| (k * c, ((k + 1) * c).min(len)))
        .collect()
}

/// Chunk sizes along an axis of `len` that give distinct chunk counts, with those counts.
pub(super) fn chunk_options(len: usize) -> Vec<(usize, usize)> {
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
pub(super) fn chunking(shape: &[usize], split_dims: usize, n: usize) -> Vec<usize> {
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
pub(super) fn shard_table(shape: &[usize], chunk: &[usize], n: usize) -> Vec<ShardSpec> {
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
pub(super) struct Var {
    pub(super) name: &'static str,
    pub(super) t: DataType,
    pub(super) extra: Vec<(String, usize)>,
    pub(super) attrs: Value,
}

pub(super) fn var(name: &'static str, t: DataType, attrs: Value) -> Var {
    Var {
        name,
        t,
        extra: vec![],
        attrs,
    }
}

/// Codes of `class` in a map store (those of [`MapCell::metric`]`("class")`).
pub(super) const MAP_CLASSES: &str =
    "healthy_periodic non_healthy_periodic chaotic failed quasi_periodic unsettled";
/// Codes of `class` in a bifurcation store (the words of [`Motion::word`]).
pub(super) const RUN_CLASSES: [&str; 6] = [
    "periodic",
    "quasi-periodic",
    "chaotic",
    "unsettled",
    "diverged",
    "failed",
];

pub(super) fn class_attrs(meanings: &str) -> Value {
    json!({
        "flag_values": [0, 1, 2, 3, 4, 5],
        "flag_meanings": meanings,
        "long_name": "class of the motion (-1: not computed yet)",
    })
}

pub(super) fn common_vars() -> Vec<Var> {
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
pub(super) fn strobe_len(r: &crate::request::BifurcationRequest) -> usize {
    if r.options
        .sections
        .contains(&geardyn_analysis::bifurcation::Section::Strobe)
    {
        (r.options.sim.record_periods as usize).min(MAX_STROBE)
    } else {
        0
    }
}

pub(super) fn ics(r: &crate::request::BifurcationRequest) -> Option<usize> {
    match r.options.mode {
        SweepMode::Multi { ics, .. } => Some(ics.max(1)),
        _ => None,
    }
}

/// The result variables of a request.
pub(super) fn variables(req: &Request) -> Vec<Var> {
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
pub(super) fn grid(req: &Request) -> Result<(Vec<String>, Vec<usize>, usize), ShardError> {
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
pub(super) fn coordinates(req: &Request) -> Vec<(String, Chunk)> {
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
pub(super) fn array_metas(plan: &Plan) -> Vec<(String, Value)> {
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

pub(super) fn group_meta(plan: &Plan) -> Value {
    zarr::group_meta(
        json!({
            "geardyn": plan,
            "title": format!("geardyn {} plan", plan.request.command()),
        }),
        &array_metas(plan),
    )
}
