"""Sharded plans on Dask: the shards of a store made by ``geardyn plan`` computed by the workers of
a ``dask.distributed`` cluster (docs/distributed.md).

A plan is made with the command-line program, which takes the command's own arguments::

    geardyn plan map2d --preset classic --x omega:0.5:2:200 --y F:0.01:0.2:100 \\
        --shards 64 --out study.zarr

then, from Python::

    import geardyn.distributed as gd
    gd.run("study.zarr")                  # a LocalCluster of 2 worker processes
    gd.run("study.zarr", client=client)   # any Client: dask-jobqueue's SLURMCluster, ...
    gd.merge("study.zarr")                # map.csv, runs.csv, figures (and Parquet with pyarrow)

    import xarray as xr
    ds = xr.open_zarr("study.zarr")       # dims omega, F (bifurcation: the parameter, ic)

Each task computes one shard in its worker through the package's own binding (the same library
as ``geardyn run-shard``), writes that shard's chunk of every array and then its done marker: a
worker killed at its walltime loses only the shard it was computing, and :func:`run` called again
submits only the shards still missing. Shards never write the same file, so no lock is needed.
"""

from __future__ import annotations

import os
import uuid

from . import _geardyn

__all__ = ["run", "status", "merge", "run_shard"]


def _path(store) -> str:
    return os.fspath(store)


def status(store) -> dict:
    """Done and missing shards: ``{"command", "shards", "done": [...], "missing": [...],
    "damaged": [...]}`` (``damaged``: missing shards that had finished but whose chunk files
    changed since; run them again)."""
    return _geardyn.shard_status(_path(store))


def run_shard(store, shard=None) -> dict:
    """Computes one shard in this process (``geardyn run-shard STORE --shard I``; without
    ``shard``, the Slurm array index ``SLURM_ARRAY_TASK_ID``). A shard done already is kept.
    Returns ``{"shard", "points", "already"}``."""
    if shard is not None and (isinstance(shard, bool) or not isinstance(shard, int) or shard < 0):
        raise ValueError(f"bad shard {shard!r}: a non-negative integer")
    i, points, already = _geardyn.run_shard(_path(store), shard)
    return {"shard": i, "points": points, "already": already}


def _task(store: str, shard: int) -> dict:
    # runs in a worker: the binding there, one shard
    return run_shard(store, shard)


def run(store, client=None, shards=None) -> list:
    """Submits the missing shards of ``store`` (or those of ``shards`` still missing) to a
    ``dask.distributed`` ``client``, one task per shard, and waits for them.

    Without ``client``, a ``LocalCluster`` of 2 worker processes (one thread each; every shard
    uses the library's threads) is started for the call and closed after it. Returns the shards
    computed, in order. A failed shard raises its error after the others have finished; the
    store keeps every shard that finished, so calling ``run`` again resumes.
    """
    try:
        from dask.distributed import Client, LocalCluster, wait
    except ImportError as e:  # pragma: no cover - message only
        raise ImportError(
            "geardyn.distributed.run needs dask.distributed: pip install 'dask[distributed]'"
        ) from e
    store = _path(store)
    st = status(store)
    todo = [s for s in st["missing"] if shards is None or s in set(shards)]
    if not todo:
        return []
    own = client is None
    cluster = None
    if own:
        cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True)
        client = Client(cluster)
    try:
        # a fresh key per call: a rerun after a failure submits the shard again
        futures = [
            client.submit(_task, store, s, key=f"geardyn-shard-{s}-{uuid.uuid4().hex}")
            for s in todo
        ]
        wait(futures)
        errors = [f for f in futures if f.status != "finished"]
        if errors:
            errors[0].result()  # raises the first failure
        return [f.result()["shard"] for f in futures]
    finally:
        if own:
            client.close()
            cluster.close()


def merge(store, out=None, parquet=True) -> str:
    """Merges the shards into the single command's folder (``geardyn merge``): ``out``, or the
    store itself. With ``parquet`` and pyarrow installed, also the runs table as Parquet
    (``map.parquet`` or ``runs.parquet``) when the library was built without its own Parquet
    writer. Returns the folder."""
    folder = _geardyn.shard_merge(_path(store), None if out is None else _path(out))
    if parquet:
        st = status(store)
        name, csv = (
            ("map.parquet", "map.csv") if st["command"] == "map2d" else ("runs.parquet", "runs.csv")
        )
        target = os.path.join(folder, name)
        if not os.path.exists(target):
            try:
                import pyarrow.csv as pacsv
                import pyarrow.parquet as pq
            except ImportError:
                return folder
            pq.write_table(pacsv.read_csv(os.path.join(folder, csv)), target)
    return folder
