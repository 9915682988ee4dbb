"""Start-up of the rule scripts: a job imports only the libraries its work needs.

Every job of the workflow is a fresh interpreter, and the tiny ones (orbits, fits, figures)
spent a third of their ~2 s importing: numba and matplotlib only to record their versions in
the provenance of a file, scipy.optimize in rule orbits, which never solves for a state.  Each
test runs the module-level imports of rule scripts (read with `ast`, as
benchmarks/bench_startup.py does) in a fresh interpreter and looks at `sys.modules`; nothing is
timed."""

from __future__ import annotations

import ast
import json
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SCRIPTS = ROOT / "workflow" / "scripts"
#: rule scripts that run MD kernels (numba) or draw (matplotlib)
NUMBA = {"md", "relaxation_md", "kernels"}
MATPLOTLIB = {"figure"}


def imports_of(script):
    tree = ast.parse(Path(SCRIPTS, f"{script}.py").read_text())
    return "\n".join(
        ast.unparse(n) for n in tree.body if isinstance(n, ast.Import | ast.ImportFrom)
    )


def loaded_after(code, modules):
    """Which of `modules` a fresh interpreter has imported after running `code`."""
    check = f"import json, sys\nprint(json.dumps([m for m in {modules!r} if m in sys.modules]))"
    probe = f"{code}\n{check}"
    out = subprocess.run(
        [sys.executable, "-c", probe],
        capture_output=True,
        text=True,
        check=True,
        cwd=ROOT,
        env=dict(os.environ, PYTHONPATH=str(ROOT / "src"), MPLBACKEND="Agg"),
    ).stdout
    return set(json.loads(out.splitlines()[-1]))


def test_provenance_records_the_versions_without_importing_numba_or_matplotlib():
    """The versions come from the installed distributions when the job has not imported the
    library, and they are the strings the modules give (`__version__`)."""
    code = "\n".join(
        [
            "from hmfdiff.pipeline.io import VERSIONED, _versions",
            "recorded = _versions()",
            "import sys",
            "lazy = [m for m in ('numba', 'matplotlib') if m in sys.modules]",
            "import importlib",
            "given = {m: importlib.import_module(m).__version__ for m in VERSIONED}",
            "assert not lazy, lazy",
            "assert {m: recorded[m] for m in VERSIONED} == given, (recorded, given)",
            "assert recorded == _versions()",  # imported now: the same strings
        ]
    )
    assert loaded_after(code, ["numba", "matplotlib"]) == {"numba", "matplotlib"}


def test_only_the_md_and_figure_rules_import_numba_or_matplotlib():
    """The module-level imports of every other rule script, with the versions a write records,
    load neither; the figure rule loads no numba."""
    scripts = sorted(p.stem for p in SCRIPTS.glob("*.py"))
    assert {"orbits", "fit", "theory", "figure", "md"} <= set(scripts)
    plain = [s for s in scripts if s not in NUMBA | MATPLOTLIB]
    versions = "from hmfdiff.pipeline.io import _versions\n_versions()"
    code = "\n".join([*map(imports_of, plain), versions])
    assert loaded_after(code, ["numba", "matplotlib"]) == set()
    code = "\n".join([*map(imports_of, sorted(MATPLOTLIB)), versions])
    assert loaded_after(code, ["numba"]) == set()


def test_rule_orbits_imports_no_scipy_optimize_and_a_state_still_solves():
    """scipy.optimize is imported by the solvers of `meanfield.equilibrium` when they run."""
    assert loaded_after(imports_of("orbits"), ["scipy.optimize"]) == set()
    code = "\n".join(
        [
            "from hmfdiff.meanfield.equilibrium import ThermalState, thermal_M0_from_energy",
            "s = ThermalState(u=0.1)",
            "assert abs(thermal_M0_from_energy(s.u) - s.M0) < 1e-12",
        ]
    )
    assert loaded_after(code, ["scipy.optimize"]) == {"scipy.optimize"}
