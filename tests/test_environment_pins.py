"""Every third-party package that the code, the tests, the studies, the benchmarks or the workflow
import is pinned in environment.txt.

A fresh virtual environment holds only what environment.txt installs; a package imported but not
pinned works on a machine that has it installed globally and fails on a user's (mpmath did, in
tests/test_drift_rotation.py). The imports are read with `ast` (nothing imported), each
top-level module name is mapped to its distribution through the installed packages' metadata,
and the distribution must appear in environment.txt with an exact `==` version."""

import ast
import importlib.metadata
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SCANNED = ("src", "tests", "studies", "benchmarks", "workflow")


def imported_top_level_modules(paths):
    """{top-level module name: first file importing it} for absolute imports in the files."""
    found = {}
    for path in paths:
        tree = ast.parse(path.read_text(), filename=str(path))
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                names = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                names = [node.module]
            else:
                continue
            for name in names:
                found.setdefault(name.split(".")[0], path)
    return found


def third_party(modules, local_names):
    """The modules neither in the standard library nor the project's own."""
    return {
        name: path
        for name, path in modules.items()
        if name not in sys.stdlib_module_names and name not in local_names and name != "__future__"
    }


def pinned_distributions(text):
    """{normalised distribution name: version} of the `name==version` lines (extras dropped)."""
    pins = {}
    for line in text.splitlines():
        line = line.split("#")[0].strip()
        m = re.fullmatch(r"([A-Za-z0-9_.\-]+)(\[[^\]]*\])?==(\S+)", line)
        if m:
            pins[normalise(m.group(1))] = m.group(3)
    return pins


def normalise(name):
    return re.sub(r"[-_.]+", "-", name).lower()


def unpinned(modules, pins, distributions_of):
    """The imported modules whose distribution has no pin, as 'module (file): why' lines."""
    problems = []
    for name, path in sorted(modules.items()):
        dists = distributions_of.get(name)
        if not dists:
            problems.append(f"{name} ({path.relative_to(ROOT)}): not installed, not pinned")
        elif not any(normalise(d) in pins for d in dists):
            problems.append(f"{name} ({path.relative_to(ROOT)}): distribution {dists} not pinned")
    return problems


def python_files():
    files = [p for d in SCANNED for p in (ROOT / d).rglob("*.py")]
    return [p for p in files if ".snakemake" not in p.parts]


def local_names(files):
    return {"hmfdiff"} | {p.stem for p in files} | {p.parent.name for p in files}


def test_every_imported_third_party_package_is_pinned():
    files = python_files()
    assert len(files) > 100
    modules = third_party(imported_top_level_modules(files), local_names(files))
    assert {"numpy", "scipy", "numba", "xarray", "pytest", "mpmath"} <= set(modules)
    pins = pinned_distributions((ROOT / "environment.txt").read_text())
    problems = unpinned(modules, pins, importlib.metadata.packages_distributions())
    assert not problems, "imported but not pinned in environment.txt:\n" + "\n".join(problems)


def test_the_check_sees_a_missing_pin(tmp_path):
    """The check itself: a test file importing a package that environment.txt lacks is caught,
    whether the package is installed here (numpy with no numpy pin) or not at all."""
    test_file = ROOT / "tests" / "test_environment_pins.py"
    source = tmp_path / "test_x.py"
    source.write_text("import numpy as np\nfrom not_a_real_package.sub import thing\nimport os\n")
    modules = third_party(imported_top_level_modules([source]), local_names([test_file]))
    assert set(modules) == {"numpy", "not_a_real_package"}
    pins = pinned_distributions("scipy==1.17.1\nsnakemake[reports]==9.27.1  # note\n-e .\n")
    assert pins == {"scipy": "1.17.1", "snakemake": "9.27.1"}
    modules = {name: test_file for name in modules}
    problems = unpinned(modules, pins, importlib.metadata.packages_distributions())
    assert len(problems) == 2 and problems[0].startswith("not_a_real_package")
    assert "numpy" in problems[1]
