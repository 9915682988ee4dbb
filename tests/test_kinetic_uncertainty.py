"""The kinetic relaxation times' uncertainty bands (`analysis.kinetic_uncertainty`) and the
N-body times read from reference copies of summaries."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from hmfdiff.analysis import kinetic_uncertainty as ku
from hmfdiff.analysis.relaxation_compare import (
    band_lines,
    with_kinetic_bands,
    with_layer_model,
    with_reference_md,
)
from hmfdiff.kinetic.relaxation import RelaxationSettings

ROOT = Path(__file__).resolve().parents[1]
TABLE = ROOT / "docs" / "reference" / "kinetic_time_uncertainty.csv"
LARGE_N = ROOT / "docs/reference/experiments/hothalo_large_n/relaxation_comparison_summary.txt"

SETTINGS = RelaxationSettings(equation="landau", kappa_max=3.5).as_dict()


def _row(**values):
    row = {
        "case": "corehalo_hothalo",
        "equation": "landau",
        "settings": dict(SETTINGS),
        "tau_R_fine": 100.0,
        "tau_R_fine_grid": 102.0,
        "tau_R_fine_harmonics": 97.0,
        "tau_R_coarse": 50.0,
        "tau_R_coarse_grid": 51.0,
        "tau_R_coarse_harmonics": 49.5,
        "dM0dtau_early": 1e-4,
        "dM0dtau_early_grid": 1.1e-4,
        "dM0dtau_early_harmonics": 1.05e-4,
    }
    row.update(values)
    return row


def test_band_adds_each_direction_from_the_default_value():
    low, high, rg, rh = ku.time_band(
        [_row()], "corehalo_hothalo", "landau", SETTINGS, "tau_R_fine", 100.5
    )
    assert rg == pytest.approx(0.02) and rh == pytest.approx(-0.03)
    assert low == pytest.approx(100.5 * 0.97) and high == pytest.approx(100.5 * 1.02)
    # both refinements raise it: the band lies above the value
    low, high, *_ = ku.time_band(
        [_row()], "corehalo_hothalo", "landau", SETTINGS, "dM0dtau_early", 1e-4
    )
    assert low == pytest.approx(1e-4) and high == pytest.approx(1e-4 * 1.15)


def test_no_band_for_other_settings_cases_or_a_stale_table():
    rows = [_row()]
    other = {**SETTINGS, "n_nodes": 48}
    assert ku.time_band(rows, "corehalo_hothalo", "landau", other, "tau_R_fine", 100.0) is None
    assert ku.time_band(rows, "corehalo_ch2", "landau", SETTINGS, "tau_R_fine", 100.0) is None
    with pytest.warns(UserWarning, match="stale"):
        assert (
            ku.time_band(
                rows,
                "corehalo_hothalo",
                "landau",
                SETTINGS,
                "tau_R_fine",
                100.0 * (1 + 2 * ku.STALE),
            )
            is None
        )
    with pytest.raises(ValueError, match="quantity"):
        ku.time_band(rows, "corehalo_hothalo", "landau", SETTINGS, "tau", 100.0)


def test_table_round_trip_and_a_wrong_file_refused(tmp_path):
    path = tmp_path / "t.csv"
    row = _row()
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(row))
        w.writeheader()
        w.writerow({**row, "settings": json.dumps(row["settings"], default=list)})
    (back,) = ku.read_uncertainty_table(path)
    assert back["tau_R_coarse_grid"] == 51.0 and back["settings"]["n_nodes"] == 600
    bad = tmp_path / "bad.csv"
    bad.write_text("case,equation\nx,y\n")
    with pytest.raises(ValueError, match="not the kinetic uncertainty table"):
        ku.read_uncertainty_table(bad)


def _comparison(tau_landau):
    ds = xr.Dataset(
        {"tau_relax_coarse_landau": ((), tau_landau)},
        coords={"N": ("N", [1000, 2000])},
        attrs={"case": "corehalo_hothalo"},
    )
    kin = {"landau": xr.Dataset(attrs={"settings": json.dumps(SETTINGS, default=list)})}
    return ds, kin


def test_comparison_dataset_gets_the_band_or_nan():
    ds, kin = _comparison(50.2)
    out = with_kinetic_bands(ds, kin, [_row()])
    low, high = out["tau_relax_coarse_landau_band"].values
    assert low == pytest.approx(50.2 * 0.99) and high == pytest.approx(50.2 * 1.02)
    assert "grid x1.5: +2.00%" in band_lines(out)[0]
    out = with_kinetic_bands(ds, kin, [])
    assert np.isnan(out["tau_relax_coarse_landau_band"].values).all()
    assert "no numerical uncertainty band" in band_lines(out)[0]


def test_large_n_times_read_from_their_reference_copy():
    text = LARGE_N.read_text()
    times = ku.md_times_from_summary(text, "corehalo_hothalo")
    assert sorted(times) == [8000, 16000]
    assert times[8000] == (4.427e5, 2.1e4) and times[16000] == (1.11e6, 5.4e4)
    # the same lines' t_R/N
    for n, (t, _) in times.items():
        line = next(x for x in text.splitlines() if x.strip().startswith(f"MD N = {n}:"))
        per_n = float(line.split("t_R/N = ")[1].split(";")[0])
        assert t / n == pytest.approx(per_n, rel=2e-3)
    assert ku.md_times_from_summary(text, "corehalo_ch2") == {}
    ds, _ = _comparison(50.0)
    ds = ds.assign_coords(N=("N", [1000, 8000]))
    out = with_reference_md(ds, times, "ref.txt")
    assert out["N_reference"].values.tolist() == [16000]  # 8000 is the dataset's own
    assert out["t_relax_md_reference"].values[0] == 1.11e6


@pytest.mark.skipif(not TABLE.exists(), reason="no uncertainty table in this checkout")
def test_reference_table_is_for_the_reproductions_settings():
    """The table's default lines were run with config/config.yaml's settings (or the band
    would never be drawn): compared here field by field."""
    import yaml

    block = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())["relaxation"]
    rows = ku.read_uncertainty_table(TABLE)
    assert {(r["case"], r["equation"]) for r in rows} >= {
        ("corehalo_hothalo", "landau"),
        ("corehalo_hothalo", "lenard_balescu"),
    }
    for r in rows:
        run = (block.get("runs") or {}).get(r["case"]) or {}
        expect = RelaxationSettings(
            equation=r["equation"],
            **{
                k: v
                for k, v in {**block, **run}.items()
                if k in RelaxationSettings.__dataclass_fields__ and k != "flux_times"
            },
        ).as_dict()
        for key in ku.SETTINGS_COMPARED:
            assert r["settings"][key] == pytest.approx(expect[key]), (r["case"], key)


LAYER_TEXT = """header line N=5 delta=1
hot lenard_balescu  N=1000 delta=9.240e-03  854  132.38  138.402  1.90329e-03  9.88718e-04  3e-7 1
hot lenard_balescu  N=4000 delta=4.685e-03  885  127.09  131.452  1.24972e-03  1.01131e-03  7e-7 1
hot   landau  N=1000 delta=9.240e-03    854    60.00      62.500  1.0e-03   1.5e-04  3.1e-07     127
ch2   landau  N=1000 delta=9.240e-03    854    60.00      62.500  1.0e-03   1.5e-04  3.1e-07     127
"""


def test_layer_model_times_are_read_and_drawn_only_beside_a_band():
    times = ku.layer_model_times(LAYER_TEXT, "corehalo_hothalo")
    assert times["lenard_balescu"] == {
        1000: (9.24e-3, 138.402, 9.88718e-4),
        4000: (4.685e-3, 131.452, 1.01131e-3),
    }
    assert times["landau"] == {1000: (9.24e-3, 62.5, 1.5e-4)}
    assert ku.layer_model_times(LAYER_TEXT, "corehalo_ch2") == {}
    ds, kin = _comparison(50.2)
    with_band = with_kinetic_bands(ds, kin, [_row()])
    out = with_layer_model(with_band, times, "f.txt")
    assert out["tau_relax_coarse_landau_layer_model"].values.tolist() == [62.5]
    assert out["N_layer_landau"].values.tolist() == [1000]
    # no band for Lenard-Balescu here (no kinetic time at all): no model either
    assert "tau_relax_coarse_lenard_balescu_layer_model" not in out
    # a stale or absent table: no band, no model
    assert "tau_relax_coarse_landau_layer_model" not in with_layer_model(
        with_kinetic_bands(ds, kin, []), times, "f.txt"
    )
