"""geardyn.orbits: the library's orbits request, with the CLI's columns and numbers."""

import csv

import pytest

import geardyn

COLUMNS = [
    "branch", "x", "v", "period", "label", "stable",
    "mu1_re", "mu1_im", "mu2_re", "mu2_im", "max_force", "p_id",
]


def test_one_orbit_has_its_multipliers_and_the_clis_columns(cli, tmp_path):
    r = geardyn.orbits("classic", omega=0.8)
    b = r.branch
    assert list(b) == COLUMNS
    assert b["stable"][0] and b["period"][0] == 1 and b["label"][0] == "1-1-0"
    assert abs(complex(b["mu1_re"][0], b["mu1_im"][0])) < 1
    # the same numbers as the CLI's branch.csv
    out = tmp_path / "o"
    cli("orbits", "--preset", "classic", "--set", "omega=0.8", "--out", out)
    rows = list(csv.DictReader(open(out / "branch.csv")))
    assert list(rows[0]) == list(b)
    assert float(rows[0]["x"]) == b["x"][0]
    assert float(rows[0]["mu1_re"]) == b["mu1_re"][0]


def test_a_branch_finds_the_doubling_of_c1():
    r = geardyn.orbits("classic", omega=0.8, param="omega", range=(0.8, 0.95))
    kinds = list(r.bifurcations["kind"])
    assert "period-doubling" in kinds
    w = r.bifurcations["omega"][kinds.index("period-doubling")]
    assert 0.8769 < w < 0.8844
    assert list(r.branch)[0] == "omega"
    pytest.importorskip("pandas")
    df = r.to_dataframe()
    assert df["stable"].any() and not df["stable"].all()


@pytest.mark.parametrize(
    "kw, text",
    [
        (dict(param="omega"), "param and range"),
        (dict(period=2**40), "bad period"),
        (dict(period=0), "period"),
        (dict(param="omega", range=(0.5, 1), ds=-1), "bad ds"),
        (dict(param="nonsense", range=(0.5, 1)), "nonsense"),
    ],
)
def test_bad_settings_name_the_setting(kw, text):
    with pytest.raises(ValueError) as e:
        geardyn.orbits("classic", **kw)
    assert text in str(e.value)


def test_a_non_number_names_the_setting():
    with pytest.raises(TypeError, match="ds"):
        geardyn.orbits("classic", param="omega", range=(0.5, 1), ds="a")
