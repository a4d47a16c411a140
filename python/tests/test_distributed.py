"""Sharded plans on Dask (issue 32): the shards of a C1 map computed by a LocalCluster of 2 worker
processes, merged, equal the single-process ``geardyn map2d`` byte for byte; xarray opens the
store with dims named after the swept parameters. Skipped without dask, xarray or zarr, or
without the CLI binary (which makes the plan)."""

import pytest

distributed = pytest.importorskip("dask.distributed")
xr = pytest.importorskip("xarray")
pytest.importorskip("zarr")

import geardyn.distributed as gd  # noqa: E402

MAP = [
    "--preset", "classic",
    "--x", "omega:0.6:1.2:6",
    "--y", "F:0.05:0.2:5",
    "--periods", "20",
    "--transient", "60",
    "--decision-periods", "300",
]


def test_a_local_cluster_equals_the_single_process(cli, tmp_path):
    single = tmp_path / "single"
    store = tmp_path / "store.zarr"
    cli("map2d", *MAP, "--out", single)
    cli("plan", "map2d", *MAP, "--shards", "4", "--out", store)
    assert gd.status(store)["missing"] == [0, 1, 2, 3]
    # one shard here first (as a resumed run would find it), the rest on the cluster
    assert gd.run_shard(store, 2) == {"shard": 2, "points": 6, "already": False}
    done = gd.run(store)
    assert done == [0, 1, 3]
    assert gd.status(store)["missing"] == []
    assert gd.run(store) == []  # nothing left: nothing submitted
    folder = gd.merge(store)
    assert (store / "map.csv").read_bytes() == (single / "map.csv").read_bytes()
    assert folder == str(store)

    ds = xr.open_zarr(store)
    assert ds["max_force"].dims == ("F", "omega")
    assert ds.sizes == {"F": 5, "omega": 6}
    for v in ["class", "period", "label", "max_force", "p_id", "tle", "healthy"]:
        assert v in ds
    import csv

    with open(single / "map.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    # cell order iy * nx + ix: row k is (F index k // 6, omega index k % 6)
    for k, r in enumerate(rows):
        cell = ds.isel(F=k // 6, omega=k % 6)
        assert float(cell["omega"]) == float(r["omega"])
        assert float(cell["F"]) == float(r["F"])
        assert str(cell["label"].values) == r["label"]
        assert float(cell["max_force"]) == float(r["max_force"])
        assert int(cell["period"]) == int(r["period"])
    assert ds["class"].attrs["flag_meanings"].split()[0] == "healthy_periodic"


def test_bad_input_is_named(tmp_path):
    with pytest.raises(ValueError, match="no such folder"):
        gd.status(tmp_path / "nothing")
    with pytest.raises(ValueError, match="bad shard"):
        gd.run_shard(tmp_path / "nothing", -1)
