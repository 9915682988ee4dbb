"""CF metadata that a maintained checker accepts (issue 22 part 5).

Every kind of netCDF output of the shared smoke run (one file per structure: stage folder,
variables, dimensions, attribute names) is given to the IOOS compliance checker
(`compliance-checker`, pinned in environment.txt; its CF 1.10 suite, run in-process) and must
raise no error: no result of weight 3 (the checker's "high priority", i.e. a violation of a
CF "shall") that failed.  Errors seen before this test: HMF unit descriptions that UDUNITS does
not parse, a dimension named `time` (CF then demands '<unit> since <epoch>', impossible for the
dimensionless HMF time), flag_values stored as text and flag meanings that are not single
words.  Warnings (weight 2) are allowed, except the one about names that differ only by case
(the theory file held Omega and omega; the orbital frequency is Omega_orbit there now).  The
integer types are also held to CF 1.8, which knows no 64-bit integers (the MD counters were
int64; `io.write_dataset` stores integers that fit in int32, all of them at paper size).

The units rule is enforced at the source: `layouts.variable`, `io.scalar` and
`io.write_dataset` refuse a unit string that is neither CF ("1", "rad") nor a named HMF
quantity, which is stored as "1" with the quantity in `comment`.
"""

from __future__ import annotations

import contextlib
import io as _io
import warnings

import netCDF4
import numpy as np
import pytest
import xarray as xr
import yaml
from _smoke import ROOT, SMOKE, smoke_workdir

from hmfdiff.pipeline import io, layouts

CF = "cf:1.10"
RESULTS_DIR = tuple(yaml.safe_load((ROOT / SMOKE).read_text())["results_dir"].split("/"))
#: output folders whose files are about one case: their title must name it
CASE_TITLED = ("relaxation", "relaxation_md", "spectrum", "windowed", "scaling", "fits")


@pytest.fixture(scope="module")
def smoke_files(tmp_path_factory):
    files = sorted(smoke_workdir(tmp_path_factory).glob("results/**/*.nc"))
    assert len(files) >= 40, files  # the smoke run writes 68 netCDF files (2026-11-25)
    return files


def cf_errors(files, cf=CF, weight=3, section=None):
    """(file name, message) for every failed result of the CF suite `cf` of weight `weight`, or
    of any weight in the section whose name starts with `section` (e.g. "§2.2")."""
    from compliance_checker.runner import CheckSuite

    suite = CheckSuite()
    with contextlib.redirect_stdout(_io.StringIO()), warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)  # its deprecated IOOS SOS checker
        suite.load_all_available_checkers()
    errors = []
    for path in files:
        ds = suite.load_dataset(str(path))
        try:
            groups = suite.run_all(ds, [cf], skip_checks=[])[cf][0]
        finally:
            ds.close()
        for g in groups:
            chosen = g.name.startswith(section) if section else g.weight == weight
            if chosen and g.value[0] < g.value[1]:
                errors += [(str(path), msg) for msg in (g.msgs or [g.name])]
    return errors


def structure(path):
    """What the CF checker reads of a file besides its values: the stage folder, the global
    attribute names, and each variable's name, dimensions, dtype and attribute names."""
    with xr.open_dataset(path, decode_cf=False) as ds:
        variables = tuple(
            sorted(
                (name, v.dims, str(v.dtype), tuple(sorted(v.attrs)))
                for name, v in ds.variables.items()
            )
        )
        return stage(path), tuple(sorted(ds.attrs)), variables


def stage(path):
    """The folder under the smoke run's results_dir that holds `path` (md, theory, ...)."""
    parts = path.parts
    for i in range(len(parts) - len(RESULTS_DIR)):
        if parts[i : i + len(RESULTS_DIR)] == RESULTS_DIR:
            return parts[i + len(RESULTS_DIR)]
    raise ValueError(f"{path} is not under {'/'.join(RESULTS_DIR)}")


def one_per_structure(files):
    """The first file of each `structure`: the seeds of one MD run differ only in values."""
    chosen = {}
    for path in files:
        chosen.setdefault(structure(path), path)
    return sorted(chosen.values())


def test_one_file_per_structure_keeps_every_kind_of_output(smoke_files):
    chosen = one_per_structure(smoke_files)
    stages = {stage(p) for p in smoke_files}
    assert len(stages) >= 12 and "md" in stages, stages
    assert {stage(p) for p in chosen} == stages
    assert len(chosen) < len(smoke_files)  # the MD seeds of a run share one structure


def test_every_kind_of_smoke_output_passes_the_cf_checker(smoke_files):
    # one file per structure (the 24 MD seed files of a run differ in values only): measured
    # 2026-11-27, the whole set took 64 s of CPU, the MD seeds 38 s of it
    errors = cf_errors(one_per_structure(smoke_files))
    listing = "\n".join(f"{f.split('results/')[-1]}: {m}" for f, m in errors[:40])
    assert not errors, f"{len(errors)} CF errors:\n{listing}"


def test_no_smoke_output_has_names_equal_but_for_case(smoke_files):
    """CF 2.3: variable names must not differ by case only (a warning of the checker): the
    theory file held the orbital frequency Omega beside the frequency coordinate omega."""
    errors = cf_errors(one_per_structure(smoke_files), section="§2.3")
    assert not errors, errors
    for path in smoke_files:
        with netCDF4.Dataset(path) as nc:
            names = list(nc.variables) + list(nc.dimensions)
            lower = {n.lower() for n in set(names)}
            assert len(lower) == len(set(names)), (path, sorted(names))


def test_integer_types_meet_cf_1_8(smoke_files):
    """CF 1.8 knows no 64-bit integers (its §2.2): every counter, index and size of every kind
    of smoke output is stored in 32 bits (the MD files' counts were int64)."""
    errors = cf_errors(one_per_structure(smoke_files), cf="cf:1.8", section="§2.2")
    listing = "\n".join(f"{f.split('results/')[-1]}: {m}" for f, m in errors[:40])
    assert not errors, f"{len(errors)} CF 1.8 data-type errors:\n{listing}"


def test_integers_stored_in_32_bits_where_they_fit_and_read_as_int64(tmp_path):
    """write_dataset stores a 64-bit integer variable in 32 bits when its values fit (its
    valid_min / valid_max / flag_values in the same type, CF 2.5.1), keeps 64 bits beyond, and
    read_dataset gives int64 back (a sum over many seed files cannot overflow 32 bits)."""
    big = np.array([0, 2**31], dtype=np.int64)  # 2^31 > int32 max
    ds = xr.Dataset(
        {
            "count": layouts.variable(
                ("bin",), np.array([3, 6_120_000]), "1", "c", valid=(0, None)
            ),
            "big": layouts.variable(("bin",), big, "1", "beyond int32", valid=(0, None)),
            "flag": layouts.variable(("bin",), np.array([0, 1], dtype=np.int8), "1", "f"),
        },
        coords={"bin": layouts.variable(("bin",), np.arange(2), "1", "bin index")},
    )
    io.write_dataset(ds, tmp_path / "x.nc", title="test")
    with netCDF4.Dataset(tmp_path / "x.nc") as nc:
        kinds = {name: str(v.dtype) for name, v in nc.variables.items()}
        assert nc["count"].getncattr("valid_min").dtype == np.int32
        assert nc["big"].getncattr("valid_min").dtype == np.int64
        assert list(nc["count"][:]) == [3, 6_120_000] and list(nc["big"][:]) == [0, 2**31]
    assert kinds == {"count": "int32", "big": "int64", "flag": "int8", "bin": "int32"}
    back = io.read_dataset(tmp_path / "x.nc")
    assert back["count"].dtype == np.int64 and back["bin"].dtype == np.int64
    assert back["flag"].dtype == np.int8
    total = sum(back["count"].values for _ in range(400))  # 2.4e9 > int32 max
    assert total[1] == 400 * 6_120_000


def test_every_smoke_output_has_a_specific_title_and_cf_units(smoke_files):
    generic = []
    for path in smoke_files:
        with netCDF4.Dataset(path) as nc:
            title, case = nc.getncattr("title"), getattr(nc, "case", None)
            where = next((p for p in path.parts if p in CASE_TITLED), None)
            if title.startswith("hmfdiff output") or (where and case and case not in title):
                generic.append(f"{path.parent.name}/{path.name}: {title!r}")
            for name, var in nc.variables.items():
                units = var.getncattr("units")
                assert units in io.CF_UNITS, f"{path}: {name} has units {units!r}"
                if units == "1" and "comment" in var.ncattrs():
                    assert isinstance(var.getncattr("comment"), str)
    assert not generic, "titles that do not say what the file holds:\n" + "\n".join(generic)


def test_variable_stores_hmf_quantities_as_cf_units_and_refuses_unknown_units():
    v = layouts.variable(("x",), np.ones(2), "action^2/time", "N D")
    assert v.attrs["units"] == "1"
    assert v.attrs["comment"] == io.HMF_COMMENT + io.HMF_UNITS["action^2/time"]
    assert "action^2 / time" in v.attrs["comment"]
    assert layouts.variable(("x",), np.ones(2), "rad", "angle").attrs["units"] == "rad"
    kept = layouts.variable(("x",), np.ones(2), "time", "t", comment="sampled every 0.5")
    assert kept.attrs["comment"].endswith("sampled every 0.5")
    assert kept.attrs["comment"].startswith(io.HMF_COMMENT + "time")
    for bad in ("action (HMF)", "seconds since 2000-01-01", "[time]", "m s-1", ""):
        with pytest.raises(ValueError, match="neither CF units"):
            layouts.variable(("x",), np.ones(2), bad, "x")
    with pytest.raises(ValueError, match="neither CF units"):
        io.scalar(1.0, "time (N units)", "t")
    assert io.scalar(1.0, "1", "M0").attrs["units"] == "1"


def test_write_dataset_refuses_units_a_checker_rejects(tmp_path):
    # a writer that builds its variables without `variable` cannot store them either
    raw = xr.Dataset({"x": xr.Variable(("n",), np.ones(3), {"units": "action", "long_name": "J"})})
    io.write_dataset(raw, tmp_path / "ok.nc", title="test")
    with netCDF4.Dataset(tmp_path / "ok.nc") as nc:
        assert nc["x"].units == "1" and nc["x"].comment == io.HMF_COMMENT + "action"
    bad = raw.copy()
    bad["x"].attrs["units"] = "[time]"
    with pytest.raises(ValueError, match=r"'\[time\]'"):
        io.write_dataset(bad, tmp_path / "bad.nc", title="test")
    assert not (tmp_path / "bad.nc").exists()
