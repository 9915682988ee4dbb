"""Integrity of the netCDF files: checksums, physical sanity checks at the readers, atomic writes,
and validation flags for every bin whose MD or theory value is not finite."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from hmfdiff.analysis.fits import VALIDATION_FLAGS, diffusion_fit, validation_rows
from hmfdiff.pipeline.io import InputFileError, atomic_path, read_dataset, write_dataset


def md_like(seed=0, n_bin=6, n_lag=40, n_block=3):
    """A dataset shaped like one MD realisation (results/md/...): sums of squared displacements
    and counts per bin, lag and block, and a time series."""
    rng = np.random.default_rng(seed)
    lag = np.arange(n_lag) * 0.5
    count_block = rng.integers(50, 100, size=(n_bin, n_lag, n_block))
    slope = np.linspace(1e-3, 3e-3, n_bin)[:, None, None]
    sum_block = count_block * (2 * slope * lag[None, :, None] + 1e-4) * rng.uniform(0.9, 1.1)
    edges = np.linspace(0.0, 1.2, n_bin + 1)
    t = np.arange(100) * 0.5

    def v(dims, data, units, long_name):
        return xr.Variable(dims, data, {"units": units, "long_name": long_name})

    ds = xr.Dataset(
        {
            "sum_dJbar2": v(("bin", "lag"), sum_block.sum(-1), "action^2", "sum of dJbar^2"),
            "count": v(("bin", "lag"), count_block.sum(-1), "1", "pairs in the sums"),
            "sum_dJbar2_block": v(("bin", "lag", "block"), sum_block, "action^2", "per block"),
            "count_block": v(("bin", "lag", "block"), count_block, "1", "pairs per block"),
            "n_particles_in_bin": v(("bin",), np.full(n_bin, 500), "1", "particles per bin"),
            "Mx": v(("time",), 0.7 + 1e-3 * rng.standard_normal(t.size), "1", "magnetisation"),
        },
        coords={
            "lag": v(("lag",), lag, "time", "time lag"),
            "time": v(("time",), t, "time", "time since the start"),
            "jbar_edges": v(("edge",), edges, "action", "bin edges in J-bar_0"),
            "jbar0": v(("bin",), 0.5 * (edges[1:] + edges[:-1]), "action", "bin centres"),
        },
        attrs={"N": 1000, "M0_actions": 0.7, "dynamics": "full", "seed": seed},
    )
    return ds


def _bytes_offset(path, array):
    """Offset in the file of the stored (little-endian, uncompressed) bytes of `array`."""
    raw = path.read_bytes()
    off = raw.find(np.ascontiguousarray(array).astype("<f8").tobytes()[:64])
    assert off > 0, "the data bytes were not found in the file"
    return off


def _overwrite(path, offset, n=32):
    with open(path, "r+b") as fh:
        fh.seek(offset)
        fh.write(bytes(range(0xA0, 0xA0 + n)))


def test_every_variable_is_written_with_a_checksum(tmp_path):
    import netCDF4

    path = write_dataset(md_like(), tmp_path / "seed0.nc")
    with netCDF4.Dataset(path) as nc:
        for name, var in nc.variables.items():
            assert var.ndim == 0 or var.filters()["fletcher32"], name


def test_corrupted_chunk_is_a_read_error_naming_the_file(tmp_path):
    """32 bytes overwritten inside `sum_dJbar2`: the read fails and names the file.  The same
    bytes overwritten in a file written without checksums (the old files) read back silently as
    other numbers: the corruption really lands in the data."""
    ds = md_like()
    middle = ds["sum_dJbar2"].size * 8 // 2
    path = write_dataset(ds, tmp_path / "seed0.nc")
    _overwrite(path, _bytes_offset(path, ds["sum_dJbar2"].values) + middle)
    with pytest.raises(InputFileError, match=r"seed0\.nc: not a readable netCDF file"):
        read_dataset(path, required=["sum_dJbar2"])

    plain = tmp_path / "plain.nc"
    ds.to_netcdf(plain, engine="netcdf4")
    _overwrite(plain, _bytes_offset(plain, ds["sum_dJbar2"].values) + middle)
    silent = read_dataset(plain)
    assert not np.array_equal(silent["sum_dJbar2"].values, ds["sum_dJbar2"].values)


@pytest.mark.parametrize(
    "variable, value, message",
    [
        ("sum_dJbar2", -3e300, "'sum_dJbar2' is a sum of squares but negative"),
        ("sum_dJbar2_block", np.nan, "'sum_dJbar2_block' is a sum of squares but negative or not"),
        ("count", 2.5, "'count' is a count but not a whole number >= 0"),
        ("count_block", -1, "'count_block' is a count but not a whole number >= 0"),
        ("jbar_edges", 0.0, "'jbar_edges' is not finite and strictly increasing"),
    ],
)
def test_fit_refuses_impossible_md_values_naming_file_and_variable(
    tmp_path, variable, value, message
):
    """The values a corrupted file without checksum could hold (the issue's ND_md = -3e300 came
    from such a file): the fit stops, naming the file and the variable."""
    good = md_like(seed=1)
    bad = md_like(seed=2)
    if variable == "count":
        bad["count"] = bad["count"].astype(float)
    data = bad[variable].values.copy()
    data.flat[data.size // 2] = value
    bad[variable] = (bad[variable].dims, data, bad[variable].attrs)
    paths = []
    for name, ds in (("seed1.nc", good), ("seed2.nc", bad)):
        ds.to_netcdf(tmp_path / name, engine="netcdf4")  # no checksum: an old file
        paths.append(tmp_path / name)
    seeds = [read_dataset(p) for p in paths]
    with pytest.raises(InputFileError, match=rf"seed2\.nc: variable {message}"):
        diffusion_fit(seeds, window=(5.0, 15.0), min_particles=10)
    fit = diffusion_fit([seeds[0], read_dataset(paths[0])], window=(5.0, 15.0), min_particles=10)
    assert np.all(np.isfinite(fit["ND_md"].values))  # the good files still fit


@pytest.mark.parametrize(
    "variable, change, message",
    [
        ("time", lambda t: t[::-1], "'time' is not strictly increasing"),
        ("lag", lambda t: np.where(np.arange(t.size) == 5, t[4], t), "'lag' is not strictly"),
    ],
)
def test_reader_refuses_a_time_axis_that_does_not_increase(tmp_path, variable, change, message):
    ds = md_like()
    ds = ds.assign_coords({variable: (variable, change(ds[variable].values), ds[variable].attrs)})
    ds.to_netcdf(tmp_path / "old.nc", engine="netcdf4")
    with pytest.raises(InputFileError, match=rf"old\.nc: variable {message}"):
        read_dataset(tmp_path / "old.nc")


def test_reader_honours_valid_range(tmp_path):
    ds = md_like()
    ds["Mx"].attrs.update(valid_min=-1.0, valid_max=1.0)
    ds.to_netcdf(tmp_path / "ok.nc", engine="netcdf4")
    read_dataset(tmp_path / "ok.nc")
    ds["Mx"].values[3] = 7.0
    ds.to_netcdf(tmp_path / "bad.nc", engine="netcdf4")
    with pytest.raises(InputFileError, match=r"bad\.nc: variable 'Mx' lies outside its valid"):
        read_dataset(tmp_path / "bad.nc")


def test_write_refuses_a_variable_without_units_and_leaves_nothing(tmp_path):
    ds = md_like()
    del ds["Mx"].attrs["units"]
    with pytest.raises(ValueError, match=r"\['Mx'\] lack 'units' or 'long_name'"):
        write_dataset(ds, tmp_path / "x.nc")
    assert list(tmp_path.iterdir()) == []


def test_atomic_path_leaves_no_file_behind(tmp_path):
    """A failing writer leaves neither the target nor its temporary file; a temporary file that
    a killed writer left behind is deleted by the next writer of the same target, and only
    that one."""
    target = tmp_path / "fig.png"
    with pytest.raises(RuntimeError), atomic_path(target) as tmp:
        tmp.write_bytes(b"half")
        raise RuntimeError("killed")
    assert list(tmp_path.iterdir()) == []
    stale = tmp_path / ".fig.png.k1ll3d_x.part"  # as a SIGKILL leaves it (mkstemp name)
    other = tmp_path / ".fig.pdf.k1ll3d_x.part"
    stale.write_bytes(b"half")
    other.write_bytes(b"half")
    with atomic_path(target) as tmp:
        tmp.write_bytes(b"whole")
    assert target.read_bytes() == b"whole"
    assert sorted(p.name for p in tmp_path.iterdir()) == [other.name, "fig.png"]


def _fit_and_theory():
    """A fit of six bins (flags from the fit: bin 1 few particles) and a theory grid whose
    values are NaN in a masked band covering bin 3."""
    kappa0 = np.array([0.2, 0.4, 0.6, 0.97, 1.3, 1.6])
    fit = xr.Dataset(
        {
            "ND_md": ("bin", np.array([1.0, 1.1, np.nan, 0.9, 1.2, 1.0])),
            "ND_md_err": ("bin", np.array([0.1, 0.1, np.nan, 0.1, np.nan, 0.1])),
            "n_particles_in_bin": ("bin", np.array([900, 5, 0, 800, 700, 600])),
            "flag": ("bin", np.array([0, 1, 0, 0, 0, 0], dtype=np.int8)),
            "kappa0": ("bin", kappa0),
            "J0": ("bin", kappa0),
            "M0": ((), 0.7),
        },
        coords={"jbar_edges": ("edge", np.linspace(0, 2, 7))},
        attrs={"dynamics": "full", "n_seeds": 3},
    )
    kappa = np.linspace(0.05, 2.0, 40)
    D = np.where(np.abs(kappa - 1) < 0.05, np.nan, 1.0 + 0.1 * kappa)
    theory = xr.Dataset({"D_lenard_balescu": ("kappa", D)}, coords={"kappa": kappa})
    return fit, theory


def test_validation_flags_every_bin_whose_md_or_theory_is_not_finite():
    fit, theory = _fit_and_theory()
    rows = validation_rows("case", fit, theory)
    flags = [r["flag"] for r in rows]
    # bin 1: the fit's flag; 2: MD not finite; 3: theory NaN; 4: no error bar; 0 and 5: ok
    assert flags == [0, 1, 3, 4, 5, 0]
    for r in rows:
        finite = all(np.isfinite(r[k]) for k in ("ND_md", "ND_theory", "ND_md_err"))
        assert (r["flag"] == 0) == (finite and r["n_particles_in_bin"] >= 10)
    assert set(flags) <= set(VALIDATION_FLAGS)


def test_validation_refuses_a_negative_theory_naming_the_variable(tmp_path):
    fit, theory = _fit_and_theory()
    theory["D_lenard_balescu"].values[10] = -2.0
    theory.to_netcdf(tmp_path / "theory.nc", engine="netcdf4")
    with pytest.raises(InputFileError, match=r"theory\.nc: variable 'D_lenard_balescu' is neg"):
        validation_rows("case", fit, read_dataset(tmp_path / "theory.nc"))
