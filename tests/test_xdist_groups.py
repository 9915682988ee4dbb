"""The suite's split over two xdist workers keeps the tests of the shared smoke build on one
worker (tests/conftest.py): the hook groups exactly the tests that use that build."""

import re
import subprocess
import sys
from pathlib import Path

import conftest

GROUP = conftest.SMOKE_GROUP

TESTS = Path(__file__).resolve().parent


PROBE = """
import pytest
from _smoke import smoke_workdir


@pytest.fixture
def built(tmp_path):
    if tmp_path is None:  # never: the probe must not build; the hook reads the source
        smoke_workdir(tmp_path)
    return tmp_path


@pytest.fixture
def derived(built):
    return built


def test_fixture_user(built):
    pass


def test_indirect_user(derived):
    pass


def test_direct_user():
    if False:
        smoke_workdir(None)


@pytest.mark.parametrize("k", range(3))
def test_bystander(k, tmp_path):
    pass
"""


def run_probe(tmp_path, *args):
    """pytest on a probe module beside a copy of the suite's conftest and _smoke (the hook under
    test reads sources, so nothing is built)."""
    for name in ("conftest.py", "_smoke.py"):
        (tmp_path / name).write_text((TESTS / name).read_text())
    (tmp_path / "test_probe.py").write_text(PROBE)
    return subprocess.run(
        [sys.executable, "-m", "pytest", "-v", "-p", "no:cacheprovider", "--rootdir", tmp_path]
        + [*args, "test_probe.py"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=600,
    )


def test_tests_that_use_the_shared_smoke_build_form_one_group(tmp_path):
    """Through a fixture, through a fixture's fixture or in the test's own code: grouped; the
    other tests of the same module: not grouped, on any worker; all grouped tests on one
    worker (the marks must be set before xdist reads them into the node ids)."""
    r = run_probe(tmp_path, "-n", "2", "--dist", "loadgroup")
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    runs = re.findall(r"^\[(gw\d+)\] .*?PASSED (\S+)", r.stdout, re.M)
    assert len(runs) == 6, r.stdout[-3000:]
    grouped = {node.split("::")[1]: w for w, node in runs if node.endswith("@" + GROUP)}
    assert sorted(grouped) == [
        f"test_direct_user@{GROUP}",
        f"test_fixture_user@{GROUP}",
        f"test_indirect_user@{GROUP}",
    ], runs
    assert len(set(grouped.values())) == 1, runs
    assert all("@" not in node for _, node in runs if "bystander" in node), runs


def test_the_suite_runs_on_two_workers_grouped():
    text = (TESTS.parent / "pyproject.toml").read_text()
    assert "-n 2 --dist loadgroup" in text
    assert "pytest-xdist==" in (TESTS.parent / "environment.txt").read_text()
