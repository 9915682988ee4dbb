"""Integrity of the netCDF files: checksums, physical sanity checks at the readers, atomic writes,
and validation flags for every bin whose MD or theory value is not finite."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from hmfdiff.analysis.fits import VALIDATION_FLAGS, diffusion_fit, validation_rows
from hmfdiff.pipeline.io import (
    InputFileError,
    atomic_path,
    check_physical,
    read_dataset,
    write_dataset,
)

ROOT = Path(__file__).resolve().parents[1]


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
            "Mx": v(("t",), 0.7 + 1e-3 * rng.standard_normal(t.size), "1", "magnetisation"),
        },
        coords={
            "lag": v(("lag",), lag, "time", "time lag"),
            "t": v(("t",), t, "time", "time since the start"),
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
        ("t", lambda t: t[::-1], "'t' is not strictly increasing"),
        ("lag", lambda t: np.where(np.arange(t.size) == 5, t[4], t), "'lag' is not strictly"),
    ],
)
def test_reader_refuses_a_time_axis_that_does_not_increase(tmp_path, variable, change, message):
    ds = md_like()
    ds = ds.assign_coords({variable: (variable, change(ds[variable].values), ds[variable].attrs)})
    ds.to_netcdf(tmp_path / "old.nc", engine="netcdf4")
    with pytest.raises(InputFileError, match=rf"old\.nc: variable {message}"):
        read_dataset(tmp_path / "old.nc")


@pytest.mark.parametrize(
    "limits", [dict(valid_min=-1.0, valid_max=1.0), dict(valid_range=np.array([-1.0, 1.0]))]
)
def test_reader_honours_valid_range(tmp_path, limits):
    """Both CF forms of the limits (valid_min/valid_max, valid_range) are enforced."""
    ds = md_like()
    ds["Mx"].attrs.update(limits)
    ds.to_netcdf(tmp_path / "ok.nc", engine="netcdf4")
    read_dataset(tmp_path / "ok.nc")
    ds["Mx"].values[3] = 7.0
    ds.to_netcdf(tmp_path / "bad.nc", engine="netcdf4")
    with pytest.raises(InputFileError, match=r"bad\.nc: variable 'Mx' lies outside its valid"):
        read_dataset(tmp_path / "bad.nc")


@pytest.mark.parametrize("value", [-1e-3, np.inf])
def test_nonnegative_check_refuses_negative_and_infinite_values(tmp_path, value):
    ds = md_like()
    ds["sum_dJbar2"].values.flat[7] = value
    ds.to_netcdf(tmp_path / "old.nc", engine="netcdf4")
    back = read_dataset(tmp_path / "old.nc")
    check_physical(back, nonnegative=["count"])  # other variables: not checked
    with pytest.raises(InputFileError, match=r"old\.nc: variable .sum_dJbar2. is negative or inf"):
        check_physical(back, nonnegative=["sum_dJbar2"])


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
        attrs={"dynamics": "full", "n_seeds": 3, "min_particles": 10, "separatrix_band": 0.03},
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


# ---- valid ranges declared by the writers (issue 20 part 8) ------------------------------
def _layouts():
    from hmfdiff.meanfield.equilibrium import make_state
    from hmfdiff.pipeline.layouts.equilibrium import equilibrium_dataset, orbits_dataset

    state = make_state({"kind": "thermal", "M0": 0.6})
    return equilibrium_dataset(state, 64, 2.5), orbits_dataset(state.M0, 64, 2.5, 3)


@pytest.mark.parametrize(
    "which, variable, index, value, message",
    [
        # a density written negative (a sign slip in the writer's physics): f >= 0
        (0, "f", 7, -1e-3, r"variable 'f' lies outside its valid range \[0, inf\] "),
        # a magnetisation above 1 (an unnormalised sum): M0 in [0, 1]
        (0, "M0", (), 1.25, r"variable 'M0' lies outside its valid range \[0, 1\] "),
        # an energy per particle below the ground state -1/2 (M0^2 instead of M0^2/2)
        (0, "u", (), -0.6, r"variable 'u' lies outside its valid range \[-0.5, inf\] "),
        # a Fourier coefficient of cos theta larger than 1 (a lost 1/2 pi)
        (1, "c", (1, 10), 3.0, r"variable 'c' lies outside its valid range \[-1, 1\] "),
    ],
)
def test_a_value_outside_the_writers_valid_range_is_refused_in_one_line(
    tmp_path, which, variable, index, value, message
):
    """The writer declares the range (layouts.variable's `valid`), the file carries it as
    valid_min / valid_max, and read_dataset refuses the file naming file, variable and range;
    the same dataset unchanged reads back."""
    ds = _layouts()[which]
    write_dataset(ds, tmp_path / "good.nc")
    read_dataset(tmp_path / "good.nc")
    data = ds[variable].values.copy()
    data[index] = value
    ds[variable] = (ds[variable].dims, data, ds[variable].attrs)
    write_dataset(ds, tmp_path / "bad.nc")
    with pytest.raises(InputFileError) as err:
        read_dataset(tmp_path / "bad.nc")
    msg = str(err.value)
    assert "\n" not in msg and msg.startswith(f"{tmp_path / 'bad.nc'}: "), msg
    assert re.search(message, msg), msg


#: the physical range every writer of the smoke run must declare, by file kind (a path
#: pattern under results/smoke): typed here from the physics, not read from the code.
#: None: an open side; "N": the number of particles of the file (attribute n_particles).
NONNEG = (0, None)
PHYSICAL_RANGES = {
    r"equilibrium/[^/]+\.nc": {
        **dict.fromkeys(["f", "density_of_states", "kappa_distribution", "kappa"], NONNEG),
        **dict.fromkeys(["beta", "mass"], NONNEG),
        "M0": (0, 1),
        "u": (-0.5, None),  # <p^2>/2 - M0^2/2 >= -1/2
    },
    r"orbits/[^/]+\.nc": {
        **dict.fromkeys(["J", "Jbar", "Omega", "dJ_dkappa", "kappa", "n"], NONNEG),
        **dict.fromkeys(["c", "sigma"], (-1, 1)),  # |(1/2pi) int cos or sin theta e^-inw| <= 1
        "M0": (0, 1),
    },
    r"theory/[^/]+\.nc": {
        **dict.fromkeys(["J", "Jbar", "Omega_orbit", "kappa", "resonance"], NONNEG),
        **dict.fromkeys(["D_landau", "D_lenard_balescu"], NONNEG),  # N D_dif >= 0
        **dict.fromkeys(["gamma_landau", "gamma_lenard_balescu"], NONNEG),
        "resonance_kappa_star": NONNEG,
        **dict.fromkeys(["resonance_n", "resonance_nprime"], (1, None)),
        **dict.fromkeys(["resonance_branch", "separatrix_mask", "M0"], (0, 1)),
    },
    r"analytic/[^/]+\.nc": {
        **dict.fromkeys(
            ["D_landau_sech4", "D_landau_small_kappa", "D_landau_librating_sum", "kappa"], NONNEG
        ),
        "D_lenard_balescu_closed": NONNEG,
        "M0": (0, 1),
    },
    r"(md/[^/]+/[^/]+/seeds\d+-\d+|scaling/[^/]+/[^/]+/N\d+/seeds)/seed\d+\.nc": {
        **dict.fromkeys(["sum_dJ2", "sum_dJbar2", "sum_dJ2_block", "sum_dJbar2_block"], NONNEG),
        **dict.fromkeys(
            ["count", "count_block", "n_particles_in_bin", "n_origins_in_block"], NONNEG
        ),
        **dict.fromkeys(["sample_J", "jbar_edges", "jbar0", "lag", "t", "time_fine"], NONNEG),
        **dict.fromkeys(["block", "tracer"], NONNEG),
        **dict.fromkeys(["Mx", "My", "Mx_fine", "My_fine"], (-1, 1)),
        "energy": (-1, None),  # bath: p^2/2 - M0 cos theta >= -1; full: H/N >= -1/2
    },
    r"(fits/[^/]+|scaling/[^/]+/[^/]+/N\d+/fit)\.nc": {
        **dict.fromkeys(["ND_md_err", "msd", "n_particles_in_bin", "kappa0", "J0"], NONNEG),
        **dict.fromkeys(["jbar0", "jbar_edges", "lag", "seed"], NONNEG),
        "M0": (0, 1),
        "flag": (0, 3),
    },
    r"scaling/[^/]+_(bath|full)\.nc": {
        **dict.fromkeys(["ND_md_err", "n_particles_in_bin", "kappa0", "jbar0"], NONNEG),
        **dict.fromkeys(["ND_theory", "ND_theory_other"], NONNEG),
        "M0": (0, 1),
        "drawn": (0, 1),
        **dict.fromkeys(["N", "n_seeds"], (1, None)),
        "flag": (0, 3),
    },
    r"windowed/[^/]+\.nc": dict.fromkeys(
        ["ND_spectrum", "ND_propagated", "jbar0", "kappa0"], NONNEG
    ),
    r"spectrum/[^/]+\.nc": {
        f"NS{c}_{d}{s}": NONNEG  # spectra: means of squared moduli, and their errors
        for c in "xy"
        for d in ("bath", "full")
        for s in ("", "_err", "_theory", "_smoothed", "_theory_fine")
    },
    r"relaxation_md/[^/]+/N\d+\.nc": {
        **dict.fromkeys(["M_abs", "M_abs_mean", "M_abs_std", "M0_actions"], (0, 1)),
        "M_phase": (-math.pi, math.pi),
        "energy": (-0.5, None),
        **dict.fromkeys(["hist", "overflow"], (0, "N")),
        **dict.fromkeys(["f_jbar", "t", "tau", "realisation", "jbar", "jbar_edges"], NONNEG),
    },
    r"relaxation/[^/]+\.nc": {
        **dict.fromkeys(
            ["f", "f_thermal", "f_thermal_analytic", "mass", "thermal_distance_max"], NONNEG
        ),
        **dict.fromkeys(["Sdot", "cell_width", "beta_thermal", "beta_thermal_grid"], NONNEG),
        **dict.fromkeys(["tau_relax_fine", "tau", "tau_flux", "Jbar", "Jbar_face"], NONNEG),
        **dict.fromkeys(["M0", "M0_thermal", "M0_thermal_grid"], (0, 1)),
        "u": (-0.5, None),
        **dict.fromkeys(["eta", "eta_face"], (-1, None)),  # kappa - 1, kappa >= 0
    },
}
#: variables with no physical bound of their own: a writer that bounds them would refuse
#: legitimate results (friction, currents, signed displacements, fitted slopes, entropies)
UNBOUNDED = {
    "dfdkappa", "dOmega_dkappa", "Dpol_landau", "Dpol_lenard_balescu", "Dpol_landau_sech4",
    "sum_dJ", "sum_dJ_block", "momentum", "sample_p", "ND_md", "ND_md_seed", "intercept",
    "ND_windowed", "flux", "flux_fokker_planck_tau0", "S", "beta_fit", "entropy",
    "entropy_realisation", "energy_drift", "eps_cc_real", "eps_cc_imag", "eps_ss_real",
    "eps_ss_imag", "Jbar_offset", "dM0dtau_initial", "dM0dtau_early", "tau_relax_initial_rate",
}  # fmt: skip


@pytest.fixture(scope="module")
def smoke_results(tmp_path_factory):
    from _smoke import smoke_workdir

    d = smoke_workdir(tmp_path_factory)
    return d / "results" / "smoke"


def test_every_writer_of_the_smoke_run_declares_the_physical_ranges(smoke_results):
    """Each netCDF file of the smoke run carries valid_min / valid_max on every variable with
    a physical range (and none on variables without one), and reads back within them."""
    files = sorted(smoke_results.rglob("*.nc"))
    seen = {pattern: set() for pattern in PHYSICAL_RANGES}
    for path in files:
        name = path.relative_to(smoke_results).as_posix()
        kinds = [p for p in PHYSICAL_RANGES if re.fullmatch(p, name)]
        ds = read_dataset(path)  # refuses a value outside a declared range
        for pattern in kinds:
            for var, (lo, hi) in PHYSICAL_RANGES[pattern].items():
                if var not in ds.variables:
                    continue
                seen[pattern].add(var)
                hi = ds.attrs["n_particles"] if hi == "N" else hi
                attrs = ds[var].attrs
                for key, bound in (("valid_min", lo), ("valid_max", hi)):
                    if bound is None:
                        assert key not in attrs, (name, var, key)
                    else:
                        assert key in attrs, (name, var, key)
                        assert float(attrs[key]) == pytest.approx(bound, rel=1e-12), (name, var)
        for var in UNBOUNDED & set(ds.variables):
            assert not {"valid_min", "valid_max", "valid_range"} & set(ds[var].attrs), (name, var)
    for pattern, expected in PHYSICAL_RANGES.items():
        assert seen[pattern] == set(expected), (pattern, set(expected) - seen[pattern])
