"""`--config` overrides one nested key of any top-level section and keeps the rest of the config
file, with and without --configfile (issue 22, part 2: overriding `cases` used to drop the whole
default config file: "missing required field(s) ['grids', 'theory', 'md', 'figures']")."""

import json

import pytest
import yaml
from _smoke import SMOKE, copy_workflow, snakemake

from hmfdiff.pipeline.io import read_dataset


@pytest.fixture(scope="module")
def workdir(tmp_path_factory):
    return copy_workflow(tmp_path_factory.mktemp("overrides"))


def _same_value_overrides(path):
    """One `--config` argument per top-level key of the config file at `path`, each setting one
    nested leaf to the value it already has: a run that kept only the overridden leaves would
    miss every other field of that section (refused by the schema)."""
    cfg = yaml.safe_load(path.read_text())
    return [f"{key}={_text(_first_leaf(value))}" for key, value in cfg.items()]


def _text(value):
    return value if isinstance(value, str) else json.dumps(value)


def _first_leaf(value):
    """{k1: {k2: leaf}} along the first key at every level (the value itself if not a dict)."""
    if not isinstance(value, dict) or not value:
        return value
    key, sub = next(iter(value.items()))
    return {key: _first_leaf(sub)}


@pytest.mark.parametrize("configfile", [None, SMOKE], ids=["default_config", "smoke_config"])
def test_override_of_every_top_level_key_keeps_the_rest(workdir, configfile):
    path = workdir / (configfile or "config/config.yaml")
    overrides = _same_value_overrides(path)
    keys = {a.split("=", 1)[0] for a in overrides}
    assert {"cases", "grids", "theory", "md", "figures"} <= keys
    extra = ["--configfile", configfile] if configfile else []
    r = snakemake(["-n", "-q", *extra, "--config", *overrides], workdir)
    assert r.returncode == 0, (r.stdout + r.stderr)[-3000:]


def test_override_of_one_case_changes_that_case_only(workdir):
    """The issue's command, on the smoke config: the overridden case's equilibrium is built at the
    new energy, and the other cases are still planned."""
    over = ["--config", "cases={thermal_u-0.1: {kind: thermal, u: -0.12}}"]
    r = snakemake(["-n", "--configfile", SMOKE, *over], workdir)
    assert r.returncode == 0, r.stderr[-3000:]
    for case in yaml.safe_load((workdir / SMOKE).read_text())["cases"]:
        assert f"equilibrium/{case}.nc" in r.stdout, case
    target = "results/smoke/equilibrium/thermal_u-0.1.nc"
    r = snakemake(["-j1", target, "--configfile", SMOKE, *over], workdir)
    assert r.returncode == 0, r.stderr[-3000:]
    ds = read_dataset(workdir / target, required=["u", "M0"])
    assert float(ds["u"]) == pytest.approx(-0.12, abs=1e-12)
