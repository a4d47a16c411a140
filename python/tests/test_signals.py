"""geardyn.indicators on synthetic signals with known answers, and geardyn.signals (the
library's signals request, the CLI's columns and numbers)."""

import csv
import math

import numpy as np
import pytest

import geardyn

NAMES = [
    "rms", "peak_to_peak", "crest_factor", "kurtosis", "fm0", "fm4", "m6a", "m8a",
    "na4", "nb4", "er", "sideband_index", "sideband_level_factor",
]


def revolutions(f, spr, revs):
    """``f(theta)`` sampled ``spr`` times per revolution over ``revs`` revolutions."""
    theta = 2 * np.pi * np.arange(spr * revs) / spr
    return f(theta)


def test_a_pure_sine_has_kurtosis_1_5_and_crest_sqrt_2():
    x = revolutions(lambda t: 2.0 * np.sin(20 * t), 256, 4)
    d = geardyn.indicators(x, samples_per_rev=256, mesh_order=20)
    assert list(d) == NAMES
    assert all(isinstance(v, float) for v in d.values())
    assert d["kurtosis"] == pytest.approx(1.5, abs=1e-12)
    assert d["crest_factor"] == pytest.approx(math.sqrt(2), abs=1e-12)
    assert d["rms"] == pytest.approx(2 / math.sqrt(2), rel=1e-12)
    assert d["peak_to_peak"] == pytest.approx(4.0, rel=1e-12)
    # all of it at the mesh order: FM0 = p2p / A(z1) = 2, no sidebands
    assert d["fm0"] == pytest.approx(2.0, rel=1e-12)
    assert d["sideband_index"] < 1e-12


def test_gaussian_noise_has_kurtosis_3():
    rng = np.random.default_rng(20261126)
    x = rng.standard_normal(1 << 16)
    d = geardyn.indicators(x, samples_per_rev=1 << 12, mesh_order=100)
    assert d["kurtosis"] == pytest.approx(3.0, abs=0.1)
    # moments recomputed here
    m = x - x.mean()
    assert d["kurtosis"] == pytest.approx(np.mean(m**4) / np.mean(m**2) ** 2, rel=1e-10)
    assert d["rms"] == pytest.approx(np.sqrt(np.mean(x**2)), rel=1e-12)
    assert d["crest_factor"] == pytest.approx(np.max(np.abs(x)) / d["rms"], rel=1e-12)
    # the TSA of 16 revolutions of noise is noise: FM4 of its difference signal near 3
    assert d["fm4"] == pytest.approx(3.0, abs=0.3)


def test_a_periodic_impulse_train_has_fm4_far_above_3():
    spr, z = 512, 16
    x = revolutions(lambda t: np.cos(z * t), spr, 8)
    x[100::spr] += 5.0  # one impulse per revolution: a broken tooth
    d = geardyn.indicators(x, samples_per_rev=spr, mesh_order=z)
    assert d["fm4"] > 50 and d["na4"] > 50
    assert d["m8a"] > d["m6a"] > d["fm4"]
    assert d["er"] > 0.1 and d["sideband_level_factor"] > 0
    clean = geardyn.indicators(
        revolutions(lambda t: np.cos(z * t), spr, 8), samples_per_rev=spr, mesh_order=z
    )
    assert clean["er"] < 1e-9


def test_amplitude_modulation_makes_sidebands():
    # a mesh tone at order 30 modulated once per revolution: sidebands at 29 and 31 of 0.25
    x = revolutions(lambda t: (1 + 0.5 * np.cos(t)) * np.cos(30 * t), 360, 2)
    d = geardyn.indicators(x, samples_per_rev=360, mesh_order=30)
    assert d["sideband_index"] == pytest.approx(0.25, rel=1e-9)


def test_na4_over_a_run_uses_the_mean_variance():
    rng = np.random.default_rng(1)
    base = rng.standard_normal(256)
    own = geardyn.indicators(2 * base, samples_per_rev=64, mesh_order=8)
    run = geardyn.indicators(2 * base, samples_per_rev=64, mesh_order=8, run=[base])
    assert run["na4"] / own["na4"] == pytest.approx((4 / 2.5) ** 2, rel=1e-9)
    assert run["fm4"] == own["fm4"]
    with pytest.raises(ValueError, match="run"):
        geardyn.indicators(base, samples_per_rev=64, mesh_order=8, run=[base[:128]])


@pytest.mark.parametrize(
    "signal, kw, word",
    [
        (np.r_[np.ones(63), np.nan], dict(samples_per_rev=32, mesh_order=4), "signal"),
        (np.ones(16), dict(samples_per_rev=32, mesh_order=4), "samples_per_rev"),
        (np.ones(100), dict(samples_per_rev=32, mesh_order=4), "samples_per_rev"),
        (np.ones(64), dict(samples_per_rev=32, mesh_order=15), "mesh_order"),
        (np.ones(64), dict(samples_per_rev=32, mesh_order=0), "mesh_order"),
        (np.ones(64), dict(samples_per_rev=32, mesh_order=4, residual="x"), "residual"),
        (np.ones((8, 8)), dict(samples_per_rev=32, mesh_order=4), "array"),
    ],
)
def test_bad_input_names_the_argument(signal, kw, word):
    with pytest.raises(ValueError, match=word) as e:
        geardyn.indicators(signal, **kw)
    assert "allowed" in str(e.value) or word in ("array",)


def test_mesh_order_error_gives_the_range():
    with pytest.raises(ValueError, match=r"2 \.\.= 14"):
        geardyn.indicators(np.ones(64), samples_per_rev=32, mesh_order=15)
    # a negative order too: the range the sampling allows, with the value given
    with pytest.raises(ValueError, match=r"mesh_order = -3: allowed 2 \.\.= 14"):
        geardyn.indicators(np.ones(64), samples_per_rev=32, mesh_order=-3)


def test_signals_have_the_clis_columns_and_numbers(cli, tmp_path):
    kw = dict(omega=1.2, F=0.15, transient=40, revolutions=4, samples_per_cycle=8,
              segment_revolutions=2)
    r = geardyn.signals(**kw)
    assert list(r.signals) == ["pair", "tau", "dte_um", "mesh_force_N", "acceleration_m_s2"]
    assert list(r.spectrum) == ["pair", "signal", "order", "amplitude"]
    assert list(r.indicators) == ["pair", "signal", "indicator", "value"]
    assert set(r.signals["pair"]) == {"healthy", "broken"}
    assert len(r.indicators["value"]) == 2 * 3 * 13
    assert r.info["result"]["options"]["mesh_order"] == 40
    pytest.importorskip("pandas")
    df = r.to_dataframe()
    assert set(df["indicator"]) == set(NAMES)
    # the same numbers as the CLI's indicators.csv
    out = tmp_path / "s"
    cli("signals", "--set", "omega=1.2", "--set", "F=0.15", "--transient", "40",
        "--revolutions", "4", "--samples-per-cycle", "8", "--segment-revolutions", "2",
        "--out", out)
    rows = list(csv.DictReader(open(out / "indicators.csv")))
    assert [float(x["value"]) for x in rows] == list(r.indicators["value"])


def test_signals_refuse_a_configuration_without_a_pair():
    with pytest.raises(ValueError, match=r"\[pair\]"):
        geardyn.signals("classic")
