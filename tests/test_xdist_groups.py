"""The suite's split over two xdist workers keeps the tests of the shared smoke build on one
worker (tests/conftest.py): the hook groups exactly the modules that use that build."""

import re
import subprocess
import sys
from pathlib import Path

import conftest

TESTS = Path(__file__).resolve().parent


class _Item:
    def __init__(self, path):
        self.path = path
        self.markers = []

    def add_marker(self, marker):
        self.markers.append(marker)


def test_tests_of_the_shared_smoke_build_form_one_group():
    users = ["test_deps.py", "test_figures.py", "test_report.py", "test_cf_compliance.py"]
    others = ["test_agreement.py", "test_slurm.py", "test_relaxation_rates.py"]
    items = {name: _Item(TESTS / name) for name in users + others}
    conftest.pytest_collection_modifyitems(None, list(items.values()))
    for name in users:
        (marker,) = items[name].markers
        assert marker.name == "xdist_group" and marker.args == (conftest.SMOKE_GROUP,), name
    for name in others:
        assert items[name].markers == [], name


def test_the_suite_runs_on_two_workers_grouped():
    text = (TESTS.parent / "pyproject.toml").read_text()
    assert "-n 2 --dist loadgroup" in text
    assert "pytest-xdist==" in (TESTS.parent / "environment.txt").read_text()


def test_the_group_reaches_xdist():
    """In a real two-worker run, tests of a module of the shared build carry the group in their
    node id and all run on one worker (the marks must be set before xdist reads them)."""
    r = subprocess.run(
        [sys.executable, "-m", "pytest", "-v", "-n", "2", "-p", "no:cacheprovider"]
        + ["tests/test_readme_numbers.py", "-k", "quotes and hothalo_large_n"],
        cwd=TESTS.parent,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    runs = re.findall(r"^\[(gw\d+)\] .*?PASSED (.+?) *$", r.stdout, re.M)
    assert len(runs) >= 4, r.stdout[-3000:]
    assert all(node.endswith("@" + conftest.SMOKE_GROUP) for _, node in runs), runs
    assert len({worker for worker, _ in runs}) == 1, runs
