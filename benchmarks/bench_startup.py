"""Benchmark of the start-up every Snakemake job pays before it works: the imports of its rule
script (workflow/scripts/*.py), each in a fresh interpreter, the present tree against a
baseline source tree.

    python benchmarks/bench_startup.py [--baseline REV_OR_SRC] [--reps 3] [--json]
                                       [--scripts orbits figure ...]

Per script: the script's own import statements (those at module level, read with `ast`, run
in the order they appear; nothing else of the script runs, so no Snakemake object is needed),
plus scipy.optimize for the scripts that rebuild a state (`BUILDS_A_STATE`); then, since every
rule writes netCDF files or figures with provenance, the versions a write records
(`hmfdiff.pipeline.io._versions`, which imported the libraries whose versions it names).
Imports made inside functions at run time (pyplot in a figure) and the Snakemake preamble (the
same in both trees) are not counted.  Three clocks: `import` (the import statements, timed
inside the interpreter), `wall` (the whole subprocess: interpreter start, imports, versions,
exit) and `cpu` (its user + system time, less sensitive than the wall clock to other
processes on a shared machine), the best of --reps each.

The baseline runs the same statements with PYTHONPATH pointing at the package of --baseline: a
source root holding hmfdiff/, or a git revision whose src/ is extracted to a temporary folder
(default ae01749, the tree before the imports were made lazy; 'none' for the present tree
alone); the ratio is baseline / present (above 1: present faster).  Baseline and present
alternate, so that a load on the machine hits both alike.

The rule counts weight the saving per job into job-seconds of the full reproduction
(`snakemake -j2`, 183 jobs).
"""

from __future__ import annotations

import argparse
import ast
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SCRIPTS = ROOT / "workflow" / "scripts"

#: jobs per rule script in the full reproduction (183 jobs): rules sharing a script add up
JOBS = {
    "md": 30 + 18,  # md, md_scaling
    "relaxation": 6,
    "relaxation_md": 14 + 3 + 2,  # relaxation_rates_md, relaxation_md, relaxation_md_control
    "figure": 16,
    "fit": 8 + 18,  # fit, fit_scaling
    "windowed": 8,
    "spectrum": 3,
    "theory": 11,
    "equilibrium": 12,
    "closed_forms": 12,
    "orbits": 12,
    "kernels": 1,
    "scaling": 4,
    "relaxation_rates": 2,
    "validation": 1,
    "relaxation_comparison": 1,
}

#: scripts that rebuild an equilibrium state (`state_from_dataset`, `make_state`, ThermalState):
#: solving for beta or M0 imports scipy.optimize, now inside the solver (`meanfield.equilibrium`)
#: instead of at its import, so the probe imports it for them as their jobs do
BUILDS_A_STATE = {
    "closed_forms",
    "equilibrium",
    "md",
    "relaxation",
    "relaxation_comparison",
    "relaxation_md",
    "scaling",
    "spectrum",
    "theory",
    "validation",
    "windowed",
}

PROBE = """
import time
_t0 = time.perf_counter()
{imports}
_t1 = time.perf_counter()
from hmfdiff.pipeline.io import _versions
_versions()
print("IMPORT", _t1 - _t0)
"""


def import_statements(script):
    """The module-level import statements of a rule script, as source, in order."""
    tree = ast.parse(Path(script).read_text(), filename=str(script))
    nodes = [n for n in tree.body if isinstance(n, ast.Import | ast.ImportFrom)]
    return "\n".join(ast.unparse(n) for n in nodes)


def probe(name):
    """The code one measurement runs for rule script `name`."""
    imports = import_statements(SCRIPTS / f"{name}.py")
    if name in BUILDS_A_STATE:
        imports += "\nfrom scipy import optimize"
    return PROBE.format(imports=imports)


def _children_cpu():
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def measure(code, src):
    """(import seconds, wall seconds, CPU seconds) of a fresh interpreter running `code`."""
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(src), str(ROOT)]))
    env.setdefault("MPLBACKEND", "Agg")
    cpu, start = _children_cpu(), time.perf_counter()
    out = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
    ).stdout
    wall, cpu = time.perf_counter() - start, _children_cpu() - cpu
    imported = float(next(x for x in out.splitlines() if x.startswith("IMPORT")).split()[1])
    return imported, wall, cpu


def baseline_src(spec, tmp):
    """The source root of the baseline `spec` (a folder or a git revision), or None."""
    if spec == "none":
        return None
    if Path(spec, "hmfdiff").is_dir():
        return Path(spec)
    archive = subprocess.run(
        ["git", "-C", str(ROOT), "archive", spec, "src"], capture_output=True, check=True
    ).stdout
    subprocess.run(["tar", "-x", "-C", tmp], input=archive, check=True)
    return Path(tmp, "src")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--baseline", default="ae01749", help="source root or git revision")
    parser.add_argument("--reps", type=int, default=3)
    parser.add_argument("--json", action="store_true")
    parser.add_argument("--scripts", nargs="*", default=sorted(JOBS))
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        rows = run(args, baseline_src(args.baseline, tmp))
    report(rows, args.json)


def run(args, baseline):
    rows = []
    for name in args.scripts:
        code = probe(name)
        row = {"script": name, "jobs": JOBS.get(name, 0)}
        present, base = [], []
        for _ in range(args.reps):  # alternate, one interpreter each
            present.append(measure(code, ROOT / "src"))
            if baseline is not None:
                base.append(measure(code, baseline))
        row["import"], row["wall"], row["cpu"] = map(min, zip(*present, strict=True))
        if base:
            row["base_import"], row["base_wall"], row["base_cpu"] = map(
                min, zip(*base, strict=True)
            )
        rows.append(row)
    return rows


def report(rows, as_json):
    baseline = bool(rows) and "base_wall" in rows[0]
    if as_json:
        print(json.dumps(rows, indent=1))
        return
    head = f"{'script':22s} {'jobs':>4s} {'import':>7s} {'wall':>6s} {'cpu':>6s}"
    if baseline:
        head += f" | {'import':>7s} {'wall':>6s} {'cpu':>6s} | {'saved wall':>10s} {'cpu':>6s}"
        print(f"{'':27s} {'present tree':^21s} | {'baseline':^21s} | {'job-s saved':^17s}")
    print(head)
    saved_wall = saved_cpu = 0.0
    for r in rows:
        line = (
            f"{r['script']:22s} {r['jobs']:4d} {r['import']:7.3f} {r['wall']:6.3f} {r['cpu']:6.3f}"
        )
        if baseline:
            wall = (r["base_wall"] - r["wall"]) * r["jobs"]
            cpu = (r["base_cpu"] - r["cpu"]) * r["jobs"]
            saved_wall, saved_cpu = saved_wall + wall, saved_cpu + cpu
            line += (
                f" | {r['base_import']:7.3f} {r['base_wall']:6.3f} {r['base_cpu']:6.3f}"
                f" | {wall:10.1f} {cpu:6.1f}"
            )
        print(line)
    if baseline:
        jobs = sum(r["jobs"] for r in rows)
        print(f"saved over {jobs} jobs: {saved_wall:.1f} job-s wall, {saved_cpu:.1f} CPU-s")


if __name__ == "__main__":
    main()
